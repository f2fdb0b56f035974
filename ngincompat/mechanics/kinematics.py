"""Kinematics of the multiplicative split F = Fe Fg (eq. 1-5), as pure functions of CFs.

A body in plane strain is meshed by its section (a two-dimensional mesh, points (X1, X2)):
its displacement (u1, u2) does not depend on X3 and u3 = 0, so its tensors are the
three-dimensional ones with Grad u's third row and column zero, and F33 = 1
(:func:`displacement_gradient`). Every law of the package then applies unchanged.
"""

from collections.abc import Sequence

import ngsolve as ngs


def displacement_gradient(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """Grad u as a 3x3 CF, for a displacement (trial or test function, GridFunction) of
    three components, or of two on a section in plane strain (Grad u embedded:
    (Grad u)_i3 = (Grad u)_3i = 0)."""
    grad = ngs.Grad(u)
    if tuple(grad.dims) == (3, 3):
        return grad
    zero = ngs.ZeroCF(())       # known zero: its derivatives and products are dropped
    return ngs.CF((grad[0, 0], grad[0, 1], zero,
                   grad[1, 0], grad[1, 1], zero,
                   zero, zero, zero), dims=(3, 3))


def deformation_gradient(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """F = I + Grad u (:func:`displacement_gradient`: F33 = 1 in plane strain)."""
    return ngs.Id(3) + displacement_gradient(u)


def component_deformation_gradient(
        components: Sequence[ngs.CoefficientFunction]) -> ngs.CoefficientFunction:
    """F = I + Grad u for a displacement given by its three scalar components u_i (trial
    functions of scalar spaces): row i of Grad u is grad u_i."""
    return ngs.Id(3) + ngs.CF(tuple(ngs.grad(c) for c in components), dims=(3, 3))


def elastic_part(F: ngs.CoefficientFunction,
                 Fg: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """Fe = F Fg^-1 (eq. 1)."""
    return F * ngs.Inv(Fg)


def jacobian(F: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """J = det F (eq. 2)."""
    return ngs.Det(F)
