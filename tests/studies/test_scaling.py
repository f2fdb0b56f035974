"""The scaling benchmark: one Newton step of the cube per linear solver, each case in its own
process with its own peak memory."""

import sys

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat import cli, config
from ngincompat.errors import ParameterError
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import NewtonSolver
from ngincompat.studies import scaling
from ngincompat.workflow import io

IN_PROCESS = ("sparsecholesky", "umfpack", "bddc", "bddc-amg", "amg")


def cube_problem(solver=None):
    """2 x 2 x 2 hexahedra, order 2 (375 dofs), at the first Newton state of t = 1, built
    for ``solver``."""
    problem = scaling.mechanics(0.5, 2, solver)
    scaling.first_state(problem)
    return problem


@pytest.fixture(scope="module")
def steps():
    return {solver: scaling.newton_step(cube_problem(solver), solver) for solver in IN_PROCESS}


def test_the_solvers_agree_on_the_newton_direction(steps):
    newton = NewtonSolver(cube_problem())
    newton.residual()
    newton.factorise()
    ref = newton.direction().FV().NumPy()
    assert np.linalg.norm(ref) > 0
    for solver in IN_PROCESS:
        du, row = steps[solver]
        assert np.linalg.norm(du.FV().NumPy() - ref) <= 1e-6 * np.linalg.norm(ref), solver
        assert row["ndof"] == 375 and 0 < row["coupling"] < 375
        assert min(row["first_assembly_s"], row["assembly_s"], row["solve_s"]) >= 0
        assert row["total_s"] > 0 and (solver in scaling.PRECONDITIONERS or row["setup_s"] >= 0)


def test_the_multigrid_row_reports_its_levels_and_cg_iterations(steps):
    """On 375 unknowns the hierarchy is its coarsest level alone, solved directly: CG needs
    one iteration to the direct solver's residual."""
    row = steps["amg"][1]
    assert row["amg_levels"] == 1 and row["cg_iterations"] == 1
    assert row["residual"] < 1e-12 and "error" not in row


def test_residuals_show_the_accuracy_of_each_solver(steps):
    for solver in ("sparsecholesky", "umfpack"):
        assert steps[solver][1]["residual"] < 1e-12
    for solver in scaling.PRECONDITIONERS:
        row = steps[solver][1]
        assert 1e-14 < row["residual"] < scaling.CG_TOL, solver
        assert 0 < row["cg_iterations"] < 50 and "error" not in row, solver


def test_the_condensed_residual_is_the_full_one():
    """||K du - r|| of the uncondensed tangent equals the reported one, for an inexact du."""
    problem = cube_problem("bddc")
    du, row = scaling.newton_step(problem, "bddc", tol=1e-3)
    assert 1e-6 < row["residual"] < 1e-1
    full = GrowthMechanics(problem.mesh, problem.growth, problem.material, order=2,
                           condense=False)
    full.u.vec.data = problem.u.vec
    full.form.AssembleLinearization(full.u.vec)
    r = NewtonSolver(full).residual()
    check = r.CreateVector()
    check.data = full.form.mat * du - r
    free = np.array(list(full.freedofs), dtype=bool)
    reference = np.linalg.norm(check.FV().NumPy()[free]) / np.linalg.norm(r.FV().NumPy())
    assert row["residual"] == pytest.approx(reference, rel=1e-6)


def test_bddc_follows_a_new_linearisation():
    """The preconditioner registered on the form is set up by AssembleLinearization itself.

    Run as the package runs, in its task manager on one thread: the cube's coarse BDDC
    problem is singular here (the preconditioned vector is of order 1e17), and its round-off
    is only reproducible from one set-up to the next on one thread."""
    with config.using(threads=1), config.task_manager():
        _bddc_follows_a_new_linearisation()


def _bddc_follows_a_new_linearisation():
    problem = cube_problem()
    pre = ngs.Preconditioner(problem.form, "bddc")
    x = problem.u.vec.CreateVector()
    x.SetRandom()
    problem.form.AssembleLinearization(problem.u.vec)
    problem.u.vec.data *= 3
    problem.form.AssembleLinearization(problem.u.vec)
    fresh = cube_problem()
    fresh.u.vec.data *= 3
    fresh_pre = ngs.Preconditioner(fresh.form, "bddc")
    fresh.form.AssembleLinearization(fresh.u.vec)
    y, z = x.CreateVector(), x.CreateVector()
    y.data = pre.mat * x
    z.data = fresh_pre.mat * x
    assert np.linalg.norm(y.FV().NumPy() - z.FV().NumPy()) < 1e-10 * np.linalg.norm(z.FV().NumPy())


def test_benchmark_writes_rows_with_per_process_peak_memory(tmp_path):
    lines = scaling.main([0.5, 1 / 6], solvers=["sparsecholesky", "pardiso"], timeout=120.0,
                         memory_limit=4.0, out=str(tmp_path))
    data = io.read_json(tmp_path / "scaling.json")
    assert data["complete"]
    rows = {(r["ndof"], r["solver"]): r for r in data["rows"]}
    small, large = rows[(375, "sparsecholesky")], rows[(6591, "sparsecholesky")]
    assert small["status"] == large["status"] == "ok"
    assert large["residual"] < 1e-12 and large["elements"] == 216
    assert 50 < small["peak_mib"] < large["peak_mib"]
    assert small["assembly_peak_mib"] <= small["peak_mib"]
    pardiso = rows[(375, "pardiso")]
    if data["pardiso"]["available"]:
        assert pardiso["status"] == "ok" and pardiso["residual"] < 1e-12
    else:
        assert pardiso["status"] == "skipped" and data["pardiso"]["reason"]
        assert any(line.startswith("pardiso skipped:") for line in lines)
    assert any("| 6591 | 2 |" in line for line in lines)
    # the tables as markdown too, for the performance page
    assert "| 6591 | 2 |" in (tmp_path / "scaling.md").read_text()
    assert "sparsecholesky" in (tmp_path / "scaling_rows.md").read_text()


def test_a_process_over_its_time_becomes_an_error_row(tmp_path):
    row = scaling.run_process(0.5, 2, None, tmp_path / "state.npy", timeout=0.2,
                              memory_limit=4.0)
    assert row["status"] == "error" and row["limit"] == "time"
    assert "timeout" in row["error"]


def test_watch_kills_a_process_over_its_memory():
    grow = "import time; x = bytearray(400 * 2**20); time.sleep(30)"
    code, limit, peak, seconds, _ = scaling.watch([sys.executable, "-c", grow], timeout=20,
                                         memory_limit=0.1, poll=0.02)
    assert limit == "memory" and code < 0 and peak > 100 and seconds < 10


def test_a_failing_case_becomes_an_error_row(tmp_path):
    row = scaling.run_process(0.5, 0, "sparsecholesky", tmp_path / "state.npy", timeout=60,
                              memory_limit=4.0)
    assert row["status"] == "error" and "ParameterError: order = 0" in row["error"]
    assert row["peak_mib"] > 0 and "limit" not in row


def test_a_solver_over_a_limit_is_skipped_on_larger_cases(monkeypatch):
    calls = []

    def fake(maxh, order, solver, state, timeout, memory_limit):
        calls.append((maxh, solver))
        if solver == "sparsecholesky":
            return {"status": "error", "error": "timeout after 1 s", "limit": "time"}
        return {"status": "ok", "state_s": 0.0, "total_s": 1.0, "peak_mib": 1.0}

    monkeypatch.setattr(scaling, "run_process", fake)
    rows, _ = scaling.run_grid(scaling.make_grid([0.5, 0.25]), ["sparsecholesky", "bddc"])
    assert [r["status"] for r in rows] == ["error", "ok", "skipped", "ok"]
    assert (0.25, "sparsecholesky") not in calls
    assert scaling.format_summary(rows).splitlines()[-1].endswith("| bddc | bddc |")
    assert "| 375 | 2 | timeout | 1.00 s / 1 MiB |" in scaling.format_summary(rows)
    assert "skipped: hit its limit at 375 dofs" in scaling.format_rows(rows)


def test_grid_and_options():
    assert scaling.make_grid() == sorted(scaling.make_grid(), key=lambda p: scaling
                                         .ndof_estimate(*p))
    assert max(scaling.ndof_estimate(*p) for p in scaling.make_grid()) >= 5e5
    assert [p for _, p in scaling.make_grid(orders=[4])] == [4, 4, 4, 4]
    assert scaling.make_grid([0.5], [2, 3]) == [(0.5, 2), (0.5, 3)]
    assert scaling.ndof_estimate(1 / 27, 2) == 3 * 55**3
    with pytest.raises(ParameterError, match="maxh"):
        scaling.make_grid([1.5])
    with pytest.raises(ParameterError, match="order"):
        scaling.make_grid(orders=[7])
    with pytest.raises(ParameterError, match="solver"):
        scaling.run_grid([(0.5, 2)], ["mumps"])
    with pytest.raises(ParameterError, match="timeout"):
        scaling.run_grid([(0.5, 2)], timeout=0)
    args = cli.build_parser().parse_args(["bench", "scaling", "--quick", "--solvers", "bddc",
                                          "--timeout", "60", "--memory-limit", "2"])
    assert (args.case, args.solvers, args.timeout, args.memory_limit) == \
        ("scaling", ["bddc"], 60.0, 2.0)
    assert args.maxh is None and args.orders is None


def test_measurements_before_a_failure_are_kept():
    row = {}
    with pytest.raises(Exception, match="mumps"):
        scaling.newton_step(cube_problem(), "mumps", row=row)
    assert row["ndof"] == 375 and row["assembly_s"] > 0 and "setup_s" not in row
