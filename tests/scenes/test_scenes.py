"""Scenes end to end through the command line: results, files, errors."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene, CustomScene, HemisphereScene, SkinExpansionScene, get_scene
from ngincompat.workflow.results import Results

REQUIRED = {"scene", "status", "params", "units", "versions", "mesh", "solver", "timings",
            "metrics", "profiles", "figures", "files"}


@pytest.fixture(scope="module")
def cube_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cube")
    code = main(["run", "cube", "--out", str(out), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "-q"])
    assert code == 0
    return out, json.loads((out / "results.json").read_text())


def test_cube_run_writes_complete_results(cube_run):
    out, results = cube_run
    assert REQUIRED <= set(results)
    assert results["scene"] == "cube"
    assert results["mesh"]["order"] == 3 and results["mesh"]["maxh"] == 0.5
    assert results["mesh"]["ndof"] > 0 and results["mesh"]["ne"] == 8
    assert set(results["versions"]) >= {"ngincompat", "ngsolve", "netgen", "numpy", "python"}
    solver = results["solver"]["growth"]
    assert results["status"] == "done"
    assert solver["converged"] and solver["steps"][-1]["residuals"]
    assert all(s["iterations"] == len(s["residuals"]) - 1 for s in solver["steps"])
    assert {"mesh", "growth", "incompatibility", "postprocess", "output"} <= set(
        results["timings"])
    metrics = results["metrics"]
    assert metrics["strain_energy"] == pytest.approx(2.19533e-7, rel=0.1)
    assert metrics["G_error_L2_rel"] < 1e-5
    # max |b| over the planes n2, n3: 1 / (12 theta^(4/3)) at theta = 1, i.e. X1 = 0
    assert metrics["burgers_max"] == pytest.approx(1 / 12, rel=1e-5)
    assert metrics["G_elastic_vs_growth_L2_rel"] < 0.05
    assert {p.name for p in out.iterdir()} == {"results.json", "fields.vtu", "profile.png",
                                              "burgers.png", "stress.png"}


def test_cube_profile_is_fig1g(cube_run):
    """Along the X1 centre line: Curl Fg : Curl Fg = 2 a^2 / (9 theta^(4/3)) (from eq. 15)
    decreases with X1, and Psi > 0."""
    _, results = cube_run
    line = results["profiles"]["line"]
    import numpy as np
    X1 = np.asarray(line["X1"])
    theta = 1 + X1 / 4
    np.testing.assert_allclose(line["curlFg_sq"], 2 * 0.0625 / (9 * theta ** (4 / 3)),
                               rtol=1e-5)
    np.testing.assert_allclose(line["theta"], theta, rtol=1e-8)
    assert min(line["Psi"]) > 0
    assert X1[0] == pytest.approx(0) and X1[-1] == pytest.approx(1)


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


@pytest.mark.parametrize("argv, message", [
    (["run", "nowhere", "--out", "o"], "unknown scene 'nowhere'"),
    (["run", "cube", "--out", "o", "--set", "colour=red"], "unknown parameter 'colour'"),
    (["run", "cube", "--out", "o", "--set", "nu=0.5"], "nu = 0.5 is out of range"),
    (["run", "cube", "--out", "o", "--order", "0"], "order = 0 is out of range"),
    (["run", "cube", "--out", "o", "--set", "order=two"], "not a valid int"),
    (["run", "cube", "--out", "o", "--set", "nu"], "KEY=VALUE"),
    (["run", "custom", "--out", "o", "--set", "theta=exp(X1"], "not a valid expression"),
    (["run", "custom", "--out", "o", "--set", "growth=volume"], "growth = 'volume'"),
    (["run", "custom", "--out", "o", "--set", "theta=1 - 2*X1*t"], "must be finite and positive"),
    (["run", "custom", "--out", "o", "--set", "outputs=pdf"], "outputs = 'pdf'"),
    (["run", "custom", "--out", "o", "--set", "direction=up"], "direction = 'up'"),
    (["run", "cube", "--out", "o", "--set", "model=half"], "model = 'half'"),
    (["run", "cube", "--out", "o", "--set", "formulation=hybrid"], "formulation = 'hybrid'"),
    (["run", "disc", "--out", "o", "--set", "formulation=mixed"], "mixed needs a bulk split"),
])
def test_bad_input_exits_2_with_one_line(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    # one error line, the last; progress lines may precede it where the check needs the mesh
    lines = err.splitlines()
    assert lines[-1].startswith("ngincompat: error:")
    assert sum(line.startswith("ngincompat:") for line in lines) == 1
    assert len(lines) == 1 or "the growth indicator must be" in lines[-1]


def test_list_names_every_scene(capsys):
    assert main(["list", "-v"]) == 0
    out = capsys.readouterr().out
    assert "cube" in out and "custom" in out and "theta" in out


def test_scene_registry_and_settings():
    assert get_scene("cube") is CubeScene
    scene = CubeScene.from_settings({"order": "3", "nu": "0.3", "elements": "tet"})
    assert (scene.order, scene.nu, scene.elements) == (3, 0.3, "tet")
    with pytest.raises(ParameterError):
        get_scene("sphere")


def test_incompatibility_only_builds_no_mechanics(tmp_path, monkeypatch):
    """G depends on Fg alone: asking only for incompatibility never builds the mechanics."""
    from ngincompat.scenes import prescribed

    def forbidden(*args, **kwargs):
        raise AssertionError("a mechanics problem was built")

    monkeypatch.setattr(prescribed, "GrowthMechanics", forbidden)
    code = main(["run", "cube", "--out", str(tmp_path), "--outputs", "incompatibility",
                 "--maxh", "0.5", "-q"])
    assert code == 0
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["solver"] == {} and "strain_energy" not in results["metrics"]
    assert results["metrics"]["G_error_L2_rel"] < 1e-6
    assert results["params"]["mechanics"] is False
    assert "Psi" not in results["profiles"]["line"]
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]
    with pytest.raises(AssertionError, match="mechanics problem was built"):
        main(["run", "cube", "--out", str(tmp_path), "--maxh", "0.5", "-q", "--overwrite"])


def test_incompatibility_only_keeps_the_scene_checks(tmp_path):
    results = main(["run", "cylinder", "--out", str(tmp_path), "--outputs", "incompatibility",
                    "--order", "2", "--maxh", "0.4", "-q"])
    assert results == 0
    metrics = json.loads((tmp_path / "results.json").read_text())["metrics"]
    assert metrics["b_eq27_error"] < 1e-6
    assert "Fe_rotation_deviation" not in metrics


def test_bad_outputs_list_exits_2(capsys, tmp_path):
    assert main(["run", "cube", "--out", str(tmp_path), "--outputs", "stress"]) == 2
    assert "--outputs 'stress'" in capsys.readouterr().err


def test_scene_describes_its_parameters_in_its_units():
    text = CubeScene(maxh=0.5).describe()
    assert "maxh" in text and "0.5" in text and "[mm]" in text and "[MPa]" in text
    assert "outputs" not in text


def test_quarter_cube_is_the_full_cube_with_mirror_planes(cube_run, tmp_path):
    """The quarter model (two mirror planes, one pinned dof) gives the full cube's energy,
    G error and largest stress from a quarter of the elements."""
    _, full = cube_run
    code = main(["run", "cube", "--out", str(tmp_path), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "--set", "model=quarter", "--set", "outputs=none", "-q"])
    assert code == 0
    quarter = json.loads((tmp_path / "results.json").read_text())
    assert quarter["mesh"]["ne"] * 4 == full["mesh"]["ne"]
    for key in ("strain_energy", "max_principal_stress", "G_norm_L2"):
        assert quarter["metrics"][key] == pytest.approx(full["metrics"][key], rel=1e-6), key
    assert quarter["metrics"]["G_error_L2_rel"] < 1e-8


def test_mixed_formulation_from_the_command_line(cube_run, tmp_path):
    """At nu = 0.4 the mixed and the displacement formulation agree to the discretisation
    error (order 3 on 2 x 2 x 2 hexahedra: 0.9 %, against 2.3 % of the displacement one from
    the converged 2.195334e-7)."""
    _, full = cube_run
    code = main(["run", "cube", "--out", str(tmp_path), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "--set", "formulation=mixed", "--set", "outputs=none",
                 "-q"])
    assert code == 0
    mixed = json.loads((tmp_path / "results.json").read_text())
    reference = 2.195334e-7
    e_mixed, e_displacement = mixed["metrics"]["strain_energy"], full["metrics"]["strain_energy"]
    assert abs(e_mixed - reference) < abs(e_displacement - reference)
    assert abs(e_mixed - reference) / reference < 0.02


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


def test_metric_units_follow_the_scene():
    assert HemisphereScene.metric_unit("burgers_max") == "1/mm"
    assert HemisphereScene.metric_unit("radial_sigma_rr_error") == "-"
    assert SkinExpansionScene.metric_unit("burgers_max_radius") == "cm"
    assert SkinExpansionScene.metric_unit("volume_inflated") == "cm^3"
    assert SkinExpansionScene.metric_unit("strain_energy_released") == "MPa cm^3 (J)"


def test_a_run_reports_its_metrics_with_units():
    results = CubeScene(maxh=1.0, order=1, g_order=2).run()
    assert results.metric_units["strain_energy"] == "N mm"
    assert results.metric_units["G_error_L2_rel"] == "-"
    assert set(results.metric_units) >= set(results.metrics)
    lines = results.metric_lines()
    assert any(line.split()[0] == "max_principal_stress" and line.endswith("MPa")
               for line in lines)
    assert Results.from_dict(results.to_dict()).metric_units == results.metric_units
