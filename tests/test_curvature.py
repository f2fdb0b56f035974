"""Curvature of the growth metric: exact path against closed forms, Kröner's linearisation,
the paper's cylinder; the discrete (Regge) path against the exact one."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import l2_norm

from geometries import cube
from ngincompat import curvature as cv
from ngincompat import fields
from ngincompat import incompatibility as inc
from ngincompat.growth import FiberGrowth, IsotropicGrowth
from ngincompat.incompatibility import grad_scalar

X = ngs.CF((ngs.x, ngs.y, ngs.z))


@pytest.fixture(scope="module")
def cube_tet():
    return cube(maxh=0.35, elements="tet")


def _hessian(phi):
    return ngs.CF(tuple(phi.Diff(a).Diff(b) for a in (ngs.x, ngs.y, ngs.z)
                        for b in (ngs.x, ngs.y, ngs.z)), dims=(3, 3))


def _conformal_closed_form(phi):
    """Curvature of g = exp(2 phi) delta in 3-D (the conformal change of the flat metric,
    Lee, Riemannian manifolds, ch. 7): with Euclidean Hess, Laplacian and gradient,
        Ric = -(Hess phi - dphi dphi) - (Lap phi + |dphi|^2) delta,
        S   = -exp(-2 phi) (4 Lap phi + 2 |dphi|^2),
        Ein = Ric - S/2 g = -(Hess phi - dphi dphi) + Lap phi delta."""
    hess = _hessian(phi)
    d = grad_scalar(phi)
    lap = ngs.Trace(hess)
    S = -ngs.exp(-2 * phi) * (4 * lap + 2 * ngs.InnerProduct(d, d))
    ein = -(hess - ngs.OuterProduct(d, d)) + lap * ngs.Id(3)
    return S, ein


def test_round_sphere_in_stereographic_coordinates(cube_tet):
    # the unit 3-sphere: g = 4 / (1 + |X|^2)^2 delta has K = 1, so S = 6, Ric = 2 g, Ein = -g
    g = 4 / (1 + ngs.InnerProduct(X, X)) ** 2 * ngs.Id(3)
    c = cv.curvature_exact(g)
    assert l2_norm(c.scalar - 6, cube_tet) < 1e-12
    assert l2_norm(c.ricci - 2 * g, cube_tet) < 1e-12
    assert l2_norm(c.einstein + g, cube_tet) < 1e-12
    # constant curvature: R_ijkl = K (g_il g_jk - g_ik g_jl), Lee's sign
    R = ngs.fem.Einsum("il,jk->ijkl", g, g) - ngs.fem.Einsum("ik,jl->ijkl", g, g)
    assert l2_norm(c.riemann - R, cube_tet) < 1e-12
    # |Ein|_g = |-g|_g = sqrt(3)
    assert l2_norm(c.einstein_norm() - np.sqrt(3), cube_tet) < 1e-12


def test_isotropic_growth_is_conformally_flat_closed_form(cube_tet):
    # Cg = theta^(2/3) I = exp(2 phi) I with phi = ln(theta) / 3
    theta = 1 + 0.5 * ngs.x * ngs.x + 0.3 * ngs.sin(2 * ngs.y) * ngs.z + 0.25 * ngs.z
    growth = IsotropicGrowth(theta)
    c = cv.growth_curvature(growth.Fg)
    S, ein = _conformal_closed_form(ngs.log(theta) / 3)
    assert l2_norm(S, cube_tet) > 0.1
    assert l2_norm(c.scalar - S, cube_tet) < 1e-12 * l2_norm(S, cube_tet)
    assert l2_norm(c.einstein - ein, cube_tet) < 1e-12 * l2_norm(ein, cube_tet)


def test_hemisphere_growth_closed_form_away_from_the_cone_point():
    # theta = 1 + R/4 (the hemisphere's linear profile) on a shell-free cube away from 0
    from netgen.occ import Box, OCCGeometry, Pnt
    mesh = ngs.Mesh(OCCGeometry(Box(Pnt(0.2, 0.2, 0.2), Pnt(1, 1, 1))).GenerateMesh(maxh=0.4))
    theta = 1 + ngs.Norm(X) / 4
    c = cv.growth_curvature(IsotropicGrowth(theta).Fg)
    S, ein = _conformal_closed_form(ngs.log(theta) / 3)
    assert l2_norm(c.scalar - S, mesh) < 1e-12 * l2_norm(S, mesh)
    assert l2_norm(c.einstein - ein, mesh) < 1e-12 * l2_norm(ein, mesh)


def test_intermediate_components_have_the_g_norm(cube_tet):
    # theta quadratic across the fibers: curved (linear across them would be flat)
    theta = 1 + 0.5 * ngs.y * ngs.y + 0.2 * ngs.z * ngs.x
    growth = FiberGrowth(theta, fields.constant("e1"))
    c = cv.growth_curvature(growth.Fg)
    pushed = cv.einstein_intermediate(c.einstein, growth.Fg)
    assert l2_norm(c.einstein_norm(), cube_tet) > 1e-2
    assert l2_norm(ngs.Norm(pushed) - c.einstein_norm(), cube_tet) < 1e-12
    # pushed components are symmetric and frame-invariant: a rotated Fg gives the same
    angle = 0.7 * ngs.x
    Q = ngs.CF((ngs.cos(angle), -ngs.sin(angle), 0, ngs.sin(angle), ngs.cos(angle), 0,
                0, 0, 1), dims=(3, 3))
    c_rot = cv.growth_curvature(Q * growth.Fg)
    assert l2_norm(c_rot.einstein - c.einstein, cube_tet) < 1e-11


def test_paper_cylinder_has_G_but_no_curvature(cube_tet):
    # section 3.4: fiber growth along e1 with theta = 1 + X2 / 4: G != 0, Cg flat
    growth = FiberGrowth(1 + ngs.y / 4, fields.constant("e1"))
    G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
    c = cv.growth_curvature(growth.Fg)
    assert l2_norm(G, cube_tet) > 0.1
    assert l2_norm(c.riemann, cube_tet) < 1e-13
    assert l2_norm(c.einstein, cube_tet) < 1e-13


def _kroner_defect(eps, mesh):
    """|Ein(Cg) - Curl(G - tr(G)/2 I)|_L2 / eps for Fg = I + eps H (Kröner: O(eps))."""
    H = ngs.CF((ngs.sin(ngs.y), ngs.x * ngs.z, 0.5 * ngs.y * ngs.y,
                ngs.cos(ngs.z) * ngs.x, 0.3 * ngs.x * ngs.y, ngs.z * ngs.z,
                ngs.y * ngs.z, ngs.exp(0.5 * ngs.x), ngs.x * ngs.x * ngs.y), dims=(3, 3))
    Fg = ngs.Id(3) + eps * H
    G = inc.incompatibility_tensor(Fg, inc.curl_exact(Fg))
    kappa = G - 0.5 * ngs.Trace(G) * ngs.Id(3)
    ein = cv.growth_curvature(Fg).einstein
    return (l2_norm(ein - inc.curl_exact(kappa), mesh) / eps,
            l2_norm(ein, mesh) / eps)


def test_kroner_linearisation_is_second_order(cube_tet):
    defects = [_kroner_defect(eps, cube_tet) for eps in (1e-1, 5e-2, 2.5e-2)]
    # Ein / eps tends to a nonzero limit, the defect / eps to zero linearly in eps
    assert all(size > 0.1 for _, size in defects)
    rates = [np.log2(a[0] / b[0]) for a, b in zip(defects[:-1], defects[1:], strict=True)]
    assert all(abs(r - 1) < 0.1 for r in rates), rates
    assert defects[-1][0] < 0.05 * defects[-1][1]
