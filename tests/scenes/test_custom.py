"""ngincompat.scenes.custom: the user's own geometry, growth and material, from expressions,
mesh files and growth data."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene, CustomScene


def test_custom_fiber_growth_from_the_command_line(tmp_path):
    code = main(["run", "custom", "--out", str(tmp_path), "--set", "growth=fiber",
                 "--set", "direction=e1", "--set", "theta=1 + X2*t/4", "--order", "2",
                 "--maxh", "0.5", "--set", "outputs=none", "-q"])
    assert code == 0
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["params"]["growth"] == "fiber"
    # eq. (27): |b| on n3 = e3 is 1/(4 theta), largest (1/4) where theta = 1
    assert results["metrics"]["burgers_max"] == pytest.approx(0.25, rel=1e-6)
    assert results["metrics"]["G_error_L2_rel"] < 1e-6
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_custom_goh_area_growth(tmp_path):
    scene = CustomScene(growth="area", direction="e3", theta="1 + 0.25*(X1 + X2**2)*t",
                        material="goh", mu=0.1, nu=0.45, k1=0.5, k2=2.0, kappa=0.1,
                        fiber="e1", order=2, maxh=0.5, outputs="none")
    results = scene.run()
    assert results.converged
    assert results.metrics["strain_energy"] > 0
    assert results.metrics["G_error_L2_rel"] < 1e-4


def test_custom_scene_on_a_vol_file_with_growth_data_from_a_previous_run(tmp_path):
    """A run writes its mesh and growth field (outputs=growth); a custom run on that mesh file
    with the growth as data reproduces it: theta = 1 + X1 t / 4 is linear, so its order-2
    interpolant is exact and the ramp 1 + t (theta_data - 1) is the cube's own time path."""
    first = CubeScene(order=2, maxh=0.5, outputs="growth").run(tmp_path / "first")
    again = CustomScene(mesh=str(tmp_path / "first" / "mesh.vol"),
                        theta_file=str(tmp_path / "first" / "growth.npz"), order=2,
                        outputs="none").run()
    assert "G_error_L2_rel" not in again.metrics     # no closed form for data
    for key in ("strain_energy", "max_principal_stress"):
        assert again.metrics[key] == pytest.approx(first.metrics[key], rel=1e-8), key
    # G of the data comes from its projection (g_order 6), the analytic run's is exact
    for key in ("burgers_max", "G_norm_L2"):
        assert again.metrics[key] == pytest.approx(first.metrics[key], rel=1e-6), key


def test_custom_scene_on_a_gmsh_file(tmp_path):
    from workflow.test_inputs import write_box_msh
    path = tmp_path / "box.msh"
    write_box_msh(path, n=(2, 1, 1), size=(2.0, 1.0, 1.0))
    results = CustomScene(mesh=str(path), theta="1 + 0.1*X1*t", order=2,
                          outputs="none").run()
    assert results.mesh.ne > 0 and results.converged
    assert results.metrics["G_error_L2_rel"] < 1e-6
    # eq. (16): |b| on n2 is |grad theta| / (3 theta^(4/3)), largest where theta = 1
    assert results.metrics["burgers_max"] == pytest.approx(0.1 / 3, rel=1e-5)


@pytest.mark.parametrize("settings, message", [
    ({"mesh": "missing.vol"}, "mesh = 'missing.vol' is out of range: allowed an existing file"),
    ({"theta_file": "missing.npz"}, "theta_file = 'missing.npz'"),
])
def test_custom_scene_refuses_missing_files(settings, message):
    with pytest.raises(ParameterError, match=message):
        CustomScene(**settings)


def test_custom_scene_refuses_a_mesh_file_together_with_a_geometry(tmp_path):
    path = tmp_path / "m.vol"
    path.write_text("x")
    with pytest.raises(ParameterError, match="geometry = 'disc'"):
        CustomScene(mesh=str(path), geometry="disc")


def test_a_file_of_another_kind_is_refused_naming_the_kinds_read(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "body.stl").write_text("solid")
    with pytest.raises(ParameterError, match=r"^mesh = 'body\.stl' is out of range: allowed "
                                             r"a file ending in \.vol, \.vol\.gz, \.msh"):
        CustomScene(mesh="body.stl")


def test_growth_data_and_an_expression_together_are_refused(tmp_path):
    path = tmp_path / "growth.npz"
    path.write_text("x")
    with pytest.raises(ParameterError, match=r"^theta = '1 \+ t' .* left unset when the growth "
                                             r"is given as data"):
        CustomScene(theta_file=str(path), theta="1 + t")


@pytest.mark.parametrize("line, axis", [("X1", 0), ("X2", 1), ("X3", 2)])
def test_the_profile_line_crosses_the_bounding_box_through_its_centre(line, axis, tmp_path):
    """On a 2 x 1 x 1 box from a mesh file: the line along the chosen axis from face to face,
    the other coordinates those of the box's centre."""
    from workflow.test_inputs import write_box_msh

    path = tmp_path / "box.msh"
    write_box_msh(path, n=(2, 1, 1), size=(2.0, 1.0, 1.0))
    case = CustomScene(mesh=str(path), line=line, order=1, g_order=2).build()
    start, end, coord = case.line
    centre = (1.0, 0.5, 0.5)
    size = (2.0, 1.0, 1.0)
    assert coord == line
    for k in range(3):
        expected = (0.0, size[k]) if k == axis else (centre[k], centre[k])
        assert (start[k], end[k]) == pytest.approx(expected, abs=1e-12)
