"""ngincompat.studies.sweep.spec: sweep files parsed and checked up front, ranges, cases."""

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene
from ngincompat.studies.sweep import load_sweep, parse_sweep, spec


def _write(path, text):
    path.write_text(text)
    return path


@pytest.mark.parametrize("text, key", [
    ('scene = "cube"\nvaryy = {nu = [0.3]}', "varyy"),
    ('scene = "sphere"\n[vary]\nnu = [0.3]', "scene"),
    ('[vary]\nnu = [0.3]', "scene"),
    ('scene = "cube"\n[vary]\nnu = []', "vary.nu"),
    ('scene = "cube"\n[vary]\nnu = 0.3', "vary.nu"),
    ('scene = "cube"\n[vary]\npoisson = [0.3]', "vary.poisson"),
    ('scene = "cube"\n[fixed]\nmaxhh = 1.0', "fixed.maxhh"),
    ('scene = "cube"\n[fixed]\nnu = [0.3, 0.4]', "fixed.nu"),
    ('scene = "cube"\n[fixed]\nnu = 0.3\n[vary]\nnu = [0.4]', "vary.nu"),
    ('scene = "cube"\n[zip]\nnu = [0.3, 0.4]\na = [0.1]', "zip.a"),
    ('scene = "cube"\n[vary]\norder = {start = 1, stop = 3, step = 0}', "vary.order.step"),
    ('scene = "cube"\n[vary]\norder = {start = 3, stop = 1, step = 1}', "vary.order"),
    ('scene = "cube"\n[vary]\nnu = {start = 0.1, stop = 0.4, step = 0.1}', "vary.nu.start"),
    ('scene = "cube"\n[vary]\nnu = {start = 0.1, stop = 0.4, count = 3}', "vary.nu.count"),
    ('scene = "cube"\n[vary]\nnu = {start = 0.1, stop = 0.4, num = 0}', "vary.nu.num"),
    ('scene = "cube"\nmetrics = []', "metrics"),
    ('scene = "cube"\nmetrics = ["strain_energy", "nu"]\n[vary]\nnu = [0.3]', "metrics"),
    ('scene = "cube"\nmetrics = ["strain_energy", "strain_energy"]', "twice"),
    ('scene = "cube"\nmetrics = ["strain_enrgy"]', "strain_enrgy"),
    ('scene = "cube"\n[vary\nnu = [0.3]', "not valid TOML"),
])
def test_bad_sweep_files_name_the_key(tmp_path, text, key):
    path = _write(tmp_path / "bad.toml", text)
    with pytest.raises(ParameterError) as info:
        load_sweep(path)
    assert key in str(info.value)


def test_bad_sweep_file_on_the_command_line(tmp_path, capsys):
    path = _write(tmp_path / "bad.toml", 'scene = "cube"\n[zip]\nnu = [0.3, 0.4]\nmu = [1.0]')
    assert main(["sweep", "run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "zip.mu" in err[0]
    assert not (tmp_path / "out").exists()


def test_a_metric_typo_is_an_error_before_any_case_runs(tmp_path, capsys):
    """Exit 2 with one line naming the unknown metric and every metric of the scene; no case
    folder (nor the sweep folder) is made."""
    path = _write(tmp_path / "typo.toml", 'scene = "cube"\nmetrics = ["strain_energy", '
                  '"G_eror_L2_rel"]\n[fixed]\nmaxh = 1.0\n[vary]\nnu = [0.3, 0.4]')
    out = tmp_path / "out"
    assert main(["sweep", "run", str(path), "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'G_eror_L2_rel'" in err[0]
    assert "allowed " + ", ".join(CubeScene.metrics) in err[0]
    assert not out.exists() and list(tmp_path.glob("**/case_*")) == []


def test_ranges_and_products():
    sweep = parse_sweep({"scene": "cube", "fixed": {"maxh": 1.0},
                         "zip": {"mu": [1.0, 2.0], "a": [0.1, 0.2]},
                         "vary": {"order": {"start": 1, "stop": 5, "step": 2},
                                  "nu": {"start": 0.0, "stop": 0.4, "num": 3}}})
    cases = sweep.cases()
    assert len(cases) == 2 * 3 * 3
    assert sweep.varied == ["mu", "a", "order", "nu"]
    assert cases[0].params == {"maxh": 1.0, "mu": 1.0, "a": 0.1, "order": 1, "nu": 0.0}
    assert cases[-1].varied == {"mu": 2.0, "a": 0.2, "order": 5, "nu": 0.4}
    assert {c.varied["order"] for c in cases} == {1, 3, 5}
    # folder names: deterministic, from the index and the parameters
    again = parse_sweep({"scene": "cube", "fixed": {"maxh": 1.0},
                         "zip": {"mu": [1.0, 2.0], "a": [0.1, 0.2]},
                         "vary": {"order": [1, 3, 5], "nu": [0.0, 0.2, 0.4]}}).cases()
    assert [c.name for c in again] == [c.name for c in cases]
    assert cases[4].name.startswith("case_004_") and len({c.name for c in cases}) == 18
    # the record beside the table lists every case with its folder
    record = sweep.record()
    assert record["varied"] == sweep.varied and len(record["cases"]) == 18
    assert record["cases"][4] == {"case": 4, "folder": cases[4].name, "params": cases[4].params}


def test_a_case_builds_its_scene_or_names_the_bad_value():
    good, bad = parse_sweep({"scene": "cube", "vary": {"nu": [0.3, 0.7]}}).cases()
    assert good.build() == CubeScene(nu=0.3)
    with pytest.raises(ParameterError, match="nu = 0.7"):
        bad.build()


@pytest.mark.parametrize("name", ["cube_poisson", "hemisphere_profiles", "disc_fibers"])
def test_example_sweep_files_are_valid(name):
    """The sweep files shipped in examples/ parse and expand to the documented case counts."""
    from pathlib import Path
    path = Path(__file__).resolve().parents[3] / "examples" / "sweeps" / f"{name}.toml"
    sweep = load_sweep(path)
    expected = {"cube_poisson": 10, "hemisphere_profiles": 12, "disc_fibers": 6}[name]
    assert len(sweep.cases()) == expected


def test_settings_for_every_case_join_the_fixed_parameters_and_the_cases_identity():
    """``sweep run --set``: typed like ``run --set``, over the file's [fixed], in every case's
    parameters, folder name and the record (so coarse and fine cases never share a folder)."""
    sweep = parse_sweep({"scene": "cube", "fixed": {"maxh": 0.5, "outputs": "none"},
                         "vary": {"nu": [0.3, 0.4]}})
    coarse = sweep.with_settings({"maxh": "1", "order": "1"})
    assert coarse.fixed == {"maxh": 1.0, "outputs": "none", "order": 1}
    assert [c.params for c in coarse.cases()] == [
        {"maxh": 1.0, "outputs": "none", "order": 1, "nu": nu} for nu in (0.3, 0.4)]
    assert [c.varied for c in coarse.cases()] == [c.varied for c in sweep.cases()]
    assert coarse.cases()[0].build() == CubeScene(maxh=1.0, order=1, nu=0.3, outputs="none")
    names = {c.name for c in sweep.cases()}
    assert names.isdisjoint(c.name for c in coarse.cases())
    assert coarse.record()["fixed"]["maxh"] == 1.0
    assert sweep.fixed == {"maxh": 0.5, "outputs": "none"}      # the sweep itself unchanged
    assert sweep.with_settings({}) == sweep


@pytest.mark.parametrize("settings, words", [
    ({"nu": "0.3"}, ["nu", "[vary]"]),
    ({"a": "0.1"}, ["a", "[zip]"]),
    ({"maxhh": "1"}, ["maxhh", "allowed"]),
    ({"maxh": "fine"}, ["maxh", "'fine'", "float"]),
    ({"order": "2.5"}, ["order", "int"]),
])
def test_settings_for_every_case_refuse_a_varied_or_bad_parameter(settings, words):
    sweep = parse_sweep({"scene": "cube", "zip": {"a": [0.1, 0.2], "mu": [1.0, 2.0]},
                         "vary": {"nu": [0.3, 0.4]}})
    with pytest.raises(ParameterError) as info:
        sweep.with_settings(settings)
    assert all(word in str(info.value) for word in words), str(info.value)


def test_a_varied_parameter_set_on_the_command_line_is_one_line_before_any_case(tmp_path,
                                                                                 capsys):
    path = _write(tmp_path / "sweep.toml", 'scene = "cube"\n[vary]\nnu = [0.3, 0.4]')
    out = tmp_path / "out"
    assert main(["sweep", "run", str(path), "--out", str(out), "--set", "maxh=1",
                 "--set", "nu=0.3"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "nu cannot be set for every case" in err[0]
    assert "[vary] nu = [0.3, 0.4]" in err[0]
    assert not out.exists()


# --- bounded plans -------------------------------------------------------------------------

def _sweep(vary):
    return {"scene": "cube", "fixed": {"maxh": 1.0, "order": 1}, "vary": vary}


@pytest.mark.parametrize("vary, what", [
    ({"nu": {"start": 0.1, "stop": 0.4, "num": 10 ** 12}}, "num"),
    ({"steps": {"start": 1, "stop": 10 ** 12, "step": 1}}, "values"),
    ({"mu": [1.0] * 1000, "nu": [0.3] * 1000, "a": [0.1] * 1000}, r"1e\+09 cases"),
])
def test_a_sweep_plan_is_bounded_before_anything_is_allocated(vary, what, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("allocated the plan")

    monkeypatch.setattr(spec.np, "linspace", never)
    monkeypatch.setattr(spec.itertools, "product", never)
    with pytest.raises(ParameterError, match=what) as info:
        spec.parse_sweep(_sweep(vary))
    assert "\n" not in str(info.value) and str(spec.MAX_CASES) in str(info.value)
