"""ngincompat.scenes.folding.measures: the measures of a bilayer against closed forms (the flat
branch, the Burgers vector at the interface, a uniform stretch, sulci of a cosine) and the
profiles sampled on its section."""

import json

import ngsolve as ngs
import numpy as np
import pytest
from conftest import FOLDING_COARSE
from scenes.folding.test_scene import SMALL

from ngincompat.fem import postprocess
from ngincompat.fem.shape import sulci
from ngincompat.references.bifurcation import prebuckled_cortex
from ngincompat.scenes.folding import FoldingScene, measures
from ngincompat.studies import folding
from ngincompat.workflow.pipeline import Solution


def test_flat_branch_is_the_homogeneous_state_in_closed_form():
    """Before the onset (theta_c = 1.08): the subcortex unstrained, stress-free and not
    growing (lambda_e = 1 along the curved axons), the cortex in the state F = diag(1,
    lambda2, 1) with sigma22 = 0 (plane strain in the section, X2 vertical:
    :func:`prebuckled_cortex`, whose out-of-plane axis is its second), to 1e-6 of mu_gray;
    the strain energy the cortex's alone."""
    scene = FoldingScene(**{**SMALL, "length": 0.5, "height": 0.3, "maxh": 0.15,
                            "axons": "curved"}, t_end=10.0, dt=10.0, release=False)
    results = scene.run()
    theta_c = 1 + scene.cortex_rate * scene.t_end
    state = prebuckled_cortex(theta_c, scene.mu_gray, scene.lam_ratio * scene.mu_gray)
    mesh, sigma, theta = results.domain, results.fields["sigma"], results.fields["theta"]
    for x1 in (0.05, 0.25, 0.45):
        cortex = mesh(x1, 0.28)
        s = np.reshape(sigma(cortex), (3, 3))
        np.testing.assert_allclose(np.diag(s), [state.sigma11, 0.0, state.sigma22],
                                   atol=1e-6 * scene.mu_gray)
        assert theta(cortex) == pytest.approx(theta_c, abs=1e-10)
        sub = mesh(x1, 0.1)
        np.testing.assert_allclose(sigma(sub), 0.0, atol=1e-6 * scene.mu_white)
        assert theta(sub) == pytest.approx(1.0, abs=1e-10)
    assert "onset_growth" not in results.metrics
    # the top is not stretched along e1 (u1 = 0), so its elastic stretch is 1 / theta_c
    assert results.metrics["top_stretch_min"] == pytest.approx(1 / theta_c, rel=1e-8)
    # the strain energy per unit depth is the cortex's, Jg Psi(Fe) (eq. 36) times its area,
    # Fe = diag(1 / theta_c, lambda2, 1)
    mu, lam = scene.mu_gray, scene.lam_ratio * scene.mu_gray
    Je = state.lambda3 / theta_c
    psi = mu / 2 * (theta_c ** -2 + state.lambda3 ** 2 + 1 - 3 - 2 * np.log(Je)) \
        + lam / 2 * np.log(Je) ** 2
    assert results.metrics["strain_energy"] == pytest.approx(
        theta_c * psi * scene.length * scene.cortex_thickness, rel=1e-8)


def test_driver_summary_figure_and_the_burgers_vector_of_the_flat_state(tmp_path):
    """``ngincompat folding`` for one axon field on the coarse flat state (theta_c = 1.08,
    before the onset, no axon growth; then released, which bends it, cortex outward):
    Fg = I + (theta_c - 1) e1 (x) e1 in the cortex, I below, so Curl Fg is the jump at the
    interface, (Curl Fg)_31 = -dFg_11/dX2, and b = G^T e3 points along e1. Across the
    interface int (Curl Fg_h)_31 dX2 = -(theta_c - 1) exactly (the interpolant equals Fg
    away from it) and G = Fg Curl Fg / Jg weighs it by 1/theta_c above and 1 below: -int b1 dX2
    lies in [(theta_c - 1) / theta_c, theta_c - 1]; b vanishes in the subcortex away from
    the interface, and the largest |b| is at the interface."""
    settings = dict(pair.split("=") for pair in FOLDING_COARSE[1::2])
    rows, results = folding.run_all(tmp_path, axons=("curved",), **settings)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["columns"] == list(folding.COLUMNS)       # released: every column
    assert rows[0]["top_curvature_released"] > 0    # the longer cortex on the convex side
    assert summary["rows"] == rows and rows[0]["status"] == "done"
    assert (tmp_path / "fields.png").is_file() and (tmp_path / "curved" / "fields.png").is_file()
    r = results["curved"]
    scene = FoldingScene.from_settings({**settings, "axons": "curved"})
    theta_c = 1 + scene.cortex_rate * scene.t_end
    s, values = postprocess.sample_line(r.domain, {"b": r.fields["b_e3"]}, (0.25, 0.0),
                                        (0.25, scene.height), n=3001)
    b1 = -values["b"][:, 0]
    integral = np.sum((b1[1:] + b1[:-1]) / 2 * np.diff(s))
    assert (theta_c - 1) / theta_c - 1e-3 < integral < theta_c - 1 + 1e-3
    below = s < scene.height - scene.cortex_thickness - scene.maxh
    np.testing.assert_allclose(values["b"][below], 0.0, atol=1e-9)
    assert rows[0]["burgers_max"] == pytest.approx(r.metrics["burgers_max"])
    # grown to t_end on the flat branch: nothing inverted, the top nowhere in contact, and
    # the band of one cortex thickness about the interface holds part of int |b| dX2
    m = r.metrics
    assert m["t_reached"] == pytest.approx(scene.t_end)
    assert m["theta_c_reached"] == pytest.approx(theta_c)
    assert m["Je_min"] > 0.5
    assert m["self_contact_area"] == 0 and m["self_contact_penetration_max"] == 0
    band = m["burgers_interface_mean"] * scene.cortex_thickness
    assert 0.25 * (theta_c - 1) / theta_c < band <= theta_c - 1 + 1e-3
    assert abs(rows[0]["burgers_max_depth"] - scene.cortex_thickness) <= scene.cortex_maxh
    section = r.profiles["section"]
    assert section["u"].shape == (len(section["X2"]), len(section["X1"]), 2)
    # the release's pseudo-time steps are one Newton step each, its last Newton solve (no
    # viscosity, dt = 0) to the full tolerance of the residual where the release began
    steps = r.solver["release"].steps
    flow = [step for step in steps if step.dt > 0]
    assert flow and all(s.iterations == 1 and s.tangents == 1 for s in flow)
    assert list(r.solver) == ["perfect", "release"]
    final = steps[-1]
    assert final.dt == 0 and final.residuals[-1] <= 1e-9 * steps[0].residuals[0]


@pytest.mark.parametrize("waves", [1, 2, 3, 17])
def test_sulci_of_a_cosine_between_symmetry_planes(waves):
    """z = a cos(k pi x / L), k half waves: a trough at every odd multiple of L / k, one half
    of a sulcus where it falls on an end (k odd: at x = L), each 2 a deep; a ripple of a
    twentieth of the amplitude on top (twin troughs about each trough) does not count."""
    x = np.linspace(0, 3, 601)
    z = 0.01 * np.cos(waves * np.pi * x / 3)
    count, depth = sulci(z + 0.0005 * np.cos(80 * np.pi * x / 3))
    assert count == waves / 2
    assert depth == pytest.approx(0.02, rel=0.1)
    assert sulci(z) == (waves / 2, pytest.approx(0.02, rel=0.005))
    assert sulci(np.full(5, 0.3)) == (0.0, 0.0)


@pytest.fixture(scope="module")
def flat_case():
    """A short bilayer's case, not grown (theta = 1 everywhere), without a march."""
    return FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2}, buckle=False).build()


def neo_hookean_stretch(mu, lam, a):
    """Psi and sigma11 of a neo-Hookean body (eq. 36) stretched by 1 + a along e1 alone,
    F = diag(1 + a, 1, 1)."""
    J = 1 + a
    psi = mu / 2 * (J * J + 2 - 3 - 2 * np.log(J)) + lam / 2 * np.log(J) ** 2
    return psi, (mu * (J * J - 1) + lam * np.log(J)) / J


def test_energy_and_stress_of_a_uniform_stretch_of_the_ungrown_bilayer(flat_case):
    """u = (a X1, 0) with no growth: the energy per unit depth is each layer's Psi times its
    area, and the largest principal stress the stiffer cortex's sigma11, reached in it."""
    case, scene = flat_case, flat_case.scene
    a = 0.1
    case.problem.u.Set(ngs.CF((a * ngs.x, 0.0)))
    lam = scene.lam_ratio
    cortex, sigma = neo_hookean_stretch(scene.mu_gray, lam * scene.mu_gray, a)
    sub, _ = neo_hookean_stretch(scene.mu_white, lam * scene.mu_white, a)
    area = scene.length * scene.cortex_thickness
    expected = cortex * area + sub * (scene.length * scene.height - area)
    assert measures.strain_energy(case, case.problem.u) == pytest.approx(expected, rel=1e-10)
    metrics = {}
    fields = measures.stresses(case, case.growth, case.problem.u, "_stretched", metrics)
    assert set(fields) == {"sigma_stretched", "sigma_max_stretched"}
    assert metrics["max_principal_stress_stretched"] == pytest.approx(sigma, rel=1e-8)
    assert 0 <= metrics["peak_tension_depth_stretched"] <= scene.cortex_thickness + 1e-12
    case.problem.u.Set(ngs.CF((0.0, 0.0)))
    assert measures.strain_energy(case, case.problem.u) == pytest.approx(0.0, abs=1e-14)


def test_the_unloaded_bilayer_is_uninverted_and_out_of_contact(flat_case):
    case = flat_case
    case.problem.u.Set(ngs.CF((0.0, 0.0)))
    assert measures.contact_metrics(case, Solution()) == {
        "Je_min": pytest.approx(1.0, abs=1e-12), "self_contact_area": 0.0,
        "self_contact_penetration_max": 0.0}
    case.problem.u.Set(ngs.CF((-0.2 * ngs.x, 0.0)))           # Je = det F = 0.8
    assert measures.contact_metrics(case, Solution())["Je_min"] == pytest.approx(0.8)


@pytest.mark.parametrize("slope, corner", [((1.0, 2.0), (1, 1)), ((1.0, -1.0), (1, 0)),
                                           ((-1.0, -1.0), (0, 0))])
def test_the_largest_burgers_vector_is_located_by_its_depth_and_x1(flat_case, slope, corner):
    """A linear field is largest at a corner of the section (X1 = corner[0] L, X2 =
    corner[1] H): its value, its depth below the top (height - X2) and its X1 exactly."""
    scene = flat_case.scene
    x1, x2 = corner[0] * scene.length, corner[1] * scene.height
    found = measures.burgers_metrics(flat_case, slope[0] * ngs.x + slope[1] * ngs.y)
    assert found["burgers_max_depth"] == pytest.approx(scene.height - x2, abs=1e-12)
    assert found["burgers_max_X1"] == pytest.approx(x1, abs=1e-12)
    assert found["burgers_max"] == pytest.approx(slope[0] * x1 + slope[1] * x2, abs=1e-12)


def test_the_interface_mean_is_over_one_cortex_thickness_about_the_interface(flat_case):
    """A hat of height 1 over the band (1 at the interface, 0 at the band's edges) has the
    mean 1/2 over it; a field that vanishes in the band has none."""
    scene = flat_case.scene
    interface, half = scene.height - scene.cortex_thickness, scene.cortex_thickness / 2
    distance = ngs.sqrt((ngs.y - interface) ** 2)
    hat = ngs.IfPos(half - distance, 1 - distance / half, 0.0)
    assert measures.interface_mean(flat_case, hat) == pytest.approx(0.5, rel=2e-3)
    outside = ngs.IfPos(distance - 2 * half, 1.0, 0.0)
    assert measures.interface_mean(flat_case, outside) == pytest.approx(0.0, abs=1e-12)


def test_the_depth_profile_runs_down_the_middle_from_the_top(flat_case):
    """X2 sampled against the depth gives height - depth; fields outside DEPTH_FIELDS are
    left out."""
    H = flat_case.scene.height
    profile = measures.depth_profile(flat_case, {"theta_a": ngs.y, "other": ngs.x}, n=41)
    assert set(profile) == {"depth", "theta_a"}
    assert profile["depth"][0] == 0 and profile["depth"][-1] == pytest.approx(H)
    np.testing.assert_allclose(profile["theta_a"], H - profile["depth"], atol=1e-8)


def test_the_section_grid_samples_the_panels_fields_refined_at_the_top(flat_case):
    """n columns over the length; 41 rows over the top five cortex thicknesses (here the whole
    height), 30 below; a panel's field without its displacement is not sampled."""
    scene = flat_case.scene
    flds = {"theta_a": ngs.x, "u": ngs.CF((0.0, ngs.y)), "sigma_max_released": ngs.CF(1.0)}
    grid = measures.section(flat_case, flds, n=31)
    assert set(grid) == {"X1", "X2", "theta_a", "u"}
    assert len(grid["X1"]) == 31 and grid["X2"][0] == 0 and grid["X2"][-1] == scene.height
    top = scene.height - 5 * scene.cortex_thickness
    assert np.sum(grid["X2"] >= top - 1e-12) == 41
    assert grid["theta_a"].shape == (len(grid["X2"]), 31)
    np.testing.assert_allclose(grid["theta_a"], np.broadcast_to(grid["X1"], (len(grid["X2"]),
                                                                             31)), atol=1e-12)
    np.testing.assert_allclose(grid["u"][..., 1], np.broadcast_to(grid["X2"][:, None],
                                                                  (len(grid["X2"]), 31)),
                               atol=1e-12)
