"""ngincompat.studies.sweep.runner: failures as rows, resume, re-runs, Dask, exit codes."""

# Every case is the cube at order 1 or 2 on one hexahedron (maxh = 1) without output files, a
# fraction of a second; most of the time goes into starting the worker processes.

import concurrent.futures
import json
import os
import shutil
import sys
import time
from pathlib import Path

import pytest
from conftest import local_dask_cluster

from ngincompat.cli import main
from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.studies import corpus
from ngincompat.studies import sweep as sweep_pkg
from ngincompat.studies.sweep import (
    load_sweep,
    parse_sweep,
    read_table,
    run_case,
    run_sweep,
    runner,
    spec,
    table,
)
from ngincompat.studies.workers import interrupted
from ngincompat.workflow import output
from ngincompat.workflow.results import MeshInfo, Results

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
    report = run_sweep(sweep, root / "out", workers=2)
    return sweep, report


@pytest.fixture(scope="module")
def resumed(tmp_path_factory):
    """The product sweep stopped after three cases, then resumed."""
    root = tmp_path_factory.mktemp("resumed")
    sweep = load_sweep(_write(root / "product.toml", PRODUCT))
    out = root / "out"
    first = run_sweep(sweep, out, workers=1, max_cases=3)
    before = _mtimes(out)
    first_table = read_table(out)
    second = run_sweep(sweep, out, resume=True)
    return sweep, out, first, first_table, before, second


def test_a_failing_case_is_a_row_and_the_others_go_on(failing):
    sweep, report = failing
    assert report.columns == ["case", "status", "warnings", "nu", "a", "order", "strain_energy",
                              "G_error_L2_rel", "seconds", "error"]
    assert report.computed == 6 and report.reused == 0 and report.pending == 0
    assert [row["case"] for row in report.rows] == list(range(6))
    done = [row for row in report.rows if row["status"] == "done"]
    failed = [row for row in report.rows if row["status"] == "failed"]
    assert len(done) == 5 and len(failed) == 1
    assert report.done == 5 and report.failed == 1
    assert failed[0]["nu"] == 0.7 and failed[0]["a"] == pytest.approx(0.35)
    assert "nu = 0.7" in failed[0]["error"] and "ParameterError" in failed[0]["error"]
    assert failed[0]["strain_energy"] is None
    assert (report.out / f"case_005_{sweep.cases()[5].key}" / "error.txt").is_file()
    for row in done:
        assert row["error"] is None and row["seconds"] > 0
        assert row["strain_energy"] > 0 and row["G_error_L2_rel"] < 1e-6
    # zipped: nu and a move together; a from the linspace range
    assert [row["a"] for row in report.rows] == pytest.approx([0.1, 0.15, 0.2, 0.25, 0.3, 0.35])
    # the table on disk is the report's table, with units
    table = read_table(report.out)
    assert table.columns == report.columns
    assert table.units == {"a": "1/mm", "strain_energy": "N mm", "G_error_L2_rel": "-",
                           "seconds": "s"}
    assert [r["status"] for r in table.rows] == ["done"] * 5 + ["failed"]
    assert table.rows[5]["error"] == failed[0]["error"]
    assert [r["strain_energy"] for r in table.rows[:5]] == [r["strain_energy"] for r in done]
    header = (report.out / "sweep.csv").read_text().splitlines()[0]
    assert header == ("case,status,warnings,nu,a [1/mm],order,strain_energy [N mm],"
                      "G_error_L2_rel [-],seconds [s],error")
    # each case folder holds its own results.json, with the parameters of its row
    for case, row in zip(sweep.cases()[:5], table.rows[:5], strict=True):
        results = output.read(report.out / case.name)
        assert results.params["nu"] == row["nu"] and results.params["order"] == 1
        assert results.metrics["strain_energy"] == row["strain_energy"]


def test_interrupted_sweep_resumes_without_recomputing(resumed):
    sweep, out, first, first_table, before, second = resumed
    assert first.computed == 3 and first.pending == 3
    assert len(first_table.rows) == 3 and len(before) == 3
    assert second.computed == 3 and second.reused == 3 and second.pending == 0
    assert second.done == 6 and second.failed == 0
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
    again = run_sweep(sweep, out)
    assert again.computed == 0 and again.reused == 6
    assert _mtimes(out) == before
    assert (out / "sweep.csv").read_bytes() == table
    # through the command line too
    assert main(["sweep", "run", str(out.parent / "product.toml"), "--out", str(out),
                 "-q"]) == 0
    assert _mtimes(out) == before
    # a failed case is tried again, the finished ones are not
    sweep, report = failing
    before = _mtimes(report.out)
    again = run_sweep(sweep, report.out)
    assert again.computed == 1 and again.reused == 5 and again.failed == 1
    assert _mtimes(report.out) == before
    assert _without_seconds(again.rows) == _without_seconds(report.rows)


def test_a_case_is_done_only_with_complete_matching_results(resumed, tmp_path):
    """A results.json that is not "done" (a ConvergenceError writes "not converged"), of other
    parameters, or none at all: the case is to be run again. ``max_cases=0`` counts without
    running."""
    sweep, out, *_ = resumed
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    cases = sweep.cases()
    path = copy / cases[0].name / "results.json"
    results = json.loads(path.read_text())
    path.write_text(json.dumps({**results, "status": "not converged",
                                "error": "growth: Newton did not converge"}))
    path = copy / cases[1].name / "results.json"
    path.write_text(json.dumps({**results, "params": {**results["params"], "nu": 0.1}}))
    (copy / cases[2].name / "results.json").unlink()
    report = run_sweep(sweep, copy, max_cases=0)
    assert report.computed == 0 and report.reused == 3 and report.pending == 3
    assert [row["case"] for row in report.rows] == [3, 4, 5]
    assert [row["case"] for row in read_table(copy).rows] == [3, 4, 5]


def test_a_case_that_does_not_converge_keeps_its_last_converged_metrics(tmp_path):
    """The row of a ConvergenceError: status "not converged", the metrics measured in the
    last converged state, and the reason; no error.txt (results.json records it)."""
    class Diverging:
        def run(self, out, overwrite, progress, label):
            err = ConvergenceError("growth: step below min_step at t = 0.5")
            err.results = Results(scene="cube", params={}, units={},
                                  mesh=MeshInfo(ne=1, nv=8, order=1, maxh=1.0),
                                  status="not converged", timings={"growth": 0.5},
                                  metrics={"strain_energy": 1e-8})
            raise err

    outcome = run_case({"scene": Diverging(), "folder": str(tmp_path / "case"),
                        "threads": None, "quiet": True})
    assert outcome == {"status": "not converged", "warnings": 0,
                       "metrics": {"strain_energy": 1e-8},
                       "seconds": 0.5,
                       "error": "ConvergenceError: growth: step below min_step at t = 0.5"}
    assert not (tmp_path / "case" / "error.txt").exists()


def test_failed_cases_make_the_command_line_exit_4(tmp_path, capfd):
    """The table is complete (the good case done, the bad one a row with its error)."""
    path = _write(tmp_path / "sweep.toml", 'scene = "cube"\nmetrics = ["strain_energy"]\n'
                  '[fixed]\nmaxh = 1.0\norder = 1\noutputs = "none"\n[vary]\nnu = [0.3, 0.7]')
    out = tmp_path / "out"
    assert main(["sweep", "run", str(path), "--out", str(out), "--workers", "1"]) == 4
    captured = capfd.readouterr()
    assert "2 cases: 1 done, 1 failed" in captured.out
    assert ("| case | status | warnings | nu | strain_energy [N mm] | seconds [s] |"
            in captured.out)
    assert "case 1: ParameterError: nu = 0.7" in captured.out
    # progress on stderr: the sweep's lines, and the case's stages from its worker
    assert "case_001_" in captured.err and "(nu=0.7): failed (ParameterError" in captured.err
    assert "] growth: t = 1/1" in captured.err
    rows = read_table(out).rows
    assert [r["status"] for r in rows] == ["done", "failed"]
    assert rows[0]["strain_energy"] > 0


#: The command line, run with Ctrl-C's default handler whatever this process inherited.
AS_FROM_A_TERMINAL = corpus.ALONE


@pytest.mark.parametrize("when, delay, most_done",
                         [("1 of 8 finished", 0, 3), ("local pool", 0.3, 0)],
                         ids=["after-a-case", "while-workers-import"])
def test_ctrl_c_ends_a_sweep_with_130_finished_rows_kept_the_rest_interrupted(
        tmp_path, when, delay, most_done):
    """A terminal's Ctrl-C (SIGINT to the process group) once the first case has finished, or
    as soon as the pool starts: exit 130; the table has every case, those that finished with
    their results, the others "interrupted" (a case that was running says so in its
    results.json too); no worker prints a traceback, whether running a case, waiting for one
    or still importing (a worker hit while importing printed its KeyboardInterrupt; the
    workers take about a second to import, hence the signal 0.3 s after the pool starts)."""
    import signal
    import subprocess

    path = _write(tmp_path / "sweep.toml", 'scene = "cube"\nmetrics = ["strain_energy"]\n'
                  '[fixed]\nmaxh = 0.5\norder = 3\noutputs = "none"\n'
                  '[vary]\nnu = [0.30, 0.32, 0.34, 0.36, 0.38, 0.40, 0.42, 0.44]')
    out = tmp_path / "out"
    # as from a terminal, whose commands take SIGINT even where this test runs with it
    # ignored (pytest started in the background of a script: the CLI keeps it ignored then)
    process = subprocess.Popen([sys.executable, "-c", AS_FROM_A_TERMINAL, "sweep", "run",
                                str(path), "--out", str(out), "--workers", "2"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    lines = []
    for line in process.stderr:
        lines.append(line)
        if when in line:
            time.sleep(delay)
            os.killpg(process.pid, signal.SIGINT)
            break
    _, rest = process.communicate(timeout=300)
    err = "".join(lines) + rest
    assert process.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    rows = read_table(out).rows
    assert [r["case"] for r in rows] == list(range(8)), (rows, err)
    statuses = [r["status"] for r in rows]
    assert "interrupted" in statuses and set(statuses) <= {"done", "interrupted"}, \
        ([(r["status"], r["error"]) for r in rows], err)
    assert statuses.count("done") <= most_done, (statuses, err)
    cases = load_sweep(path).cases()
    for row, case in zip(rows, cases, strict=True):
        folder = out / case.name
        if row["status"] == "done":
            assert row["strain_energy"] > 0
            assert output.read(folder).status == "done"
        else:
            assert row["strain_energy"] is None and "interrupted" in row["error"]
            if (folder / "results.json").is_file():     # the row is what the run wrote
                assert output.read(folder).status == "interrupted", row
    assert not (out / ".ngincompat.lock").exists()


@pytest.mark.parametrize("to_the_group", [True, False],
                         ids=["ctrl-c-to-the-group", "sigterm-to-the-sweep-alone"])
def test_ctrl_c_while_the_workers_mesh_stops_their_meshers_within_seconds(tmp_path,
                                                                          to_the_group):
    """A sweep of 1000 mm cylinders, each a minute of meshing (Netgen kept the workers'
    Ctrl-C waiting until the mesh was done): Ctrl-C as both workers mesh ends the sweep with
    130, every row "interrupted", no traceback and no lock, and the sweep's processes
    together use far less CPU than one mesh (their imports and a second of meshing each).
    So does a SIGTERM to the sweep's process alone (a batch system that signals the job's
    leader), which the pool passes on to its workers."""
    import resource
    import signal
    import subprocess

    path = _write(tmp_path / "sweep.toml", 'scene = "cylinder"\nmetrics = ["rotation_rate"]\n'
                  '[fixed]\nlength = 1000\nmaxh = 0.5\norder = 2\nmax_dofs = 2000000\n'
                  'outputs = "none"\n'
                  '[vary]\nnu = [0.3, 0.4]')
    out = tmp_path / "out"
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    process = subprocess.Popen([sys.executable, "-c", AS_FROM_A_TERMINAL, "sweep", "run",
                                str(path), "--out", str(out), "--workers", "2"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    lines, meshing = [], 0
    for line in process.stderr:
        lines.append(line)
        meshing += "meshing ..." in line
        if meshing == 2:
            time.sleep(1.0)                 # well into both meshers
            if to_the_group:
                os.killpg(process.pid, signal.SIGINT)
            else:
                os.kill(process.pid, signal.SIGTERM)
            break
    _, rest = process.communicate(timeout=600)
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = used.ru_utime + used.ru_stime - children.ru_utime - children.ru_stime
    err = "".join(lines) + rest
    assert process.returncode == 130, err
    assert "Traceback" not in err
    assert [r["status"] for r in read_table(out).rows] == ["interrupted"] * 2
    assert cpu < 30.0, cpu
    assert not (out / ".ngincompat.lock").exists()


class _EndsAsTheSignalArrives:
    """A pool of one worker, in this process, on which the race of a Ctrl-C is forced: the
    first case runs to its end and writes its results.json, and then the Ctrl-C reaches the
    sweep before the pool has told it of the end. ``told``: what the pool then says of that
    case: nothing ("not yet"), or "interrupted" (the worker was hit just after the write)."""

    window = 1
    told = "not yet"

    def __init__(self, workers, threads, progress):
        pass

    def submit(self, task):
        run_case(task)
        future = concurrent.futures.Future()
        if self.told == "interrupted":
            future.set_result(interrupted(None))
        return future

    def wait(self, futures):
        raise KeyboardInterrupt

    def close(self, cancel):
        pass


@pytest.mark.parametrize("told", ["not yet", "interrupted"])
def test_a_case_that_ends_as_the_sweep_is_interrupted_is_a_done_row(tmp_path, monkeypatch,
                                                                    told):
    """The forced race of a sweep stopped by Ctrl-C: a case finishes right after the signal.
    Its row is what its folder holds (done, with its metrics), whatever the pool said; the
    case that never started is "interrupted"; the journal is gone."""
    from ngincompat.studies.sweep import runner

    monkeypatch.setattr(_EndsAsTheSignalArrives, "told", told)
    monkeypatch.setattr(runner, "LocalPool", _EndsAsTheSignalArrives)
    sweep = parse_sweep({"scene": "cube", "metrics": ["strain_energy"],
                         "fixed": {"maxh": 1.0, "order": 1, "outputs": "none"},
                         "vary": {"nu": [0.3, 0.4]}})
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_sweep(sweep, out)
    first, second = read_table(out).rows
    record = output.read(out / sweep.cases()[0].name)
    assert record.status == "done"
    assert first["status"] == "done" and first["error"] is None
    assert first["strain_energy"] == pytest.approx(record.metrics["strain_energy"], rel=1e-12)
    assert second["status"] == "interrupted" and second["strain_energy"] is None
    assert not (out / sweep.cases()[1].name / "results.json").exists()
    assert not list(out.glob("*.journal.jsonl"))


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


def test_a_sweep_with_settings_for_every_case_never_mixes_with_the_sweep_without(tmp_path):
    """A folder of the coarse sweep (``--set order=1``): the sweep as the file has it is
    another sweep (refused without resume), and resuming takes over none of the coarse
    cases; the other way round likewise."""
    sweep = parse_sweep({"scene": "cube", "fixed": {"maxh": 1.0, "outputs": "none"},
                         "vary": {"nu": [0.3]}})
    coarse = sweep.with_settings({"order": "1"})
    out = tmp_path / "out"
    first = run_sweep(coarse, out, workers=1)
    assert first.done == 1 and read_table(out).rows[0]["status"] == "done"
    assert output.read(out / coarse.cases()[0].name).params["order"] == 1
    with pytest.raises(ParameterError, match="--resume"):
        run_sweep(sweep, out, max_cases=0)
    fine = run_sweep(sweep, out, max_cases=0, resume=True)
    assert (fine.reused, fine.computed, fine.pending) == (0, 0, 1)
    again = run_sweep(coarse, out, max_cases=0, resume=True)
    assert (again.reused, again.pending, again.done) == (1, 0, 1)


def test_a_folder_holding_a_run_is_refused(tmp_path):
    out = tmp_path / "run"
    out.mkdir()
    (out / "results.json").write_text("{}")
    with pytest.raises(ParameterError, match="holds another run"):
        run_sweep(parse_sweep({"scene": "cube", "vary": {"nu": [0.3]}}), out, max_cases=0)


def test_dask_cluster_gives_the_same_table(failing, tmp_path):
    sweep, local = failing
    environment = dict(os.environ)
    with local_dask_cluster() as cluster:
        assert dict(os.environ) == environment    # the nanny's settings do not leak
        report = run_sweep(sweep, tmp_path / "out", scheduler=cluster.scheduler_address)
    assert report.computed == 6
    assert report.columns == local.columns
    assert [r["status"] for r in report.rows] == ["done"] * 5 + ["failed"]
    dask_rows, local_rows = _without_seconds(report.rows), _without_seconds(local.rows)
    for d, loc in zip(dask_rows, local_rows, strict=True):
        assert d.keys() == loc.keys()
        for key, value in loc.items():
            assert d[key] == (pytest.approx(value, rel=1e-9) if isinstance(value, float)
                              else value), key


def _sweep(vary):
    return {"scene": "cube", "fixed": {"maxh": 1.0, "order": 1}, "vary": vary}


def test_the_table_costs_the_same_per_finished_case_however_many_cases(tmp_path,
                                                                       monkeypatch):
    """Rejected cases go through the same bookkeeping as run ones without running: the
    table is written a fixed number of times and each case adds one journal line of the
    same size, whether the sweep has 10 or 200 cases."""
    writes, appended = [], []
    real_write = table.write_table

    def counting_write(out, tbl, record):
        writes.append(len(tbl.rows))
        return real_write(out, tbl, record)

    real_open = open

    def watching_open(path, mode="r", *args, **kwargs):
        stream = real_open(path, mode, *args, **kwargs)
        if str(path).endswith(table.JOURNAL):
            write = stream.write
            stream.write = lambda text: appended.append(len(text)) or write(text)
        return stream

    monkeypatch.setattr(runner, "write_table", counting_write)
    monkeypatch.setattr(runner, "open", watching_open, raising=False)
    per_case = {}
    for n in (10, 200):
        writes.clear(), appended.clear()
        sweep = spec.parse_sweep(_sweep({"mu": [-1.0 - k / 1000 for k in range(n)]}))
        report = sweep_pkg.run_sweep(sweep, tmp_path / f"s{n}", workers=1)
        assert len(report.table.rows) == n and len(writes) == 2
        assert len(appended) == n
        per_case[n] = max(appended)
        assert not (tmp_path / f"s{n}" / table.JOURNAL).exists()
        rows = json.loads((tmp_path / f"s{n}" / table.RECORD).read_text())["rows"]
        assert len(rows) == n
    # the same line whatever the number of cases (a longer index and value at most); the
    # whole table of 200 rows, as written before, is 200 times one
    assert per_case[200] < 1.5 * per_case[10]
