"""ngincompat.scenes.atrophy.scene: the atrophy scene's parameters, their checks against each
other, its time steps and seeds, units and warnings."""

from types import SimpleNamespace

import numpy as np
import pytest

from geometries import brain
from geometries.fsaverage_brain import from_mni
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import AtrophyScene, get_scene
from ngincompat.scenes.atrophy.scene import NAMED_SEEDS

#: A small brain (3 x 2.5 x 2 cm, gray shell 0.5 cm), ten years in steps of one: seconds.
SMALL = dict(semi_axes="3,2.5,2", gray_thickness=0.5, t_end=10.0, dt=1.0, snapshots=1,
             g_order=2, outputs="none")


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


def test_curvature_on_hexahedra_is_refused_before_computing(tmp_path):
    from conftest import voxel_labels as labels
    from conftest import write_nifti as write
    path = tmp_path / "brain.nii.gz"
    write(path, labels())
    with pytest.raises(ParameterError, match="needs a tetrahedral mesh"):
        AtrophyScene(geometry=str(path), maxh=0.5, seed="uniform",
                     **dict(SMALL, outputs="curvature")).build()


def test_the_je_warning_says_how_much_of_the_volume_it_is():
    from types import SimpleNamespace

    from ngincompat.scenes import AtrophyScene

    def lines(metrics):
        return AtrophyScene().trust(SimpleNamespace(metrics=metrics))

    (line,) = lines({"Je_deviation_max": 0.5, "Je_deviation_volume_fraction": 2e-5})
    assert line.startswith("Je_deviation_max = 0.5 > 0.1 over a volume fraction of 2e-05: ")
    assert "refine" in line
    assert lines({"Je_deviation_max": 0.5})[0].startswith("Je_deviation_max = 0.5 > 0.1: ")
    assert lines({"Je_deviation_max": 0.05, "Je_deviation_volume_fraction": 0.0}) == []


def test_the_cortex_resolution_warning_names_the_median_and_what_to_refine():
    def lines(metrics):
        return AtrophyScene().trust(SimpleNamespace(metrics=metrics))

    (line,) = lines({"cortex_elements_across_median": 1.5})
    assert line.startswith("cortex_elements_across_median = 1.5 < 2: the cortex is "
                           "under-resolved")
    assert "cortex_layers" in line
    assert lines({"cortex_elements_across_median": 2.0}) == []
    assert len(lines({"cortex_elements_across_median": 1.0, "Je_deviation_max": 0.2})) == 2


@pytest.mark.parametrize("t_end, dt, snapshots, times, steps, solved", [
    (10.0, 1.0, 3, (), 10, [3, 7, 10]),            # equally spaced, rounded to steps
    (10.0, 3.0, 4, (), 4, [1, 2, 3, 4]),           # 4 steps of 2.5 <= dt
    (10.0, 2.5, 1, (), 4, [4]),                    # t_end / dt an integer: no extra step
    (10.0, 1.0, 1, (7.6, 2.4), 10, [2, 8, 10]),    # times sorted, the end always
    (10.0, 1.0, 1, (4.9, 5.1), 10, [5, 10]),       # two times on one step: one
    (10.0, 1.0, 1, (0.01,), 10, [1, 10]),          # before the first step: the first
])
def test_time_steps_and_the_steps_solved(t_end, dt, snapshots, times, steps, solved):
    scene = AtrophyScene(t_end=t_end, dt=dt, snapshots=snapshots, times=times)
    assert scene.n_steps() == steps
    assert scene.snapshot_steps() == solved


@pytest.mark.parametrize("setting, message", [
    (dict(gray_thickness=3.0), r"^gray_thickness = 3\.0 .* in \(0, 3\) \(half the smallest "),
    (dict(seed="entorhinal"), r"^seed = 'entorhinal' .*\(named seeds need an anatomical one"),
    (dict(dt=50.0), r"^dt = 50\.0 .* in \(0, t_end = 40\]"),
    (dict(t_end=10.0, dt=1.0, snapshots=11), r"^snapshots = 11 .* \[1, 10\] \(the number of "),
    (dict(geometry="brain.stl"), r"^geometry = 'brain\.stl' .* a file ending in \.nii, "),
])
def test_settings_are_checked_against_each_other(setting, message):
    with pytest.raises(ParameterError, match=message):
        AtrophyScene(**setting)


def test_a_seed_on_the_edge_of_the_ellipsoid_is_inside():
    assert AtrophyScene(seed=(0.0, 0.0, -6.0)).seed_centre() == (0.0, 0.0, -6.0)
    assert AtrophyScene(seed="uniform").seed_centre() is None
    with pytest.raises(ParameterError, match="inside or on the body"):
        AtrophyScene(seed=(0.0, 0.0, -6.01))


def test_a_named_seed_is_mirrored_for_the_right_hemisphere():
    """The entorhinal seed in MNI mm on the left, its mirror image (MNI x negated) on the
    right, in the project's cm."""
    left = AtrophyScene(geometry="mni152", seed="entorhinal").seed_centre()
    right = AtrophyScene(geometry="mni152", seed="entorhinal", hemisphere="right").seed_centre()
    x, y, z = NAMED_SEEDS["entorhinal"]
    np.testing.assert_allclose(left, from_mni((x, y, z)))
    np.testing.assert_allclose(right, from_mni((-x, y, z)))
    differ = [i for i in range(3) if left[i] != right[i]]
    assert len(differ) == 1 and left[differ[0]] == -right[differ[0]] != 0


def test_each_tissue_has_its_law_and_moduli():
    scene = AtrophyScene(rate_gray=0.05, rate_white=0.002, theta_min=0.6, mu_gray=2.0,
                         mu_white=0.5, nu=0.45)
    laws = scene.laws()
    assert (laws["gray"].rate, laws["white"].rate) == (0.05, 0.002)
    assert laws["gray"].theta_min == laws["white"].theta_min == 0.6
    assert scene.material_moduli() == {"gray": (2.0, 0.45), "white": (0.5, 0.45)}
