"""Adaptive load and time stepping around :class:`~ngincompat.fem.solver.NewtonSolver`:
prescribed growth applied in load steps (:func:`solve_growth`), coupled growth marched in time
(:func:`solve_coupled`). A step whose Newton iteration fails is undone and retried at half the
size; after an easy one the next doubles (:class:`~ngincompat.fem.solver.NewtonOptions`'
``step_up``, ``step_hold``, ``max_step``, ``min_step``). Every attempted step is recorded
(:class:`~ngincompat.fem.solver.StepRecord`).
"""

import logging
import time as _time
from collections.abc import Callable

import ngsolve as ngs

from ngincompat import config
from ngincompat.errors import ConvergenceError, Interrupted
from ngincompat.fem.coupled import CoupledProblem, FrozenGrowth
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import (
    NewtonOptions,
    NewtonProblem,
    NewtonSolver,
    SolverHistory,
    StepRecord,
)
from ngincompat.progress import SILENT, Progress, StageProgress

log = logging.getLogger(__name__)


def solve_growth(problem: GrowthMechanics, time: ngs.Parameter,
                 options: NewtonOptions = NewtonOptions(), t_end: float = 1.0,
                 progress: Progress = SILENT, stage: str = "growth") -> SolverHistory:
    """Apply prescribed growth from the current time to ``t_end`` in adaptive load steps.

    Parameters
    ----------
    problem : GrowthMechanics
    time : ngsolve.Parameter
        The growth time that the problem's Fg depends on.
    options : NewtonOptions
    t_end : float
    progress : Progress
        Where steps and cuts are reported (default: nowhere).
    stage : str
        The stage's name in the progress report.

    Returns
    -------
    SolverHistory

    Raises
    ------
    ConvergenceError
        When a step would fall below ``options.min_step``; ``problem.u`` and ``time`` then
        hold the last converged state.
    """
    def advance(t: float, t_new: float) -> None:
        if options.predictor:
            before = problem.growth_load()
            time.Set(t_new)
            increment = problem.growth_load()
            increment.data -= before
            problem.u.vec.data += problem.compatible_displacement(increment)
        else:
            time.Set(t_new)

    t0 = time.Get()
    return _march(problem, options, t0, t_end, (t_end - t0) / options.steps, advance,
                  restore=lambda t: time.Set(t), accept=None,
                  report=progress.march(stage, t0, t_end))


def solve_coupled(problem: CoupledProblem | FrozenGrowth, t_end: float, dt: float,
                  options: NewtonOptions = NewtonOptions(max_iter=20), t_start: float = 0.0,
                  schedule: Callable[[float], object] | None = None,
                  on_step: Callable[[float], bool] | None = None,
                  progress: Progress = SILENT, stage: str = "growth", unit: str = "",
                  energy: Callable[[], float] | None = None) -> SolverHistory:
    """March a :class:`~ngincompat.fem.coupled.CoupledProblem` in time with adaptive steps.

    Parameters
    ----------
    problem : CoupledProblem
    t_end, dt, t_start : float
        End time, first time step and start time (the scene's time unit).
    schedule : callable, optional
        ``schedule(t)`` sets time-dependent loads (e.g. the volume target) for time t.
    on_step : callable, optional
        ``on_step(t)`` after every converged step, e.g. to write a checkpoint; if it returns
        True, the march ends there (e.g. where an instability was detected).
    progress : Progress
        Where steps and cuts are reported, under the name ``stage`` with time ``unit``.
    energy : callable, optional
        The energy of the current state whose derivative the residual is (as for
        :class:`~ngincompat.fem.solver.NewtonSolver`), e.g. ``problem.energy`` at frozen growth.

    Returns
    -------
    SolverHistory

    Raises
    ------
    ConvergenceError
        Below ``options.min_step``; the state then holds the last converged step.
    """
    state = problem.state.vec
    start, previous = state.CreateVector(), state.CreateVector()
    times = {"start": t_start, "previous": None}    # of ``start`` and ``previous``

    def advance(t: float, t_new: float) -> None:
        problem.dt.Set(t_new - t)
        if schedule is not None:
            schedule(t_new)
        start.data = state                  # the last converged state
        times["start"] = t
        if options.extrapolate and times["previous"] is not None:
            state.data += (t_new - t) / (t - times["previous"]) * (start - previous)

    def restore(t: float) -> None:
        if schedule is not None:
            schedule(t)

    def accept(t: float) -> bool:
        previous.data = start
        times["previous"] = times["start"]
        problem.accept_step()
        return on_step is not None and on_step(t)

    return _march(problem, options, t_start, t_end, dt, advance, restore, accept,
                  progress.march(stage, t_start, t_end, unit), energy)


def _march(problem: NewtonProblem, options: NewtonOptions, t: float, t_end: float, dt: float,
           advance: Callable[[float, float], None], restore: Callable[[float], object],
           accept: Callable[[float], bool] | None, report: StageProgress,
           energy: Callable[[], float] | None = None) -> SolverHistory:
    """The adaptive stepping loop: a failed step is undone and retried at half the size.

    ``report`` (a :class:`~ngincompat.progress.StageProgress`) hears of every converged and
    every cut step as it happens; ``accept(t)`` returning True ends the march at t."""
    solver = NewtonSolver(problem, options, energy=energy)
    history = SolverHistory(t_reached=t)
    saved = problem.state.vec.CreateVector()
    saved.data = problem.state.vec          # the last converged state, always
    held = 0                                # steps still to converge before dt may grow
    with config.task_manager():
        try:
            while t < t_end - 1e-12 * max(1.0, abs(t_end)):
                dt = min(dt, t_end - t)
                advance(t, t + dt)
                record = StepRecord(t=t + dt, dt=dt, converged=False)
                start = _time.perf_counter()
                record.converged = solver.minimise(record)
                record.seconds = _time.perf_counter() - start
                history.steps.append(record)
                if record.converged:
                    t += dt
                    history.t_reached = t
                    # t's state is kept before accept (a checkpoint, an observation) runs:
                    # a Ctrl-C there reports t with t's state, not the step's before
                    saved.data = problem.state.vec
                    stop = accept is not None and accept(t)
                    saved.data = problem.state.vec          # as accept left it
                    report.step(t, dt, record.iterations)
                    log.info("t = %.4g reached in %d Newton iterations", t, record.iterations)
                    if stop:
                        break
                    if held:
                        held -= 1
                    elif record.iterations <= options.step_up:
                        dt = min(2 * dt, options.max_step)
                    continue
                problem.state.vec.data = saved
                restore(t)
                report.cut(t, dt, record.reason)
                log.info("step to t = %.4g failed (%s); cutting the step", t + dt,
                         record.reason)
                dt /= 2
                held = options.step_hold
                if dt < options.min_step:
                    raise ConvergenceError(
                        f"growth could not be applied beyond t = {t:.6g}: the step fell below "
                        f"min_step = {options.min_step:g} ({record.reason})",
                        history=history, t_converged=t)
        except KeyboardInterrupt:
            problem.state.vec.data = saved
            restore(t)
            raise Interrupted(f"interrupted at t = {t:.6g}", history=history,
                              t_converged=t) from None
        finally:
            report.close()
    history.converged = True
    return history
