"""The brain atrophy scene (section 3.5): compatible atrophy is stress free, the released body
is self-equilibrated, volumes add up, bad input is named."""

import ngsolve as ngs
import numpy as np
import pytest

from geometries import brain
from ngincompat import sampling
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.mechanics.atrophy import AtrophyLaw
from ngincompat.scenes import AtrophyScene, get_scene
from ngincompat.workflow import output

#: A small brain (3 x 2.5 x 2 cm, gray shell 0.5 cm), ten years in steps of one: seconds.
SMALL = dict(semi_axes="3,2.5,2", gray_thickness=0.5, t_end=10.0, dt=1.0, snapshots=1,
             g_order=2, outputs="none")


def logistic_backward_euler(c0, alpha, dt, n):
    """The backward-Euler logistic map, solved in closed form: c - dt alpha c (1 - c) = c_n."""
    c, out = c0, []
    for _ in range(n):
        a = dt * alpha
        c = ((a - 1) + np.sqrt((1 - a) ** 2 + 4 * a * c)) / (2 * a)
        out.append(c)
    return np.array(out)


def test_brain_semi_axes_lie_along_e1_e2_e3():
    mesh = brain(semi_axes=(3.0, 2.5, 2.0), gray=0.5, maxh=1.0, curve_order=1)
    pts = np.array([v.point for v in mesh.vertices])
    assert np.max(np.abs(pts), axis=0) == pytest.approx([3.0, 2.5, 2.0], abs=0.02)  # vertices


def test_registered_with_units():
    assert get_scene("atrophy") is AtrophyScene
    assert AtrophyScene.unit_of(AtrophyScene.parameters()["d_ext"][2]) == "cm^2/yr"
    units = {m: AtrophyScene.metric_unit(m) for m in ("front_radius", "c_integral",
                                                     "burgers_max", "volume_loss")}
    assert units == {"front_radius": "cm", "c_integral": "cm^3", "burgers_max": "1/cm",
                     "volume_loss": "-"}


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


@pytest.mark.parametrize("times, message", [
    ("0,5", r"times.*in \[0.001, 150\]"), ("5,11", r"times.*\(0, t_end = 10\]"),
    ((5.0, 11.0), r"times.*\(0, t_end = 10\]"),
    ("a,b", r"^times = 'a,b' is not a valid list of floats: allowed a comma list of numbers"),
])
def test_times_outside_the_run_are_refused(times, message):
    with pytest.raises(ParameterError, match=message):
        AtrophyScene(times=times, seed="uniform", **SMALL)


@pytest.mark.parametrize("setting, match", [
    ({"d_ext": -1.0}, "d_ext.*in \\[0, "),
    ({"seed": "0,0,-7"}, "seed.*inside or on the body"),
    ({"rate_gray": 4.0, "dt": 0.1}, "rate_gray.*pass theta_min"),
    ({"theta_min": 1.2}, "theta_min.*in \\(0, 1\\)"),
    ({"semi_axes": "1,2"}, "semi_axes"),
])
def test_bad_input_names_the_parameter_and_range(setting, match):
    with pytest.raises(ParameterError, match=match):
        AtrophyScene(**setting)


def test_bad_input_on_the_command_line_exits_2_with_one_line(capsys, tmp_path):
    assert main(["run", "atrophy", "--out", str(tmp_path / "a"), "--set", "d_ext=-0.1"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "d_ext" in err


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


def test_curvature_on_hexahedra_is_refused_before_computing(tmp_path):
    from conftest import voxel_labels as labels
    from conftest import write_nifti as write
    path = tmp_path / "brain.nii.gz"
    write(path, labels())
    with pytest.raises(ParameterError, match="needs a tetrahedral mesh"):
        AtrophyScene(geometry=str(path), maxh=0.5, seed="uniform",
                     **dict(SMALL, outputs="curvature")).build()
