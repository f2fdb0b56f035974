"""Where a solve's time goes (ngincompat.fem.work): exclusive parts, and each stage's share."""

import time

import pytest
from fem.test_coupled import LAW, _stretched_bar

from ngincompat.fem import work
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stages import CoupledStage
from ngincompat.workflow.pipeline import solve_stages


def test_a_part_inside_another_counts_for_the_inner_one_only():
    before = work.totals()
    with work.part("eigenpairs"):
        time.sleep(0.05)
        with work.part("assembly"):
            time.sleep(0.1)
    spent = work.since(before)
    assert spent["assembly"] == pytest.approx(0.1, abs=0.05)
    assert spent["eigenpairs"] == pytest.approx(0.05, abs=0.04)
    assert spent["eigenpairs"] < spent["assembly"]
    assert spent["residual"] == 0.0


def test_an_unknown_kind_of_work_is_refused_with_the_allowed_ones():
    with pytest.raises(ValueError, match="allowed assembly, factorisation"):
        with work.part("meshing"):
            pass


def test_a_stage_keeps_the_work_of_its_newton_iterations():
    """The coupled bar's march: assembly, factorisation, solves and residuals are counted
    in its history, within the stage's wall time."""
    problem, _ = _stretched_bar(LAW)
    stage = CoupledStage("growth", problem, t_end=1.0, dt=0.5,
                         options=NewtonOptions(max_iter=20, linear_solver="direct"))
    solution = solve_stages([stage])
    spent = solution.histories["growth"].work
    assert set(spent) == set(work.KINDS)
    for kind in ("assembly", "factorisation", "linear solve", "residual"):
        assert spent[kind] > 0, kind
    assert spent["contact search"] == spent["eigenpairs"] == 0.0
    assert sum(spent.values()) <= solution.timings["growth"]
    assert solution.histories["growth"].as_dict()["work"] == spent
