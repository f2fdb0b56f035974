"""Named presets (``--preset``): every scene's are valid settings, applied under the explicit
ones, recognised in the results, and refused by name when unknown."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.parameters import PRESETS
from ngincompat.scenes import SCENES


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
