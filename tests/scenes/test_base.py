"""ngincompat.scenes.base: what every scene shares: typed settings and their errors, presets,
the registry, descriptions and metric units, the limits on time steps and mesh size, and the
record of a run."""

import json
from dataclasses import dataclass

import pytest

from geometries import cube
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.parameters import PRESETS
from ngincompat.scenes import (
    SCENES,
    AtrophyScene,
    CubeScene,
    HemisphereScene,
    SkinExpansionScene,
    get_scene,
)
from ngincompat.scenes.base import MAX_TIME_STEPS, UNKNOWNS_PER_ELEMENT, Scene, check_time_steps
from ngincompat.workflow.results import Results


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


def test_a_scenes_parameter_and_preset_lines_spell_defaults_units_and_settings():
    atrophy = SCENES["atrophy"]
    assert atrophy.parameter_line("semi_axes") == (
        "semi_axes (tuple of 3 floats, default 8.5,7,6 cm): allowed three numbers in "
        "[0.001, 100]")
    assert atrophy.parameter_line("times").startswith("times (list of floats, default none yr)")
    assert CubeScene.parameter_line("mechanics") == (
        "mechanics (bool, default true): allowed true or false")
    assert CubeScene.preset_line("default") == "the defaults above"
    assert CubeScene.preset_line("preview") == " ".join(
        f"{k}={v}" for k, v in CubeScene.preset_settings("preview").items())
    assert "maxh=0.5" in CubeScene.preset_line("preview")


def test_scene_registry_and_settings():
    assert get_scene("cube") is CubeScene
    scene = CubeScene.from_settings({"order": "3", "nu": "0.3", "elements": "tet"})
    assert (scene.order, scene.nu, scene.elements) == (3, 0.3, "tet")
    with pytest.raises(ParameterError):
        get_scene("sphere")


def test_bad_outputs_list_exits_2(capsys, tmp_path):
    assert main(["run", "cube", "--out", str(tmp_path), "--outputs", "stress"]) == 2
    assert "--outputs 'stress'" in capsys.readouterr().err


def test_scene_describes_its_parameters_in_its_units():
    text = CubeScene(maxh=0.5).describe()
    assert "maxh" in text and "0.5" in text and "[mm]" in text and "[MPa]" in text
    assert "outputs" not in text


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


@pytest.mark.parametrize("name", sorted(SCENES))
def test_every_preset_is_a_valid_scene_that_knows_its_name(name):
    cls = SCENES[name]
    assert set(cls.presets) <= set(PRESETS) - {"default"}
    for preset in cls.preset_names():
        scene = cls.from_settings({}, preset=preset)
        assert scene.preset() == preset
        for key, value in cls.preset_settings(preset).items():
            assert scene.settings()[key] == cls.typed_settings({key: value})[key]


def test_explicit_settings_win_over_the_preset():
    cls = SCENES["cube"]
    assert cls.preset_settings("preview")["maxh"] != 0.3
    scene = cls.from_settings({"maxh": "0.3"}, preset="preview")
    assert scene.maxh == 0.3
    assert scene.order == cls.preset_settings("preview")["order"]
    assert scene.preset() == "custom"
    # a parameter no preset sets does not change the name
    assert cls.from_settings({"a": 0.1}, preset="preview").preset() == "preview"


def test_unknown_preset_is_refused_with_the_allowed_names(capsys, tmp_path):
    with pytest.raises(ParameterError, match="preset.*preview"):
        SCENES["cube"].from_settings({}, preset="fastest")
    assert main(["run", "cube", "--out", str(tmp_path / "r"), "--preset", "fastest"]) == 2
    assert "preset" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


def test_run_records_the_preset(tmp_path):
    out = tmp_path / "run"
    code = main(["run", "cube", "--out", str(out), "--preset", "preview", "--outputs",
                 "incompatibility", "-q"])
    assert code == 0
    record = json.loads((out / "results.json").read_text())
    assert record["preset"] == "preview"
    assert record["params"]["maxh"] == SCENES["cube"].preset_settings("preview")["maxh"]


def test_list_shows_each_scenes_presets(capsys):
    assert main(["list", "-v"]) == 0
    text = capsys.readouterr().out
    for cls in SCENES.values():
        for preset in cls.preset_names():
            assert f"--preset {preset}" in text
    assert "--preset preview: maxh=0.5" in text


#: Scenes whose preview runs in seconds; the others' previews take up to a minute each.
QUICK_PREVIEWS = ("cube", "hemisphere", "disc", "cylinder", "custom")


def _run_preset(name, preset, out):
    code = main(["run", name, "--out", str(out), "--preset", preset, "--set", "outputs=none",
                 "-q"])
    record = json.loads((out / "results.json").read_text())
    return code, record


@pytest.mark.parametrize("name", QUICK_PREVIEWS)
def test_preview_runs_converged_on_the_quick_scenes(name, tmp_path):
    """``--preset preview`` from the command line: the run converges, records its preset and
    has the preset's mesh settings."""
    code, record = _run_preset(name, "preview", tmp_path / name)
    assert code == 0 and record["status"] == "done" and record["preset"] == "preview"
    for key, value in SCENES[name].preset_settings("preview").items():
        assert record["params"][key] == value


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(set(SCENES) - set(QUICK_PREVIEWS)))
def test_preview_runs_converged_on_the_coupled_scenes(name, tmp_path):
    """The coupled scenes' previews (up to a minute each on a quiet machine)."""
    code, record = _run_preset(name, "preview", tmp_path / name)
    assert code == 0 and record["status"] == "done" and record["preset"] == "preview"


def test_every_scene_has_a_preview_and_a_paper_preset_finer_than_its_preview():
    """Each scene's presets: preview and paper besides the defaults, the preview's mesh no
    finer and its order no higher than the default's, the paper's mesh no coarser."""
    for name, cls in SCENES.items():
        assert cls.preset_names() == PRESETS, name
        default = cls()
        preview = cls.from_settings({}, preset="preview")
        paper = cls.from_settings({}, preset="paper")
        assert preview.maxh >= default.maxh >= paper.maxh, name
        assert preview.order <= default.order, name


def test_a_duration_may_take_at_most_max_time_steps_steps():
    """t_end / dt <= MAX_TIME_STEPS: at the limit accepted, past it refused naming the step
    and the smallest step allowed."""
    check_time_steps("t_end", 10.0, "dt", 10.0 / MAX_TIME_STEPS)
    with pytest.raises(ParameterError, match=r"^dt = 0\.0009 is out of range: allowed "
                                             r">= t_end / 10000 = 0\.001 \(at most 10000 "):
        check_time_steps("t_end", 10.0, "dt", 0.0009)


def test_the_unknowns_per_element_are_the_nodes_share_times_the_components():
    """Order k: a tetrahedron's k^3 / 6 nodes, a hexahedron's k^3, a triangle's k^2 / 2, times
    3 components (2 on a section in plane strain)."""
    assert UNKNOWNS_PER_ELEMENT["tet"](6) == 108
    assert UNKNOWNS_PER_ELEMENT["hex"](2) == 24
    assert UNKNOWNS_PER_ELEMENT["triangle"](2) == 4


def test_a_mesh_past_max_elements_or_max_dofs_is_refused_before_meshing_naming_maxh():
    """The estimate of the cube's mesh and its unknowns at order 6 against the limits: at each
    limit accepted, one below refused, the message naming the limit to raise."""
    elements, shape = CubeScene(elements="hex", maxh=0.25).mesh_estimate()
    dofs = int(elements * UNKNOWNS_PER_ELEMENT[shape](6))
    settings = dict(elements="hex", maxh=0.25, order=6)
    assert CubeScene(max_elements=int(elements), max_dofs=dofs, **settings).maxh == 0.25
    with pytest.raises(ParameterError, match=r"^maxh = 0\.25 .* about 64 elements at order 6, "
                                             r"more than max_elements = 63 "):
        CubeScene(max_elements=int(elements) - 1, **settings)
    with pytest.raises(ParameterError, match=rf"^maxh = 0\.25 .* unknowns at order 6, more "
                                             rf"than max_dofs = {dofs - 1} \(raise it with "
                                             rf"--set max_dofs=N"):
        CubeScene(max_dofs=dofs - 1, **settings)
    # the quarter model's mesh is a quarter of the full one's
    full, _ = CubeScene().mesh_estimate()
    assert CubeScene(model="quarter").mesh_estimate()[0] == pytest.approx(full / 4)


def test_the_mixed_formulation_counts_its_pressure_and_bubbles_against_max_dofs():
    """The atrophy scene's mixed pair on tetrahedra of order 2 has 4 + 13 unknowns per
    element, the displacement 4: at maxh 0.6 (about 35,000 tetrahedra) the mixed brain
    passes max_dofs = 500,000 and is refused, the displacement formulation's is not."""
    assert AtrophyScene(maxh=0.8).unknowns_per_element("tet") == 17
    assert AtrophyScene(maxh=0.8, formulation="displacement").unknowns_per_element("tet") == 4
    with pytest.raises(ParameterError, match=r"^maxh = 0\.6 .* about 5\.\de\+05 unknowns at "
                                             r"order 2, more than max_dofs = 500000"):
        AtrophyScene(maxh=0.6)
    assert AtrophyScene(maxh=0.6, formulation="displacement").maxh == 0.6


def test_the_mesher_failure_names_the_scenes_lengths_in_its_units():
    text = CubeScene(maxh=0.5).unmeshable(RuntimeError(" surface meshing failed \n"))
    assert text.startswith("the mesher failed on this cube geometry (surface meshing failed): ")
    assert "its lengths are maxh = 0.5, side = 1 (mm)" in text
    assert "a = " not in text           # a gradient, not a length


def test_the_title_names_the_variant():
    assert CubeScene(model="quarter").title() == "cube (model=quarter, formulation=displacement)"
    assert get_scene("atrophy")().title() == "atrophy"


def test_a_scene_without_a_case_says_so():
    @dataclass(frozen=True)
    class Bare(Scene):
        name = "bare"

    with pytest.raises(TypeError, match="Bare must define build"):
        Bare().build()
    assert Bare().resumes("anywhere") is False and Bare().trust(None) == []


def test_the_record_of_a_run_holds_the_scene_its_mesh_and_its_units():
    """An empty record on a 2 x 2 x 2 hexahedral cube: its element and vertex counts, the
    order asked for, the scene's settings and preset, a copy of its units and the unit of
    every metric it declares."""
    scene = CubeScene(maxh=0.5)
    results = scene.record(cube(maxh=0.5), order=2, status="done")
    assert (results.mesh.ne, results.mesh.nv, results.mesh.order, results.mesh.maxh) == (
        8, 27, 2, 0.5)
    assert results.mesh.ndof is None and results.metrics == {}
    assert results.scene == "cube" and results.params == scene.settings()
    assert results.preset == "default" and results.status == "done"
    assert set(results.metric_units) == set(CubeScene.metrics)
    assert results.metric_units["strain_energy"] == "N mm"
    results.units["length"] = "m"
    assert CubeScene.units["length"] == "mm"
    assert scene.record(cube(maxh=0.5)).mesh.order == scene.order
