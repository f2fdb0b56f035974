"""The scene pipeline: stages walked in order, failures and interruptions recorded, results
measured, written only when asked."""

import json
import math

import pytest

from ngincompat.errors import ConvergenceError, Interrupted
from ngincompat.fem.solver import SolverHistory
from ngincompat.workflow import pipeline
from ngincompat.workflow.results import DONE, INTERRUPTED, NOT_CONVERGED, MeshInfo, Results


class FakeStage:
    """A stage that converges, fails (ConvergenceError) or is interrupted, and logs its run."""

    def __init__(self, name, log, outcome="converge"):
        self.name, self.log, self.outcome = name, log, outcome

    def run(self, progress):
        self.log.append(self.name)
        history = SolverHistory(converged=self.outcome == "converge", t_reached=0.5)
        if self.outcome == "fail":
            raise ConvergenceError("step below min_step", history=history, t_converged=0.5)
        if self.outcome == "interrupt":
            raise Interrupted("Ctrl-C", history=history, t_converged=0.5)
        if self.outcome == "keyboard":
            raise KeyboardInterrupt
        return history


def test_stages_run_in_order_and_after_follows_each_converged_stage():
    log, after = [], []
    stages = [FakeStage(n, log) for n in ("inflation", "hold", "deflation")]
    solution = pipeline.solve_stages(stages, after=lambda stage: after.append(stage.name))
    assert log == after == ["inflation", "hold", "deflation"]
    assert solution.status == DONE and solution.converged and solution.error is None
    assert list(solution.histories) == log and set(solution.timings) == set(log)


@pytest.mark.parametrize("outcome, status", [("fail", NOT_CONVERGED),
                                             ("interrupt", INTERRUPTED)])
def test_a_stage_that_stops_ends_the_walk_and_keeps_its_history(outcome, status):
    log, after = [], []
    stages = [FakeStage("inflation", log), FakeStage("hold", log, outcome),
              FakeStage("deflation", log)]
    solution = pipeline.solve_stages(stages, after=lambda stage: after.append(stage.name))
    assert log == ["inflation", "hold"] and after == ["inflation"]
    assert solution.status == status and not solution.converged
    assert solution.error.startswith("hold: ")
    assert solution.histories["hold"].t_reached == 0.5


class FakeCase:
    def __init__(self, stages, extra=None):
        self.stages = stages
        self.extra = extra or {}

    def solve(self, solution, progress, workdir):
        pipeline.solve_stages(self.stages, progress, solution)

    def _results(self, solution, status):
        return Results(scene="fake", params={}, units={"length": "mm"},
                       mesh=MeshInfo(ne=1, nv=4, order=1, maxh=1.0), status=status,
                       error=solution.error, solver=dict(solution.histories))

    def interrupted(self, solution):
        return self._results(solution, INTERRUPTED)

    def measure(self, solution, progress):
        results = self._results(solution, solution.status)
        results.metrics = {"strain_energy": 1.5, **self.extra}
        return results


class FakeScene:
    name = "fake"

    def __init__(self, *outcomes, extra=None):
        self.log = []
        self.outcomes = outcomes
        self.extra = extra

    def build(self):
        return FakeCase([FakeStage(f"stage{i}", self.log, outcome)
                         for i, outcome in enumerate(self.outcomes)], self.extra)

    def resumes(self, out):
        return False


def test_run_without_a_folder_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    results = pipeline.run(FakeScene("converge", "converge"))
    assert results.status == DONE and results.metrics == {"strain_energy": 1.5}
    assert set(results.timings) >= {"mesh", "stage0", "stage1"}
    assert list(tmp_path.iterdir()) == []


def test_a_stage_that_does_not_converge_is_measured_written_and_raised(tmp_path):
    with pytest.raises(ConvergenceError) as err:
        pipeline.run(FakeScene("converge", "fail", "converge"), tmp_path / "run")
    results = err.value.results
    assert results.status == NOT_CONVERGED and results.metrics == {"strain_energy": 1.5}
    written = json.loads((tmp_path / "run" / "results.json").read_text())
    assert written["status"] == NOT_CONVERGED and written["metrics"] == results.metrics
    assert written["error"].startswith("stage1: step below min_step")


@pytest.mark.parametrize("value", [math.inf, -math.inf, math.nan])
def test_a_metric_that_is_not_finite_fails_a_converged_run(tmp_path, value):
    """Every stage converged, but a metric overflowed: not "done" (exit 3), the metric null in
    results.json and named in the error."""
    with pytest.raises(ConvergenceError) as err:
        pipeline.run(FakeScene("converge", extra={"burgers_max": value}), tmp_path / "run")
    assert err.value.results.status == NOT_CONVERGED
    written = json.loads((tmp_path / "run" / "results.json").read_text())
    assert written["status"] == NOT_CONVERGED and written["metrics"]["burgers_max"] is None
    assert "burgers_max" in written["error"] and written["metrics"]["strain_energy"] == 1.5


def test_a_metric_that_is_not_finite_is_named_after_a_stage_that_did_not_converge(tmp_path):
    with pytest.raises(ConvergenceError) as err:
        pipeline.run(FakeScene("converge", "fail", extra={"burgers_max": math.inf}),
                     tmp_path / "run")
    written = json.loads((tmp_path / "run" / "results.json").read_text())
    assert written["error"].startswith("stage1: step below min_step")
    assert "metrics not finite: burgers_max" in written["error"]
    assert str(err.value) == written["error"]


@pytest.mark.parametrize("outcome", ["interrupt", "keyboard"])
def test_an_interrupted_run_is_marked_and_keeps_its_history(tmp_path, outcome):
    """Ctrl-C inside a stage (the solver's Interrupted) or while setting a stage up (a bare
    KeyboardInterrupt): results.json says "interrupted", with the stages that ran."""
    scene = FakeScene("converge", outcome, "converge")
    with pytest.raises(Interrupted) as err:
        pipeline.run(scene, tmp_path / "run")
    assert scene.log == ["stage0", "stage1"]
    written = json.loads((tmp_path / "run" / "results.json").read_text())
    assert written["status"] == INTERRUPTED and written["metrics"] == {}
    assert "stage0" in written["solver"]
    assert err.value.results.status == INTERRUPTED


@pytest.mark.parametrize("outcome", ["converge", "fail"])
def test_fallback_stage_runs_the_second_path_only_after_a_reset(outcome):
    """A failed first path is reset, then the second runs under the first's name; its
    history starts with the failed attempt's steps. A second path that fails too fails the
    stage."""
    from ngincompat.fem.solver import StepRecord
    from ngincompat.fem.stages import FallbackStage

    log = []

    class Failing(FakeStage):
        def run(self, progress):
            self.log.append(self.name)
            attempt = SolverHistory(steps=[StepRecord(t=0.1, dt=0.1, converged=True,
                                                      iterations=5)])
            raise ConvergenceError("limit point", history=attempt, t_converged=0.1)

    stage = FallbackStage(Failing("deflation", log), FakeStage("lowered", log, outcome),
                          reset=lambda: log.append("reset"))
    assert stage.name == "deflation"
    if outcome == "fail":
        with pytest.raises(ConvergenceError):
            stage.run(pipeline.SILENT)
        assert log == ["deflation", "reset", "lowered"]
        return
    history = stage.run(pipeline.SILENT)
    assert log == ["deflation", "reset", "lowered"]
    assert [s.iterations for s in history.steps] == [5] and history.converged
    # a first path that converges is all there is
    log.clear()
    assert FallbackStage(FakeStage("deflation", log), FakeStage("lowered", log),
                         reset=lambda: log.append("reset")).run(pipeline.SILENT).converged
    assert log == ["deflation"]
