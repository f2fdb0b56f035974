"""ngincompat.scenes.hemisphere: the half ball of section 3.2 against the 1-D radial solution,
its quarter model and the directions of its Burgers vectors."""

import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import Box, OCCGeometry, Pnt

from ngincompat.errors import ParameterError
from ngincompat.references.radial import solve_radial
from ngincompat.scenes import HemisphereScene
from ngincompat.scenes.hemisphere import PROFILES, spherical_basis
from ngincompat.studies import paper


def test_radial_reference_is_stress_free_for_uniform_growth():
    ref = solve_radial(lambda R: 1.5 + 0 * R, 0.55, 1.1)
    R = np.linspace(0.05, 1, 9)
    assert np.max(np.abs(np.concatenate(ref.cauchy(R)))) < 1e-10
    assert ref.radius(1.0) == pytest.approx(1.5 ** (1 / 3), rel=1e-10)


@pytest.fixture(scope="module")
def hemisphere_symmetry():
    """The linear profile in symmetry mode at default settings."""
    return HemisphereScene(flat_face="symmetry").run()


def test_hemisphere_symmetry_matches_radial_solution(hemisphere_symmetry):
    """sigma_rr, sigma_thetatheta, sigma_phiphi against the 1-D solution within 1e-3 of the
    largest stress at the defaults."""
    m = hemisphere_symmetry.metrics
    for key in ("radial_sigma_rr_error", "radial_sigma_thetatheta_error",
                "radial_sigma_phiphi_error"):
        assert m[key] < 1e-3, (key, m[key])


def test_hemisphere_agreement_improves_under_refinement(hemisphere_symmetry):
    coarse = HemisphereScene(flat_face="symmetry", order=3, centre_maxh=0.1).run()
    for key in ("radial_sigma_rr_error", "radial_sigma_thetatheta_error"):
        assert hemisphere_symmetry.metrics[key] < 0.5 * coarse.metrics[key]


def test_quarter_hemisphere_of_the_main_job_matches_radial_solution():
    """The main job's hemisphere (a quarter with mirror planes X1 = 0, X2 = 0, its centre
    refined to 0.04) in symmetry mode: every stress within 2e-4 of the largest, closer to the
    1-D solution than the full hemisphere at its defaults (1.8-2.1e-4)."""
    m = HemisphereScene(flat_face="symmetry", **paper.HEMISPHERE).run().metrics
    for key in ("radial_sigma_rr_error", "radial_sigma_thetatheta_error",
                "radial_sigma_phiphi_error"):
        assert m[key] < 2e-4, (key, m[key])


def test_quarter_hemisphere_is_the_full_one_with_mirror_planes():
    """The free-face hemisphere is symmetric about X1 = 0 and X2 = 0: the quarter model (one
    pinned dof, the translation along X3) gives the full body's strain energy (reported for
    the whole body) up to the discretisation error of these coarse meshes (1.2e-3 measured)."""
    runs = {model: HemisphereScene(model=model, order=3, maxh=0.5, centre_maxh=0.1).run()
            for model in ("full", "quarter")}
    full, quarter = runs["full"], runs["quarter"]
    assert quarter.mesh.ne < full.mesh.ne
    assert len(HemisphereScene(model="quarter", order=2).build().mechanics().pinned) == 1
    assert quarter.metrics["strain_energy"] == pytest.approx(full.metrics["strain_energy"],
                                                             rel=2e-3)
    assert np.isfinite(quarter.metrics["burgers_max"])


def test_hemisphere_burgers_vector_directions(hemisphere_symmetry):
    """b vanishes on radial planes, is circumferential on the meridional plane and meridional
    on the circumferential plane (section 3.2), up to the projection error."""
    m = hemisphere_symmetry.metrics
    assert m["b_radial_rel"] < 5e-3
    assert m["b_meridional_off_circumferential"] < 5e-3
    assert m["b_circumferential_off_meridional"] < 5e-3
    line = hemisphere_symmetry.profile("line")
    assert np.max(line["|b_meridional|"]) > 0.05


def test_hemisphere_profiles_order_the_burgers_vector():
    """Fig. 2g: near the core |b| is largest for the concave profile, smallest for the convex
    one; near the surface the order reverses."""
    b = {}
    for profile in ("concave", "convex"):
        r = HemisphereScene(profile=profile, order=2, maxh=0.4, centre_maxh=0.1,
                            g_order=4).run()
        b[profile] = np.asarray(r.profile("line")["|b_meridional|"])
    assert b["concave"][20] > 2 * b["convex"][20]
    assert b["convex"][-5] > 2 * b["concave"][-5]


@pytest.fixture(scope="module")
def box():
    """A coarse mesh of the box [-1, 1]^3, to evaluate fields at points of any sign."""
    return ngs.Mesh(OCCGeometry(Box(Pnt(-1, -1, -1), Pnt(1, 1, 1))).GenerateMesh(maxh=1.0))


def test_the_growth_profiles_run_from_the_core_to_the_surface(box):
    """f(0) = 0, f(1) = 1; concave rises faster than linear inside, convex slower; each
    CoefficientFunction builder is its numpy twin."""
    s = np.linspace(0.0, 1.0, 11)
    for name, (_, f) in PROFILES.items():
        assert (f(0.0), f(1.0)) == (0.0, 1.0), name
    assert np.all(PROFILES["concave"][1](s[1:-1]) > s[1:-1])
    assert np.all(PROFILES["convex"][1](s[1:-1]) < s[1:-1])
    point = box(0.2, 0.3, 0.4)
    R = np.sqrt(0.2 ** 2 + 0.3 ** 2 + 0.4 ** 2)
    for name, (f_cf, f_np) in PROFILES.items():
        value = f_cf(ngs.Norm(ngs.CF((ngs.x, ngs.y, ngs.z))))(point)
        assert value == pytest.approx(f_np(R), rel=1e-14), name


@pytest.mark.parametrize("point", [(0.3, 0.4, 0.5), (-0.2, 0.1, 0.05), (0.5, -0.5, -0.2)])
def test_the_spherical_basis_is_orthonormal_with_e_r_radial_and_e_theta_about_e3(box, point):
    """e_r = X / |X|, e_theta = e3 x X / |e3 x X| (horizontal), e_phi = e_theta x e_r."""
    e = {k: np.array(v(box(*point))) for k, v in spherical_basis().items()}
    X = np.array(point)
    np.testing.assert_allclose(e["r"], X / np.linalg.norm(X), atol=1e-14)
    around = np.cross([0.0, 0.0, 1.0], X)
    np.testing.assert_allclose(e["theta"], around / np.linalg.norm(around), atol=1e-14)
    frame = np.array([e["r"], e["theta"], e["phi"]])
    np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(frame) == pytest.approx(-1.0)     # (r, theta, phi) is left-handed
    np.testing.assert_allclose(e["phi"], np.cross(e["theta"], e["r"]), atol=1e-14)


def test_the_core_mesh_size_may_not_exceed_the_mesh_size():
    with pytest.raises(ParameterError, match=r"^centre_maxh = 0\.6 .* in \(0, maxh = 0\.5\]"):
        HemisphereScene(centre_maxh=0.6)
    assert HemisphereScene(centre_maxh=0.5).centre_maxh == 0.5
