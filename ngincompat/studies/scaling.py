"""Cost of one Newton step against problem size and linear solver: ``ngincompat bench scaling``.

Every Newton iteration of :mod:`ngincompat.fem.solver` assembles the tangent K (the linearisation
of the energy), prepares a linear solver for it and solves K du = r once. This benchmark
measures these three costs and the memory they need for the cube scene's mechanics problem
(:class:`~ngincompat.scenes.CubeScene`: hexahedra, traction-free with rigid-body pins, static
condensation) from about 1e3 to more than 5e5 dofs, so that the solver can be chosen by size:

``sparsecholesky``, ``umfpack``
    NGSolve's sparse direct solvers on the condensed (coupling) system, exactly as
    :class:`~ngincompat.fem.solver.NewtonSolver` uses them (``factorise``, ``direction``):
    r + harmonic_extension_trans r, the factorisation, then harmonic_extension and inner_solve
    for the element interiors.
``bddc``
    CG (:class:`ngsolve.krylovspace.CGSolver`, relative tolerance 1e-8 in the preconditioned
    norm) on the same condensed system, preconditioned by NGSolve's element-level BDDC. The
    preconditioner is registered on the form and set up by AssembleLinearization itself
    (tests/studies/test_scaling.py checks that it follows a new linearisation). BDDC takes its
    free dofs from the space, which does not know the six rigid-body pins, so CG runs with
    the preconditioner projected onto the free dofs, P C P.
``bddc-amg``
    The same with an algebraic multigrid as BDDC's coarse space (``coarsetype="h1amg"``) in
    place of the factorised wirebasket problem, whose memory grows faster than the unknowns.
``amg``
    CG on the same condensed system, preconditioned by one V-cycle of PyAMG's
    smoothed-aggregation multigrid built from the rigid motions (:mod:`ngincompat.fem.amg`,
    as Newton's ``linear_solver="amg"``). Its set-up is the hierarchy's construction from
    the assembled matrix.
``pardiso``
    MKL Pardiso, only where NGSolve can load MKL. The pip NGSolve links OpenBLAS; without the
    ``mkl`` package its cases are skipped with NGSolve's reason.

The state is that of the first Newton iteration at t = 1: u = the compatible displacement of
the full growth (:meth:`~ngincompat.fem.problem.GrowthMechanics.compatible_displacement`), so K is
the real tangent of a solve. Per (mesh, order, solver) the row reports

* ndof and ``coupling``: the free dofs of the condensed system that the solver sees (``nze``:
  the nonzeros its matrix stores),
* ``assembly_s``: AssembleLinearization without a preconditioner into the allocated matrix,
  as in every Newton step after the first (``first_assembly_s``: the first one, which also
  allocates the matrix); ``setup_s``: the factorisation, or for BDDC the extra time of
  registering it and assembling with it (element Schur complements and the factorised
  wirebasket system; the difference of two timed assemblies, so it carries their noise and
  can come out slightly negative in small cases); ``solve_s``: condensation, solve and
  extension; ``total_s`` the sum: one Newton step apart from the residual and the line search
  (for BDDC directly the time of its assembly and the solve),
* ``cg_iterations`` (BDDC) and ``residual`` = ||K du - r|| / ||r||. It is evaluated on the
  condensed system: the interior rows of K du - r vanish by construction (the element-local
  inner solve is exact) and its coupling rows are S du_c - r_c with the Schur complement S and
  the condensed right-hand side r_c, so a solver that fails silently shows here,
* ``peak_mib``: the peak resident set size (``VmHWM``, :func:`peak_mib`) of the case's own
  process at its end (mesh, space, tangent and solver; Python and NGSolve alone take some
  200 MiB), and ``assembly_peak_mib`` the same right after the plain assembly.

Each case runs in its own process (``python -m ngincompat.studies.scaling TASK.json``, see
:func:`run_task`) with NGSolve's task manager on all cores (``NGS_NUM_THREADS`` in the
environment sets the number). The parent kills a process that runs longer than its time
limit or whose resident set grows beyond its memory limit (polled every 0.1 s). The
compatible displacement is computed once per (mesh, order) by a process of its own and
handed to the cases as a file, so the factorisation of its vector Laplacian does not count in
their peak memory. A case that fails, or runs out of memory
or time, becomes a row with the error (and the peak memory the kernel accounted for it); a
solver that hit a limit is skipped on larger cases. The machine's load average at the start of
each case is recorded (``load``): when other processes occupy the cores, the task manager's
threads wait for each other at every parallel loop, and the small cases, CG above all, become
many times slower. BDDC's element Schur complements call LAPACK inside the task manager's tasks,
and OpenBLAS then starts threads of its own: with one of two cores busy elsewhere, the BDDC
setup became fifty times slower than with ``OPENBLAS_NUM_THREADS=1`` (the cases inherit the
environment; ``docs/measurements/solver-costs.md``, "Choosing the linear solver").
"""

import contextlib
import itertools
import logging
import math
import os
import signal
import subprocess
import sys
import tempfile
import time as _time
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ngincompat import config
from ngincompat.errors import require
from ngincompat.resources import peak_mib
from ngincompat.workflow import io, tables

if TYPE_CHECKING:     # NGSolve is imported where a case runs
    import ngsolve as ngs

    from ngincompat.fem.problem import GrowthMechanics

log = logging.getLogger(__name__)

#: The linear solvers, in table order.
SOLVERS = ("sparsecholesky", "umfpack", "bddc", "bddc-amg", "amg", "pardiso")
#: The BDDC-preconditioned CG solvers and the options of their preconditioner.
PRECONDITIONERS: dict[str, dict[str, str]] = {"bddc": {}, "bddc-amg": {"coarsetype": "h1amg"}}
#: Relative tolerance and iteration limit of the BDDC-preconditioned CG.
CG_TOL = 1e-8
CG_MAXITER = 1000
#: Default grid, (hexahedra per edge n, order p; ndof = 3 (p n + 1)^3): order 2 from 1029 to
#: 555579 dofs, order 3 up to 46875, order 4 (fewer, larger elements) up to 555579 dofs.
GRID = ((3, 2), (5, 2), (8, 2), (12, 2), (18, 2), (28, 2),
        (2, 3), (4, 3), (8, 3),
        (2, 4), (4, 4), (8, 4), (14, 4))
#: ``--quick``: 375 and 2187 dofs.
QUICK_GRID = ((2, 2), (4, 2))
#: Orders of a grid built from ``--maxh`` alone.
DEFAULT_ORDERS = (2,)
#: Default limits of one case's process: wall time [s] and resident set [GiB].
TIMEOUT = 3600.0
MEMORY_LIMIT = 16.0


def mechanics(maxh: float, order: int, solver: str | None = None) -> "GrowthMechanics":
    """The cube scene's mechanics problem (condensed) at t = 1, as the scene's case builds
    it for ``solver`` (one of :data:`SOLVERS`: BDDC needs the energy form on VectorH1)."""
    from ngincompat.scenes import CubeScene

    # the scene's size guards give way to the benchmark's own limits of time and memory
    case = CubeScene(maxh=maxh, order=order, elements="hex", max_dofs=10**10,
                     max_elements=10**9).build()
    case.time.Set(1.0)
    return case.mechanics("cg" if solver in PRECONDITIONERS else
                          "amg" if solver == "amg" else "direct")


def first_state(problem: "GrowthMechanics") -> np.ndarray:
    """Set u to the compatible displacement of the growth at the current time (the start of
    the first Newton iteration of a solve); returns u as an array."""
    problem.u.vec.data = problem.compatible_displacement(problem.growth_load())
    return problem.u.vec.FV().NumPy().copy()


def newton_step(problem: "GrowthMechanics", solver: str, tol: float = CG_TOL,
                maxiter: int = CG_MAXITER, row: dict[str, Any] | None = None
                ) -> tuple["ngs.BaseVector", dict[str, Any]]:
    """Assemble the tangent at the problem's state and solve K du = r once with ``solver``
    (``problem`` as :func:`mechanics` builds it for that solver).

    Returns du (the full Newton direction, as :class:`NewtonSolver` computes it) and
    the row of measurements described in the module docstring, filled into ``row`` if given
    (so that what was measured before a failure is kept).
    """
    import ngsolve as ngs
    from ngsolve.krylovspace import CGSolver

    from ngincompat.fem.amg import SmoothedAggregation
    from ngincompat.fem.rigid import rigid_body_modes
    from ngincompat.fem.solver import NewtonSolver

    a, u, free = problem.form, problem.u.vec, problem.freedofs
    r = NewtonSolver(problem).residual()
    row = {} if row is None else row
    row.update(ndof=problem.ndof, coupling=free.NumSet())
    start = _time.perf_counter()
    a.AssembleLinearization(u)  # also allocates the matrix, which only the first step does
    row["first_assembly_s"] = _time.perf_counter() - start
    start = _time.perf_counter()
    a.AssembleLinearization(u)
    row["assembly_s"] = _time.perf_counter() - start
    row["assembly_peak_mib"] = peak_mib()
    row["nze"] = a.mat.nze
    start = _time.perf_counter()
    if solver in PRECONDITIONERS:
        pre = ngs.Preconditioner(a, "bddc", **PRECONDITIONERS[solver])
        a.AssembleLinearization(u)
        project = ngs.Projector(free, True)
        inverse = CGSolver(a.mat, project @ pre.mat @ project, tol=tol, maxiter=maxiter)
        row["setup_s"] = _time.perf_counter() - start - row["assembly_s"]
    elif solver == "amg":
        pre = SmoothedAggregation(a.mat, free, rigid_body_modes(problem.fes))
        inverse = CGSolver(a.mat, pre, tol=tol, maxiter=maxiter)
        row["setup_s"] = _time.perf_counter() - start
        row["amg_levels"] = pre.levels
    else:
        inverse = a.mat.Inverse(free, inverse=solver)
        row["setup_s"] = _time.perf_counter() - start
    start = _time.perf_counter()
    rhs = r.CreateVector()
    rhs.data = r
    rhs.data += a.harmonic_extension_trans * r
    du_c = r.CreateVector()
    du_c.data = inverse * rhs
    du = r.CreateVector()
    du.data = du_c
    du.data += a.harmonic_extension * du_c
    du.data += a.inner_solve * rhs
    row["solve_s"] = _time.perf_counter() - start
    row["total_s"] = row["assembly_s"] + row["setup_s"] + row["solve_s"]
    check = r.CreateVector()
    check.data = a.mat * du_c - rhs
    mask = np.array(list(free), dtype=bool)
    row["residual"] = (np.linalg.norm(check.FV().NumPy()[mask])
                       / np.linalg.norm(r.FV().NumPy()))
    if solver in PRECONDITIONERS or solver == "amg":
        row["cg_iterations"] = len(inverse.residuals) - 1
        if inverse.residuals[-1] > tol * inverse.residuals[0]:
            row["error"] = f"CG did not reach the tolerance in {maxiter} iterations"
    return du, row


def pardiso_status() -> tuple[bool, str]:
    """(True, "") if NGSolve factorises with inverse="pardiso" here, else (False, its reason)."""
    import ngsolve as ngs

    matrix = ngs.la.SparseMatrixd.CreateFromCOO([0, 1], [0, 1], [1.0, 2.0], 2, 2)
    try:
        matrix.Inverse(inverse="pardiso")
    except Exception as exc:  # NGSolve raises RuntimeError or NgException
        return False, str(exc).strip()
    return True, ""


# ---------------------------------------------------------------------------------------------
# The case processes


def run_task(path: str | os.PathLike) -> None:
    """Entry of a case's process (``python -m ngincompat.studies.scaling TASK.json``).

    The task file, written by :func:`run_process`, holds ``maxh``, ``order``, ``solver``
    (None: compute the compatible displacement), ``state`` (the .npy file of the compatible
    displacement: written without a solver, read with one) and ``result`` (the .json file
    the row is written to). Exceptions become the row's error.
    """
    task = io.read_json(path)
    with contextlib.suppress(OSError):  # the first process to go if the machine runs out
        Path("/proc/self/oom_score_adj").write_text("1000")
    from pyngcore import GetNumThreads

    row: dict[str, Any] = {"load": os.getloadavg()[0]}
    config.configure(threads=int(os.environ.get("NGS_NUM_THREADS") or os.cpu_count() or 1))
    start = _time.perf_counter()
    try:
        with config.task_manager():
            row["threads"] = GetNumThreads()
            problem = mechanics(task["maxh"], task["order"], task["solver"])
            row["elements"] = problem.mesh.ne
            if task["solver"] is None:
                np.save(task["state"], first_state(problem))
                row["state_s"] = _time.perf_counter() - start
            else:
                state = np.load(task["state"])
                require(state.size == problem.ndof, "state size", state.size,
                        f"ndof = {problem.ndof}")
                problem.u.vec.FV().NumPy()[:] = state
                row["base_peak_mib"] = peak_mib()
                newton_step(problem, task["solver"], row=row)
    except Exception as exc:  # every failure becomes the row's error
        row["error"] = f"{type(exc).__name__}: {exc}".strip()
    row["status"] = "error" if "error" in row else "ok"
    row["process_s"] = _time.perf_counter() - start
    row["peak_mib"] = peak_mib()
    io.write_json(task["result"], row)


def _rss_mib(pid: int) -> float:
    """Current resident set size of process ``pid`` [MiB]; 0 once it has exited."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return 0.0
    for line in status.splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def watch(cmd: Sequence[str], timeout: float, memory_limit: float,
          poll: float = 0.1) -> tuple[int, str | None, float, float, str]:
    """Run ``cmd``, killing it when it runs longer than ``timeout`` seconds or its resident
    set grows beyond ``memory_limit`` GiB.

    Returns (exit code, the limit it hit: None, "time" or "memory", its peak resident set
    [MiB] as the kernel accounted it, its wall time [s], its stderr).
    """
    with tempfile.TemporaryFile("w+") as err:
        start = _time.monotonic()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, text=True)
        limit = None
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if _time.monotonic() - start > timeout:
                limit = "time"
            elif _rss_mib(proc.pid) > memory_limit * 1024:
                limit = "memory"
            if limit:
                proc.kill()
                _, status, usage = os.wait4(proc.pid, 0)
                break
            _time.sleep(poll)
        proc.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        return (proc.returncode, limit, usage.ru_maxrss / 1024, _time.monotonic() - start,
                err.read())


def run_process(maxh: float, order: int, solver: str | None, state: str | os.PathLike,
                timeout: float, memory_limit: float) -> dict[str, Any]:
    """Run one case (``solver`` None: the compatible displacement into ``state``) in its own
    process; returns its row.

    A process that hits its time or memory limit, or whose allocation the machine refuses
    (``limit``: "time" or "memory"), crashes or exits without a row becomes an error row, with
    the peak memory it had reached.
    """
    with tempfile.TemporaryDirectory() as scratch:
        result = Path(scratch) / "row.json"
        task = io.write_json(Path(scratch) / "task.json",
                             {"maxh": maxh, "order": order, "solver": solver,
                              "state": str(state), "result": str(result)})
        cmd = [sys.executable, "-m", "ngincompat.studies.scaling", str(task)]
        code, limit, peak, seconds, stderr = watch(cmd, timeout, memory_limit)
        if result.exists():
            row = io.read_json(result)
            if "MemoryError" in row.get("error", ""):  # an allocation beyond the machine
                row["limit"] = "memory"
            return row
    if limit == "time":
        error = f"timeout after {timeout:g} s"
    elif limit == "memory":
        error = f"out of memory: resident set above {memory_limit:g} GiB after {seconds:.0f} s"
    else:
        lines = stderr.strip().splitlines()
        why = f"killed by {signal.Signals(-code).name}" if code < 0 else f"exit code {code}"
        error = f"process {why}" + (f": {lines[-1]}" if lines else "")
    return {"status": "error", "error": error, "limit": limit, "peak_mib": peak}


# ---------------------------------------------------------------------------------------------
# The grid


def cells_per_edge(maxh: float) -> int:
    """Hexahedra per edge of the unit cube at ``maxh``, as :func:`geometries.cube` makes them."""
    return max(1, math.ceil(1 / maxh - 1e-9))


def ndof_estimate(maxh: float, order: int) -> int:
    """ndof of the cube's hexahedral mesh: 3 (order n + 1)^3 for n cells per edge."""
    return 3 * (order * cells_per_edge(maxh) + 1) ** 3


def make_grid(maxhs: Sequence[float] | None = None, orders: Collection[int] | None = None,
              quick: bool = False) -> list[tuple[float, int]]:
    """The (maxh, order) cases by increasing size.

    Without ``maxhs`` the default grid (:data:`GRID`, or :data:`QUICK_GRID` with ``quick``),
    restricted to ``orders`` if given; with ``maxhs`` every maxh with every order of ``orders``
    (default :data:`DEFAULT_ORDERS`).
    """
    for order in orders or ():
        require(isinstance(order, int) and 1 <= order <= 10, "order", order,
                "an integer in [1, 10]")
    if maxhs is None:
        pairs = [(1 / n, p) for n, p in (QUICK_GRID if quick else GRID)
                 if orders is None or p in orders]
        require(pairs, "orders", orders, "orders of the default grid "
                f"{sorted({p for _, p in GRID})}, or give --maxh too")
    else:
        for maxh in maxhs:
            require(0 < maxh <= 1, "maxh", maxh, "in (0, 1] (the cube's edge is 1)")
        pairs = list(itertools.product(maxhs, orders or DEFAULT_ORDERS))
    return sorted(pairs, key=lambda pair: (ndof_estimate(*pair), pair[1]))


def run_grid(grid: Iterable[tuple[float, int]], solvers: Sequence[str] = SOLVERS,
             timeout: float = TIMEOUT, memory_limit: float = MEMORY_LIMIT,
             on_row: Callable[[list[dict[str, Any]]], object] | None = None
             ) -> tuple[list[dict[str, Any]], tuple[bool, str]]:
    """Run every solver on every (maxh, order) of ``grid``, each in its own process.

    Returns the rows (one per case and solver, in grid order) and the pardiso status. A solver
    that hit its time or memory limit is skipped on the cases with more dofs; ``on_row(rows)``
    is called after every row (e.g. to save the partial table).
    """
    for solver in solvers:
        require(solver in SOLVERS, "solver", solver, ", ".join(SOLVERS))
    require(timeout > 0, "timeout", timeout, "> 0 s")
    require(memory_limit > 0, "memory limit", memory_limit, "> 0 GiB")
    pardiso = pardiso_status()
    limited: dict[str, int] = {}  # solver -> ndof where it hit a limit
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for maxh, order in grid:
            state = Path(scratch) / f"state_h{maxh:g}_p{order}.npy"
            prepared = run_process(maxh, order, None, state, timeout, memory_limit)
            size = ndof_estimate(maxh, order)
            for solver in solvers:
                row = {"maxh": maxh, "order": order, "solver": solver, "ndof": size,
                       "elements": cells_per_edge(maxh) ** 3}
                if solver == "pardiso" and not pardiso[0]:
                    row.update(status="skipped", error=pardiso[1])
                elif solver in limited and size > limited[solver]:
                    row.update(status="skipped",
                               error=f"hit its limit at {limited[solver]} dofs")
                elif prepared["status"] != "ok":
                    row.update(status="error", error=f"state: {prepared['error']}")
                else:
                    log.info("scaling: %d dofs, order %d, %s", size, order, solver)
                    row.update(run_process(maxh, order, solver, state, timeout, memory_limit))
                    row["state_s"] = prepared["state_s"]
                    if row.get("limit"):
                        limited[solver] = size
                rows.append(row)
                if on_row is not None:
                    on_row(rows)
    return rows, pardiso


# ---------------------------------------------------------------------------------------------
# Tables


#: Columns of the full table (one row per case and solver) and their units.
COLUMNS = ("elements", "order", "ndof", "coupling", "solver", "assembly_s", "setup_s",
           "solve_s", "total_s", "cg_iterations", "residual", "peak_mib", "note")
UNITS = {"assembly_s": "s", "setup_s": "s", "solve_s": "s", "total_s": "s", "residual": "-",
         "peak_mib": "MiB"}


def _note(row: Mapping[str, Any]) -> str:
    """Why a row has no measurements, or its error."""
    if row["status"] == "skipped" and row["solver"] == "pardiso":
        return "skipped: not available (below)"
    if row["status"] == "skipped":
        return f"skipped: {row.get('error', '')}"
    return row.get("error", "").replace("|", "/")


def format_rows(rows: Iterable[Mapping[str, Any]]) -> str:
    """The full markdown table: one line per case and solver."""
    return tables.markdown([{**r, "note": _note(r)} for r in rows], list(COLUMNS), UNITS)


def format_summary(rows: Sequence[Mapping[str, Any]]) -> str:
    """Per (mesh, order): total seconds / peak MiB of each solver, the fastest and the
    leanest one among those that succeeded."""
    solvers = [s for s in SOLVERS if any(r["solver"] == s for r in rows)]
    cases: dict[tuple[int, int], dict[str, Mapping[str, Any]]] = {}
    for r in rows:
        cases.setdefault((r["ndof"], r["order"]), {})[r["solver"]] = r
    summary = []
    for (ndof, order), by_solver in cases.items():
        line: dict[str, Any] = {"ndof": ndof, "order": order}
        for s, r in by_solver.items():
            if r["status"] == "ok":
                line[s] = f"{r['total_s']:.2f} s / {r['peak_mib']:.0f} MiB"
            elif r.get("limit"):
                line[s] = {"time": "timeout", "memory": "out of memory"}[r["limit"]]
            else:
                line[s] = r["status"]
        ok = [r for r in by_solver.values() if r["status"] == "ok"]
        line["fastest"] = min(ok, key=lambda r: r["total_s"])["solver"] if ok else "-"
        line["least memory"] = min(ok, key=lambda r: r["peak_mib"])["solver"] if ok else "-"
        summary.append(line)
    return tables.markdown(summary, ["ndof", "order", *solvers, "fastest", "least memory"])


def main(maxhs: Sequence[float] | None = None, orders: Collection[int] | None = None,
         quick: bool = False, solvers: Iterable[str] | None = None, timeout: float = TIMEOUT,
         memory_limit: float = MEMORY_LIMIT, out: str | os.PathLike | None = None) -> list[str]:
    """Run the benchmark (``ngincompat bench scaling``); returns the lines to print.

    Parameters
    ----------
    maxhs, orders : sequence, optional
        The grid (see :func:`make_grid`).
    quick : bool
        The small default grid :data:`QUICK_GRID`.
    solvers : sequence of str, optional
        Among :data:`SOLVERS` (default: all).
    timeout : float
        Wall-time limit of one case's process [s].
    memory_limit : float
        Resident-set limit of one case's process [GiB].
    out : path-like, optional
        Folder of ``scaling.json``, rewritten atomically after every case so that a long run
        keeps what it measured, and at the end of the tables as markdown, ``scaling.md`` (per
        size and solver) and ``scaling_rows.md`` (every row).

    Returns
    -------
    list of str
    """
    grid = make_grid(maxhs, orders, quick)
    solvers = list(solvers or SOLVERS)
    path = Path(out) / "scaling.json" if out else None
    settings = {"grid": grid, "solvers": solvers, "timeout_s": timeout,
                "memory_limit_gib": memory_limit, "cg_tol": CG_TOL}

    def save(rows: list[dict[str, Any]], pardiso: dict[str, Any] | None = None,
             complete: bool = False) -> None:
        if path is not None:
            io.write_json(path, {**settings, "complete": complete, "pardiso": pardiso,
                                 "rows": rows, **io.provenance()})

    start = _time.perf_counter()
    rows, pardiso = run_grid(grid, solvers, timeout, memory_limit, on_row=save)
    save(rows, {"available": pardiso[0], "reason": pardiso[1]}, complete=True)
    lines = [format_rows(rows), "", format_summary(rows), ""]
    loads = [r["load"] for r in rows if "load" in r]
    if loads:
        lines.append(f"load average at the start of the cases: {min(loads):.1f} to "
                     f"{max(loads):.1f} ({os.cpu_count()} cores)")
    if "pardiso" in solvers and not pardiso[0]:
        lines.append(f"pardiso skipped: {pardiso[1]}")
    lines.append(f"{len(rows)} rows in {_time.perf_counter() - start:.0f} s")
    if path is not None:
        # out: given, as path is
        tables.write_markdown(Path(out) / "scaling.md", lines[2])  # type: ignore[arg-type]
        tables.write_markdown(Path(out) / "scaling_rows.md", lines[0])  # type: ignore[arg-type]
        lines.append(f"written to {path} (and scaling.md, scaling_rows.md)")
    return lines


if __name__ == "__main__":
    run_task(sys.argv[1])
