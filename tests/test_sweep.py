"""Parameter sweeps: failures as rows, resume, re-runs, Dask, bad sweep files, the plot.

Every case is the cube at order 1 or 2 on one hexahedron (maxh = 1) without output files, a
fraction of a second; most of the time goes into starting the worker processes.
"""

import json
import shutil
import sys
from pathlib import Path

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.sweep import load_sweep, parse_sweep, read_table, run_sweep

# six cases: (nu, a) zipped, the last nu out of range (its case fails in the scene)
FAILING = """
scene = "cube"
metrics = ["strain_energy", "G_error_L2_rel"]

[fixed]
maxh = 1.0
outputs = "none"

[zip]
nu = [0.2, 0.3, 0.4, 0.45, 0.49, 0.7]
a = {start = 0.1, stop = 0.35, num = 6}

[vary]
order = [1]
"""

# six cases, all fine: order x nu
PRODUCT = """
scene = "cube"

[fixed]
maxh = 1.0
outputs = "none"

[vary]
order = {start = 1, stop = 2, step = 1}
nu = {start = 0.3, stop = 0.45, num = 3}
"""


def _write(path, text):
    path.write_text(text)
    return path


def _mtimes(out):
    return {p.parent.name: p.stat().st_mtime_ns for p in Path(out).glob("case_*/results.json")}


def _without_seconds(rows):
    return [{k: v for k, v in row.items() if k != "seconds"} for row in rows]


@pytest.fixture(scope="module")
def failing(tmp_path_factory):
    root = tmp_path_factory.mktemp("failing")
    sweep = load_sweep(_write(root / "failing.toml", FAILING))
    report = run_sweep(sweep, root / "out", workers=2, quiet=True)
    return sweep, report


@pytest.fixture(scope="module")
def resumed(tmp_path_factory):
    """The product sweep stopped after three cases, then resumed."""
    root = tmp_path_factory.mktemp("resumed")
    sweep = load_sweep(_write(root / "product.toml", PRODUCT))
    out = root / "out"
    first = run_sweep(sweep, out, workers=1, quiet=True, max_cases=3)
    before = _mtimes(out)
    first_table = read_table(out)
    second = run_sweep(sweep, out, resume=True, quiet=True)
    return sweep, out, first, first_table, before, second


def test_a_failing_case_is_a_row_and_the_others_go_on(failing):
    sweep, report = failing
    assert report.columns == ["case", "status", "nu", "a", "order", "strain_energy",
                              "G_error_L2_rel", "seconds", "error"]
    assert report.computed == 6 and report.reused == 0 and report.pending == 0
    assert [row["case"] for row in report.rows] == list(range(6))
    ok = [row for row in report.rows if row["status"] == "ok"]
    failed = [row for row in report.rows if row["status"] == "failed"]
    assert len(ok) == 5 and len(failed) == 1
    assert failed[0]["nu"] == 0.7 and failed[0]["a"] == pytest.approx(0.35)
    assert "nu = 0.7" in failed[0]["error"] and "ParameterError" in failed[0]["error"]
    assert failed[0]["strain_energy"] is None
    assert (report.out / f"case_005_{sweep.cases()[5].key}" / "error.txt").is_file()
    for row in ok:
        assert row["error"] is None and row["seconds"] > 0
        assert row["strain_energy"] > 0 and row["G_error_L2_rel"] < 1e-6
    # zipped: nu and a move together; a from the linspace range
    assert [row["a"] for row in report.rows] == pytest.approx([0.1, 0.15, 0.2, 0.25, 0.3, 0.35])
    # the table on disk is the report's table
    columns, rows = read_table(report.out)
    assert columns == report.columns
    assert [r["status"] for r in rows] == ["ok"] * 5 + ["failed"]
    assert rows[5]["error"] == failed[0]["error"]
    assert [r["strain_energy"] for r in rows[:5]] == [r["strain_energy"] for r in ok]
    # each case folder holds its own results.json, with the parameters of its row
    for case, row in zip(sweep.cases()[:5], rows[:5], strict=True):
        results = json.loads((report.out / case.name / "results.json").read_text())
        assert results["params"]["nu"] == row["nu"] and results["params"]["order"] == 1
        assert results["metrics"]["strain_energy"] == row["strain_energy"]


def test_parquet_table_matches_csv(failing):
    pq = pytest.importorskip("pyarrow.parquet")
    _, report = failing
    table = pq.read_table(report.out / "sweep.parquet").to_pylist()
    assert [r["status"] for r in table] == [r["status"] for r in report.rows]
    assert [r["strain_energy"] for r in table] == [r["strain_energy"] for r in report.rows]


def test_interrupted_sweep_resumes_without_recomputing(resumed):
    sweep, out, first, first_table, before, second = resumed
    assert first.computed == 3 and first.pending == 3
    assert len(first_table[1]) == 3 and len(before) == 3
    assert second.computed == 3 and second.reused == 3 and second.pending == 0
    assert second.ok == 6 and second.failed == 0
    after = _mtimes(out)
    assert len(after) == 6
    assert {name: after[name] for name in before} == before   # the first three untouched
    # the rows of the first three are rebuilt from their results.json, unchanged
    assert _without_seconds(second.rows[:3]) == _without_seconds(first.rows)
    assert [(r["order"], r["nu"]) for r in second.rows] == \
        [(o, nu) for o in (1, 2) for nu in (0.3, 0.375, 0.45)]
    # default metrics: every metric of results.json
    assert {"strain_energy", "G_error_L2_rel", "burgers_max"} <= set(second.columns)


def test_rerunning_a_finished_sweep_recomputes_nothing(resumed, failing):
    sweep, out, *_ = resumed
    before = _mtimes(out)
    table = (out / "sweep.csv").read_bytes()
    again = run_sweep(sweep, out, quiet=True)
    assert again.computed == 0 and again.reused == 6
    assert _mtimes(out) == before
    assert (out / "sweep.csv").read_bytes() == table
    # through the command line too
    assert main(["sweep", "run", str(out.parent / "product.toml"), "--out", str(out),
                 "-q"]) == 0
    assert _mtimes(out) == before
    # a failed case is retried, the finished ones are not
    sweep, report = failing
    before = _mtimes(report.out)
    again = run_sweep(sweep, report.out, quiet=True)
    assert again.computed == 1 and again.reused == 5 and again.failed == 1
    assert _mtimes(report.out) == before
    assert _without_seconds(again.rows) == _without_seconds(report.rows)


def test_a_case_is_done_only_with_complete_matching_results(resumed, tmp_path):
    """A results.json with an error (a ConvergenceError writes one), of other parameters, or
    none at all: the case is to be run again. ``max_cases=0`` counts without running."""
    sweep, out, *_ = resumed
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    cases = sweep.cases()
    path = copy / cases[0].name / "results.json"
    results = json.loads(path.read_text())
    path.write_text(json.dumps({**results, "error": "Newton did not converge"}))
    path = copy / cases[1].name / "results.json"
    path.write_text(json.dumps({**results, "params": {**results["params"], "nu": 0.1}}))
    (copy / cases[2].name / "results.json").unlink()
    report = run_sweep(sweep, copy, max_cases=0)
    assert report.computed == 0 and report.reused == 3 and report.pending == 3
    assert [row["case"] for row in report.rows] == [3, 4, 5]
    assert [row["case"] for row in read_table(copy)[1]] == [3, 4, 5]


def test_scheduler_without_dask_is_a_parameter_error(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "dask", None)
    sweep = parse_sweep({"scene": "cube", "vary": {"nu": [0.3]}})
    with pytest.raises(ParameterError, match="dask"):
        run_sweep(sweep, tmp_path / "out", scheduler="tcp://127.0.0.1:8786")


def test_another_sweep_in_the_same_folder_needs_resume(tmp_path):
    out = tmp_path / "out"
    run_sweep(parse_sweep({"scene": "cube", "vary": {"nu": [0.3, 0.4]}}), out, max_cases=0)
    assert (out / "sweep.json").is_file()
    changed = parse_sweep({"scene": "cube", "vary": {"nu": [0.3, 0.45]}})
    with pytest.raises(ParameterError, match="--resume"):
        run_sweep(changed, out, max_cases=0)
    report = run_sweep(changed, out, max_cases=0, resume=True)
    assert report.computed == 0 and report.pending == 2


def test_dask_cluster_gives_the_same_table(failing, tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    sweep, local = failing
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        report = run_sweep(sweep, tmp_path / "out", scheduler=cluster.scheduler_address,
                           quiet=True)
    assert report.computed == 6
    assert report.columns == local.columns
    assert [r["status"] for r in report.rows] == ["ok"] * 5 + ["failed"]
    dask_rows, local_rows = _without_seconds(report.rows), _without_seconds(local.rows)
    for d, loc in zip(dask_rows, local_rows, strict=True):
        assert d.keys() == loc.keys()
        for key, value in loc.items():
            assert d[key] == (pytest.approx(value, rel=1e-9) if isinstance(value, float)
                              else value), key


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


def test_sweep_plot_writes_a_png(resumed, tmp_path, capsys):
    _, out, *_ = resumed
    png = tmp_path / "energy.png"
    code = main(["sweep", "plot", str(out), "--metric", "strain_energy", "--x", "nu",
                 "--hue", "order", "--logy", "--out", str(png)])
    assert code == 0
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    # without --hue the two orders share every nu: refused, naming what varies
    code = main(["sweep", "plot", str(out), "--metric", "strain_energy", "--x", "nu",
                 "--out", str(tmp_path / "bad.png")])
    assert code == 2 and "order" in capsys.readouterr().err
    # ... unless --where fixes it
    code = main(["sweep", "plot", str(out), "--metric", "strain_energy", "--x", "nu",
                 "--where", "order=2", "--out", str(tmp_path / "one.png")])
    assert code == 0 and (tmp_path / "one.png").is_file()
    code = main(["sweep", "plot", str(out), "--metric", "energy", "--x", "nu",
                 "--out", str(tmp_path / "bad.png")])
    assert code == 2 and "energy" in capsys.readouterr().err
    assert not (tmp_path / "bad.png").exists()


@pytest.mark.parametrize("name", ["cube_poisson", "hemisphere_profiles", "disc_fibers"])
def test_example_sweep_files_are_valid(name):
    """The sweep files shipped in examples/ parse and expand to the documented case counts."""
    from pathlib import Path
    path = Path(__file__).parent.parent / "examples" / "sweeps" / f"{name}.toml"
    sweep = load_sweep(path)
    expected = {"cube_poisson": 10, "hemisphere_profiles": 12, "disc_fibers": 6}[name]
    assert len(sweep.cases()) == expected
