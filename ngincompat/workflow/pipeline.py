"""The scene pipeline: one path from parameters to results, the same from Python and the
command line.

    scene (parameters, validated)  --build()-->  case: mesh, growth, material, BCs, stages
    case  --solve()-->  solution: the stages walked in order (histories, status)
    case, solution  --measure()-->  Results (typed; fields included)
    Results  --output.write(out)-->  results.json, VTK, figures   (only this touches files)

:func:`run` does all of it; with ``out=None`` nothing is written, and a notebook draws
``results.fields`` with ``ngsolve.webgui.Draw``. A stage is a load history as data: a name, a
unit of its marching parameter and a ``run(progress)`` that marches it and returns its
:class:`~ngincompat.fem.solver.SolverHistory`. :func:`solve_stages` walks a case's stages, stops
at the first that fails to converge (the state is then the last converged one) or is
interrupted, and records which.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time as _time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from netgen.libngpy._meshing import NgException

from ngincompat import parallel
from ngincompat.errors import (
    ConvergenceError,
    Interrupted,
    InterruptedBeforeComputing,
    ParameterError,
)
from ngincompat.fem import work
from ngincompat.fem.solver import SolverHistory
from ngincompat.fem.stages import Stage
from ngincompat.progress import SILENT, Progress
from ngincompat.resources import peak_mib
from ngincompat.workflow import output
from ngincompat.workflow.results import DONE, INTERRUPTED, NOT_CONVERGED, Results

#: The errors of a run that every rank of a distributed run raises together (a check or a
#: residual reduced over the ranks, an interrupt sent to every rank); any other exception
#: raised inside a run ends a distributed job (:func:`~ngincompat.parallel.alone_ends_the_job`).
COLLECTIVE = (ParameterError, ConvergenceError, Interrupted, KeyboardInterrupt)

log = logging.getLogger(__name__)


@contextlib.contextmanager
def timed(timings: dict, phase: str) -> Iterator[None]:
    """Add the wall time of the block to ``timings[phase]``."""
    start = _time.perf_counter()
    try:
        yield
    finally:
        timings[phase] = timings.get(phase, 0.0) + _time.perf_counter() - start


@dataclass
class Solution:
    """What solving a case produced: the solver history and wall time of every stage that
    ran, how the walk ended, and the case-specific state (the problems) for measuring."""

    histories: dict[str, SolverHistory] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    status: str = DONE
    error: str | None = None
    state: Any = None

    @property
    def converged(self) -> bool:
        return self.status == DONE


class Case(Protocol):
    """What a scene builds: knows its stages and how to measure their result."""

    def solve(self, solution: Solution, progress: Progress, workdir: Path | None) -> None:
        """Walk the stages into ``solution`` (see :func:`solve_stages`); ``workdir`` is the
        run's folder (checkpoints), or None."""

    def interrupted(self, solution: Solution) -> Results:
        """The record of an interrupted run: parameters and histories, no metrics."""

    def measure(self, solution: Solution, progress: Progress) -> Results:
        """Fields, metrics, profiles and figures of the solved state."""


def solve_stages(stages: Iterable[Stage], progress: Progress = SILENT,
                 solution: Solution | None = None,
                 after: Callable[[Stage], object] | None = None) -> Solution:
    """Run ``stages`` in order into ``solution``; stop at a failure or an interruption.

    A stage that does not converge leaves the last converged state and sets the status
    ``"not converged"`` with the reason; an interrupted one sets ``"interrupted"``. Either way
    the history up to that point is kept, with the seconds per kind of work the stage took
    (``work``: :mod:`ngincompat.fem.work`). ``after(stage)``, if given, is called after every
    stage that converged (to note quantities of that moment). Returns the solution.
    """
    solution = Solution() if solution is None else solution
    for stage in stages:
        before = work.totals()
        try:
            with timed(solution.timings, stage.name):
                solution.histories[stage.name] = stage.run(progress)
                solution.histories[stage.name].work = work.since(before)
                if after is not None:
                    after(stage)
        except (ConvergenceError, Interrupted) as err:
            if err.history is not None:
                err.history.work = work.since(before)
                solution.histories[stage.name] = err.history
            interrupted = isinstance(err, Interrupted)
            solution.status = INTERRUPTED if interrupted else NOT_CONVERGED
            solution.error = f"{stage.name}: {err}"
            progress.line(f"{stage.name}: {'interrupted' if interrupted else 'not converged'}"
                          f" ({err})")
            break
    return solution


def _warn(scene: Any, results: Results) -> None:
    """The scene's warnings on its results (:meth:`Scene.warnings`; none for a scene without
    indicators), each also logged (once: by rank 0 of a distributed run)."""
    check = getattr(scene, "warnings", None)
    results.warnings = list(check(results)) if check else []
    for line in results.warnings if parallel.is_root() else ():
        log.warning("%s: %s", scene.name, line)


def _refuse_non_finite(solution: Solution, results: Results) -> None:
    """A run that reports a metric that is not a finite number has not computed what it
    reports: it is "not converged" (exit 3) and its error names those metrics, also after a
    stage that did not converge. The fields, figures and growth data of that state are not
    written (:func:`ngincompat.workflow.output.write`); results.json keeps the finite metrics
    (the others null) and the time series the frames taken before."""
    bad = results.non_finite()
    if not bad:
        return
    reason = (f"metrics not finite: {', '.join(bad)} (the input drives the model beyond what "
              "double precision holds; the fields of that state are not written)")
    solution.error = reason if solution.status == DONE else f"{solution.error}; {reason}"
    solution.status = results.status = NOT_CONVERGED
    results.error = solution.error


def run(scene: Any, out: str | os.PathLike | None = None, *, overwrite: bool = False,
        progress: Progress = SILENT,
        label: str | None = None) -> Results:
    """Build, solve and measure ``scene``; write its folder ``out`` if given.

    Parameters
    ----------
    scene : Scene
    out : path-like, optional
        Output folder, checked before anything is computed
        (:func:`ngincompat.workflow.output.prepare`).
    overwrite : bool
        Replace a run already in ``out``.
    progress : Progress
        Where cases, stages and steps are reported (default: nowhere).
    label : str, optional
        The case's name in the progress report (default: the scene's name).

    Returns
    -------
    Results

    Raises
    ------
    ParameterError
        ``out`` cannot take the run, or the mesher failed on the scene's geometry
        (:meth:`~ngincompat.scenes.base.Scene.unmeshable`: a body far thinner than its mesh
        size); nothing is written.
    ConvergenceError
        A stage did not converge; the results of the last converged state were measured and
        written first and are in the exception's ``results``.
    Interrupted
        Ctrl-C: results.json marked "interrupted" (solver history, no metrics) was written;
        the exception's ``results`` holds it.
    KeyboardInterrupt
        Ctrl-C after results.json was written complete: the record stands as written.

    Notes
    -----
    In a distributed run any other exception (a defect, not a checked input) prints its
    traceback and ends every rank, exit code 1 (:data:`COLLECTIVE`).
    """
    if out is not None:
        out = parallel.on_root(output.prepare, out, overwrite=overwrite,
                               resume=scene.resumes(out), run_files=output.RUN_FILES)
    try:
        with parallel.alone_ends_the_job(COLLECTIVE):
            return _run(scene, out, progress, label)
    finally:
        if out is not None:
            parallel.on_root(output.release, out)


def _run(scene: Any, out: Path | None, progress: Progress, label: str | None) -> Results:
    """:func:`run` in a folder already prepared (or none)."""
    with progress.case(label or scene.name):
        timings: dict[str, float] = {}
        try:
            with progress.phase("meshing"), timed(timings, "mesh"):
                case = scene.build()
        except KeyboardInterrupt:
            raise InterruptedBeforeComputing("interrupted while meshing: nothing was computed, "
                                             "nothing written") from None
        except NgException as err:
            raise ParameterError(scene.unmeshable(err)) from None
        solution = Solution()
        try:
            case.solve(solution, progress, out)
        except KeyboardInterrupt:
            solution.status, solution.error = INTERRUPTED, "interrupted while setting up"
        results, phase = None, "measuring"
        try:
            if solution.status == INTERRUPTED:
                results = case.interrupted(solution)
            else:
                results = case.measure(solution, progress)
                # every rank's peak memory so far (the solve and the measures), rank 0 first
                results.provenance["peak_mib"] = [round(m) for m in
                                                  parallel.per_rank(peak_mib())]
                _refuse_non_finite(solution, results)
                _warn(scene, results)
            results.timings = {**timings, **solution.timings, **results.timings}
            if out is not None:
                phase = "writing"
                with progress.phase("writing results"):
                    output.write(results, out)
                    phase = "written"
        except KeyboardInterrupt:
            if phase == "written":      # the record is complete: it stands, the caller stops
                raise
            # the files the write finished (it lists them in results.files) are kept
            kept = [] if results is None or phase != "writing" else results.files
            solution.status, solution.error = INTERRUPTED, f"interrupted while {phase}"
            results = case.interrupted(solution)
            results.files += [f for f in kept if f not in results.files]
            results.timings = {**timings, **solution.timings}
            if out is not None:
                output.write(results, out, outputs=set())
        progress.outcome(solution.status)
    if solution.status == DONE:
        return results
    kind = Interrupted if solution.status == INTERRUPTED else ConvergenceError
    error = kind(solution.error)
    error.results = results
    raise error
