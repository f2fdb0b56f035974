"""The trust gate: each scene's accuracy indicators and their thresholds, warnings in the
results of a run past one, none for a run within them."""

import json
import math

import pytest

from ngincompat.cli import main
from ngincompat.fem.solver import SolverHistory, StepRecord
from ngincompat.scenes import CubeScene
from ngincompat.scenes.trust import NEWTON_PER_STEP, Indicator, solver_effort


def test_an_indicator_warns_only_past_its_limit():
    ind = Indicator("Je_deviation_max", 0.1, "refine")
    assert ind.check({"Je_deviation_max": 0.1}) is None
    assert ind.check({}) is None and ind.check({"Je_deviation_max": math.nan}) is None
    assert ind.check({"Je_deviation_max": 0.98}) == "Je_deviation_max = 0.98 > 0.1: refine"


class _Run:
    def __init__(self, iterations):
        steps = [StepRecord(t=1.0, dt=1.0, converged=True, iterations=n) for n in iterations]
        self.solver = {"growth": SolverHistory(steps=steps)}


def test_the_solver_effort_warns_on_many_newton_iterations_per_step():
    assert solver_effort(_Run([NEWTON_PER_STEP] * 3)) is None
    assert solver_effort(_Run([])) is None
    warning = solver_effort(_Run([NEWTON_PER_STEP + 1, NEWTON_PER_STEP + 2]))
    assert warning.startswith(f"Newton iterations per step = {NEWTON_PER_STEP + 1.5:.3g} > ")


def test_a_run_within_its_indicators_has_no_warning():
    results = CubeScene(order=2, maxh=0.5, outputs="none").run()
    assert results.status == "done" and results.warnings == []


@pytest.mark.parametrize("order", [2, 3])
def test_the_mixed_formulation_on_tetrahedra_does_not_lock_nor_warn(order):
    """The cube's largest principal stress on tetrahedra at nu = 0.49999 against the same
    on hexahedra (another discretisation, whose pair is stable): within 8 % (without the
    bubbles, 0.198 against 0.0030 MPa at order 2), and the same as at nu = 0.499."""
    stress = {}
    for elements in ("tet", "hex"):
        for nu in (0.499, 0.49999):
            results = CubeScene(order=order, maxh=0.25, elements=elements,
                                formulation="mixed", nu=nu, outputs="none").run()
            assert results.status == "done" and results.warnings == []
            stress[elements, nu] = results.metrics["max_principal_stress"]
    assert stress["tet", 0.49999] == pytest.approx(stress["hex", 0.49999], rel=0.08)
    assert stress["tet", 0.49999] == pytest.approx(stress["tet", 0.499], rel=0.01)


def test_a_locked_run_at_nu_0_49999_warns_and_still_exits_0(tmp_path, capsys, caplog):
    """The displacement formulation at nu = 0.49999 (one hexahedron, order 2): 181 Newton
    iterations and a stress of 3.1 MPa against the mixed form's 0.003; exit 0 with its
    results, the warning logged (standard error) and in results.json."""
    out = tmp_path / "run"
    code = main(["run", "cube", "--order", "2", "--maxh", "1", "--set", "elements=hex",
                 "--set", "nu=0.49999", "--set", "outputs=none", "--out", str(out), "-q"])
    err = capsys.readouterr().err
    written = json.loads((out / "results.json").read_text())
    assert code == 0 and written["status"] == "done"
    assert any("volumetric locking" in w for w in written["warnings"])
    assert "volumetric locking" in caplog.text and "Traceback" not in err


def test_the_coarse_atrophy_run_warns_and_still_writes_its_results(tmp_path, caplog):
    """The gray shell one element thick: |Je / theta - 1| 0.54 (the defaults: 1.2e-2). Exit 0,
    the results written, the indicator named. (Its equilibrium residual was 3.5e-5 with the
    unstable pressure pair of the mixed form on tetrahedra; with the bubbles it is 4e-16.)"""
    out = tmp_path / "run"
    code = main(["run", "atrophy", "--out", str(out), "--maxh", "2", "--set", "t_end=10",
                 "--set", "dt=1", "--set", "snapshots=2", "-q"])
    written = json.loads((out / "results.json").read_text())
    assert code == 0 and written["status"] == "done"
    assert [w.split(" = ")[0] for w in written["warnings"]] == ["Je_deviation_max"]
    assert "Je_deviation_max = 0.538" in caplog.text
    assert written["metrics"]["equilibrium_residual_rel"] < 1e-12
    share = written["metrics"]["Je_deviation_volume_fraction"]
    assert 0 < share < 1e-3 and f"over a volume fraction of {share:.2g}" in caplog.text


@pytest.mark.parametrize("scene, metric, good, bad", [
    ("skin", "volume_error_rel", 1e-4, 1e-2),
    ("folding", "equilibrium_residual", 1.5e-11, 1e-3),
    ("folding", "release_reaction_rel", 1e-9, 1e-2)])
def test_skin_and_folding_name_their_indicators(scene, metric, good, bad):
    """The accuracy indicators of the coupled scenes: a value as their runs give stays quiet,
    one past the threshold is one warning naming the metric."""
    from ngincompat.scenes import SCENES
    cls = SCENES[scene]
    assert metric in cls.metrics and metric in [i.metric for i in cls.indicators]
    run = _Run([3, 4])
    run.metrics = {metric: good}
    assert cls().warnings(run) == []
    run.metrics = {metric: bad}
    assert [w.split(" = ")[0] for w in cls().warnings(run)] == [metric]
