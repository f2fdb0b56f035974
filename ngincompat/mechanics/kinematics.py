"""Kinematics of the multiplicative split F = Fe Fg (eq. 1-5), as pure functions of CFs."""

import ngsolve as ngs


def deformation_gradient(u):
    """F = I + Grad u, for a displacement (trial function or GridFunction)."""
    return ngs.Id(3) + ngs.Grad(u)


def component_deformation_gradient(components):
    """F = I + Grad u for a displacement given by its three scalar components u_i (trial
    functions of scalar spaces): row i of Grad u is grad u_i."""
    return ngs.Id(3) + ngs.CF(tuple(ngs.grad(c) for c in components), dims=(3, 3))


def elastic_part(F, Fg):
    """Fe = F Fg^-1 (eq. 1)."""
    return F * ngs.Inv(Fg)


def jacobian(F):
    """J = det F (eq. 2)."""
    return ngs.Det(F)
