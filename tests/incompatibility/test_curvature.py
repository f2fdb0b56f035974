"""ngincompat.incompatibility.curvature: the growth metric's exact curvature, scenes' reports."""

import json

import ngsolve as ngs
import numpy as np
import pytest
from conftest import l2_norm

from geometries import cube
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility import operators as inc
from ngincompat.incompatibility.operators import grad_scalar
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import FiberGrowth, IsotropicGrowth
from ngincompat.scenes import curvature as curvature_report

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
    # the coordinate formula of Riemann contracts to the same Ricci (two routes)
    ricci = ngs.fem.Einsum("kijl,kl->ij", c.riemann, ngs.Inv(g))
    assert l2_norm(ricci - c.ricci, cube_tet) < 1e-12
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
    ricci = ngs.fem.Einsum("kijl,kl->ij", c.riemann, ngs.Inv(c.metric))
    assert l2_norm(ricci - c.ricci, cube_tet) < 1e-12 * l2_norm(ein, cube_tet)


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


# ---------------------------------------------------------------- scenes

def test_cylinder_scene_reports_flat_and_the_verdict():
    from ngincompat.scenes import get_scene
    results = get_scene("cylinder").from_settings(
        {"maxh": 0.5, "order": 2, "mechanics": False, "outputs": "curvature"}).run()
    m = results.metrics
    assert m["G_norm_L2"] > 0.1
    assert m["einstein_norm_L2"] < 1e-14 < m["einstein_norm_L2_error"]
    assert abs(m["scalar_curvature_min"]) < 1e-14 and abs(m["scalar_curvature_max"]) < 1e-14
    assert curvature_report.verdict(m).startswith("compatible")
    assert "einstein_norm_g" in results.fields and "einstein_norm_g" in results.profiles["line"]
    assert any(f.file == "curvature.png" for f in results.figures)


def test_hemisphere_scene_is_incompatible_with_exact_scalar_curvature():
    from ngincompat.scenes import get_scene
    results = get_scene("hemisphere").from_settings(
        {"maxh": 0.5, "centre_maxh": 0.5, "order": 2, "mechanics": False,
         "outputs": "curvature"}).run()
    m = results.metrics
    assert m["einstein_norm_L2"] > 100 * m["einstein_norm_L2_error"]
    assert curvature_report.verdict(m).startswith("incompatible")
    # S against the conformal closed form at points of the profile line R in (0, 1]
    line = results.profiles["line"]
    R = np.asarray(line["R"])
    S = np.asarray(line["scalar_curvature"])
    # theta = 1 + R/4, phi = ln(theta)/3: S = -theta^(-2/3) (4 Lap phi + 2 |phi'|^2) with
    # phi' = 1/(12 theta), Lap phi = phi'' + 2 phi'/R, phi'' = -1/(48 theta^2)
    theta = 1 + R / 4
    d1 = 1 / (12 * theta)
    lap = -1 / (48 * theta ** 2) + 2 * d1 / np.where(R > 0, R, np.inf)
    expected = -theta ** (-2 / 3) * (4 * lap + 2 * d1 ** 2)
    inside = (R > 0.05) & (R < 0.95)
    assert np.allclose(S[inside], expected[inside], rtol=1e-8)


@pytest.mark.slow
def test_skin_reports_discrete_curvature_beside_b():
    from conftest import SKIN_COARSE

    from ngincompat.scenes import get_scene
    settings = dict(item.split("=") for item in SKIN_COARSE[1::2])
    results = get_scene("skin").from_settings({**settings, "outputs": "curvature"}).run()
    m = results.metrics
    assert m["einstein_norm_L2"] > 0 and m["einstein_norm_L2_error"] > 0
    assert m["scalar_curvature_min"] < m["scalar_curvature_max"]
    assert "einstein_norm_g" in results.profiles["line"]
    assert any(f.file == "curvature.png" for f in results.figures)


def test_curvature_benchmark_writes_error_against_cost(tmp_path):
    from ngincompat.studies import curvature_rates
    lines = curvature_rates.main(out=tmp_path, quick=True)
    rows = json.loads((tmp_path / "curvature_rates.json").read_text())["rows"]
    assert [(r["body"], r["k"]) for r in rows] == [("hemisphere", 1), ("hemisphere", 2)]
    # p-refinement: every error measure falls from k = 1 to k = 2
    for measure in ("pairing", "lift", "elementwise"):
        assert rows[1][measure] < 0.5 * rows[0][measure]
    assert (tmp_path / "curvature_hemisphere.png").stat().st_size > 0
    assert lines[-1] == f"plots and tables written to {tmp_path}"


def test_curvature_benchmark_runs_the_bodies_and_degrees_asked_for(tmp_path, capsys):
    """``--bodies`` and ``--orders`` choose the grid (over ``--quick``'s one level); an
    unknown body is refused before anything runs, in one line."""
    from ngincompat.cli import main
    assert main(["bench", "curvature", "--quick", "--orders", "1", "--out",
                 str(tmp_path)]) == 0
    rows = json.loads((tmp_path / "curvature_rates.json").read_text())["rows"]
    assert [(r["body"], r["k"], r["level"]) for r in rows] == [("hemisphere", 1, 0)]
    assert main(["bench", "curvature", "--bodies", "sphere"]) == 2
    assert "--bodies 'sphere': allowed hemisphere, disc" in capsys.readouterr().err
