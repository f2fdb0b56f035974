"""ngincompat.scenes.atrophy.case: compatible atrophy is stress free, the released body is
self-equilibrated, volumes add up, frames and sections hold what the paper finds."""

import ngsolve as ngs
import numpy as np
import pytest
from scenes.atrophy.test_scene import SMALL

from ngincompat import sampling
from ngincompat.mechanics.atrophy import AtrophyLaw
from ngincompat.scenes import AtrophyScene
from ngincompat.workflow import output


def logistic_backward_euler(c0, alpha, dt, n):
    """The backward-Euler logistic map, solved in closed form: c - dt alpha c (1 - c) = c_n."""
    c, out = c0, []
    for _ in range(n):
        a = dt * alpha
        c = ((a - 1) + np.sqrt((1 - a) ** 2 + 4 * a * c)) / (2 * a)
        out.append(c)
    return np.array(out)


def test_equal_rates_and_uniform_c_are_compatible():
    """theta uniform: G = 0, no stress, J = theta to round-off; theta from the logistic map."""
    scene = AtrophyScene(maxh=2.0, seed="uniform", rate_gray=0.03, rate_white=0.03, **SMALL)
    results = scene.run()
    m, f, mesh = results.metrics, results.fields, results.domain
    assert m["burgers_max"] < 1e-10
    assert m["G_norm_L2"] < 1e-10
    s = f["sigma_max_principal"]
    assert max(sampling.maximum(s, mesh), sampling.maximum(-s, mesh)) < 1e-9
    assert m["Je_deviation_max"] < 1e-10
    assert m["volume_bookkeeping_error"] < 1e-12
    c = logistic_backward_euler(0.1, 0.6, 1.0, 10)
    theta = AtrophyLaw(0.03, 0.7).theta(np.sum(c))
    for key in ("volume_loss", "gray_volume_loss", "white_volume_loss", "volume_loss_theta"):
        assert m[key] == pytest.approx(1 - theta, rel=1e-10), key
    assert m["c_min"] == pytest.approx(0.1) and m["c_max"] == pytest.approx(c[-1], rel=1e-12)


@pytest.fixture(scope="module")
def atrophied(tmp_path_factory):
    """The small brain with the default rates (gray 30 times faster than white), seeded at
    its basal pole, on two meshes; the finer one written to a folder."""
    out = tmp_path_factory.mktemp("atrophy")
    settings = dict(SMALL, seed="0,0,-2", seed_radius=1.0, d_ext=0.05)
    coarse = AtrophyScene(maxh=1.0, **settings).run()
    fine = AtrophyScene(maxh=0.5, **dict(settings, outputs="vtk,figures")).run(out)
    return coarse, fine, out


def test_released_body_is_self_equilibrated(atrophied):
    coarse, fine, _ = atrophied
    residuals = [r.metrics["equilibrium_residual_rel"] for r in (coarse, fine)]
    assert residuals[1] < residuals[0] and residuals[1] < 1e-2, residuals


def test_volume_bookkeeping(atrophied):
    for r in atrophied[:2]:
        m = r.metrics
        assert m["volume_bookkeeping_error"] <= m["Je_deviation_max"]
        assert m["volume_loss"] == pytest.approx(m["volume_loss_theta"], abs=1e-3)
        assert m["gray_volume_loss"] > 5 * m["white_volume_loss"] > 0
        assert m["theta_min_reached"] > 0.7 and m["c_min"] >= 0 and m["c_max"] <= 1


def test_outputs_and_profiles(atrophied):
    _, fine, out = atrophied
    line = fine.profile("line")
    for key in ("R", "c", "theta", "sigma_rr", "sigma_thetatheta", "burgers"):
        assert key in line
    # |b| peaks at the gray/white interface, 0.5 cm below the surface along +X1, within the
    # elements next to it (h = 0.5), over which the projected path smears the jump of theta
    assert fine.metrics["burgers_peak_depth"] == pytest.approx(0.5, abs=0.5 + 1e-9)
    series = fine.profile("series")
    assert len(series["t"]) == 11 and np.all(np.diff(series["c_integral"]) > 0)
    assert np.all(np.diff(series["front_radius"]) >= 0)
    for name in ("sections.png", "volume_loss.png", "spreading.png", "fields.vtu"):
        assert (out / name).is_file(), name
    back = output.read(out)
    assert back.figures[-1].kind == "maps"
    assert back.profile("sections")["e3_theta"].shape == (121, 121)


def test_the_burgers_vectors_of_each_section_lie_in_its_plane_as_the_paper_finds(atrophied):
    """Fig. 5d: "The Burgers vectors are in the plane and aligned with the interface". For
    isotropic growth Fg = theta I, G^T n is proportional to grad theta x n (eqs. 10, 11): in
    the plane, and across grad theta, which the jump of the growth rate at the gray/white
    interface points along the interface's normal. On each section b's normal component is
    round-off against |b|, its in-plane components make up |b|, and where |b| is large they
    are near tangent to the interface (the inner ellipsoid, semi-axes less the gray
    thickness: a median |cos| to its normal of 0.09-0.14 on this coarse mesh, where vectors
    of any direction would give about 0.7); the figure draws them as arrows."""
    _, fine, _ = atrophied
    sections = fine.profile("sections")
    inner = np.array([3.0, 2.5, 2.0]) - 0.5
    for k, plane in enumerate(("e1", "e2", "e3")):
        norm = sections[f"{plane}_|b|"]
        inplane = sections[f"{plane}_b_inplane"]
        big = np.isfinite(norm) & (norm > 0.3 * np.nanmax(norm))
        assert big.sum() > 50
        assert np.nanmax(np.abs(sections[f"{plane}_b_normal"])) < 1e-8 * np.nanmax(norm)
        assert np.allclose(np.linalg.norm(inplane, axis=-1)[big], norm[big], rtol=1e-8)
        i, j = [m for m in range(3) if m != k]
        U, V = np.meshgrid(sections[f"{plane}_u"], sections[f"{plane}_v"])
        normal = np.stack([U / inner[i] ** 2, V / inner[j] ** 2], axis=-1)[big]
        cosine = (np.abs(np.sum(normal * inplane[big], axis=-1))
                  / (np.linalg.norm(normal, axis=-1) * norm[big]))
        assert np.median(cosine) < 0.25, np.median(cosine)
    sections_figure = next(f for f in fine.figures if f.file == "sections.png")
    assert len(sections_figure.arrows) == 3


def test_frames_at_chosen_times_make_a_pvd_time_series(tmp_path):
    """Frames at t = 4, 7 and the end: the collection names them in order, and each frame
    holds the state of its time (frozen), not the end's."""
    scene = AtrophyScene(maxh=2.0, seed="0,0,-1.5", times="7,4",
                         **dict(SMALL, outputs="vtk"))
    results = scene.run(tmp_path)
    assert [t for t, _ in results.frames] == pytest.approx([4.0, 7.0, 10.0])
    assert list(results.solver) == ["t=4", "t=7", "t=10"]
    pvd = (tmp_path / "fields.pvd").read_text()
    names = [f"fields_{k:03d}.vtu" for k in range(3)]
    for t, name in zip((4.0, 7.0, 10.0), names, strict=True):
        assert f'timestep="{t!r}"' in pvd and f'file="{name}"' in pvd
        assert (tmp_path / name).stat().st_size > 0 and name in results.files
    mesh, series, snaps = results.domain, results.profile("series"), results.profile("snapshots")
    volume0 = ngs.Integrate(1.0, mesh)
    for k, (t, frame) in enumerate(results.frames):
        assert set(frame) == {"c", "theta", "u", "J", "Je", "|b_e1|", "|b_e2|", "|b_e3|",
                              "sigma_max_principal"}
        step = int(np.argmin(np.abs(series["t"] - t)))
        # the series integrates with the lumped mass (vertex rule on curved elements): 3e-3
        assert ngs.Integrate(frame["c"], mesh) == pytest.approx(series["c_integral"][step],
                                                                rel=1e-2)
        loss = 1 - ngs.Integrate(frame["J"], mesh, order=6) / volume0
        assert loss == pytest.approx(snaps["total_volume_loss"][k], abs=1e-4)
    losses = snaps["total_volume_loss"]
    assert 0 < losses[0] < losses[1] < losses[2]


def test_curvature_of_the_growth_metric_beside_b():
    """Uniform theta is a constant metric, flat: the verdict is compatible; a seeded front
    with gray atrophying faster is not, and |Ein|_g is sampled beside |b|."""
    flat = AtrophyScene(maxh=2.0, seed="uniform", rate_gray=0.03, rate_white=0.03,
                        **dict(SMALL, outputs="curvature")).run()
    assert flat.metrics["einstein_norm_L2"] < 1e-8        # 5e-10 measured
    assert "compatible: a stress-free state exists" in "\n".join(flat.metric_lines())
    curved = AtrophyScene(maxh=2.0, seed="0,0,-1.5", seed_radius=1.0,
                          **dict(SMALL, outputs="curvature")).run()
    m = curved.metrics
    assert m["einstein_norm_L2"] > 1e6 * flat.metrics["einstein_norm_L2"]     # 0.77
    assert m["scalar_curvature_min"] < 0 < m["scalar_curvature_max"]
    assert "incompatible" in "\n".join(curved.metric_lines())
    line = curved.profile("line")
    assert np.nanmax(line["einstein_norm_g"]) > 0 and "curvature.png" in [
        f.file for f in curved.figures]


def test_curvature_on_a_tetrahedral_voxel_brain(tmp_path):
    """The voxel brain split into tetrahedra: equal rates with a uniform c stay compatible
    (flat metric, no stress) through the staircase surface and interface; gray atrophying
    faster is not."""
    from conftest import voxel_labels as labels
    from conftest import write_nifti as write
    path = str(write(tmp_path / "brain.nii.gz", labels()))
    settings = dict(SMALL, geometry=path, elements="tet", maxh=0.5, outputs="curvature")
    flat = AtrophyScene(seed="uniform", rate_gray=0.03, rate_white=0.03, **settings).run()
    m = flat.metrics
    assert m["einstein_norm_L2"] < 1e-8 and m["burgers_max"] < 1e-10
    assert m["Je_deviation_max"] < 1e-10
    assert "compatible: a stress-free state exists" in "\n".join(flat.metric_lines())
    curved = AtrophyScene(seed="uniform", **settings).run()
    assert curved.metrics["einstein_norm_L2"] > 1e6 * max(m["einstein_norm_L2"], 1e-16)
    assert "incompatible" in "\n".join(curved.metric_lines())


@pytest.fixture
def uniform_case():
    """The small brain's case (2 cm elements) with a uniform seed, before any step."""
    return AtrophyScene(maxh=2.0, seed="uniform", **dict(SMALL, snapshots=2)).build()


def test_one_stage_per_snapshot_each_from_the_last(uniform_case):
    stages = uniform_case.stages()
    assert [(s.name, s.first, s.last, s.dt) for s in stages] == [("t=5", 0, 5, 1.0),
                                                                 ("t=10", 5, 10, 1.0)]
    assert all(s.case is uniform_case for s in stages)


def test_the_reference_volumes_are_those_of_the_ellipsoids(uniform_case):
    """Gray: the shell between the ellipsoid (3, 2.5, 2) and the inner one, its semi-axes
    less 0.5; white: the inner one (4/3 pi abc each, to the curved mesh's geometry error)."""
    outer, inner = 4 / 3 * np.pi * 3.0 * 2.5 * 2.0, 4 / 3 * np.pi * 2.5 * 2.0 * 1.5
    volume0 = uniform_case.volume0
    assert volume0["total"] == pytest.approx(outer, rel=2e-3)
    assert volume0["white"] == pytest.approx(inner, rel=2e-3)
    assert volume0["gray"] == pytest.approx(outer - inner, rel=2e-3)
    assert volume0["gray"] + volume0["white"] == pytest.approx(volume0["total"], rel=1e-14)
    assert uniform_case.volumes(ngs.CF(1.0))["total"] == pytest.approx(volume0["total"],
                                                                      rel=1e-10)


def test_every_step_is_recorded_with_the_amount_of_protein(uniform_case):
    """From a uniform c0 = 0.1 c stays uniform and follows the backward-Euler logistic map,
    so int c dV grows in its proportion (the lumped mass integrates a constant to its volume
    by the vertex rule, within 1e-2 of V on these curved elements). Nothing has atrophied at
    t = 0; gray atrophies from the first step on."""
    case = uniform_case
    assert case.series["t"] == [0.0]
    assert case.series["total_volume_loss_theta"][0] == pytest.approx(0.0, abs=1e-12)
    case.advance(3, 1.0)
    assert case.series["t"] == pytest.approx([0.0, 1.0, 2.0, 3.0])
    c = logistic_backward_euler(0.1, case.scene.alpha, 1.0, 3)
    amount = np.array(case.series["c_integral"])
    assert amount[0] == pytest.approx(0.1 * case.volume0["total"], rel=1e-2)
    np.testing.assert_allclose(amount[1:] / amount[0], c / 0.1, rtol=1e-10)
    assert case.c_extremes == pytest.approx([0.1, c[-1]], rel=1e-10)
    losses = case.series["gray_volume_loss_theta"]
    assert 0 < losses[1] < losses[2] < losses[3]
    assert "front_radius" not in case.series      # a uniform seed has no front
