"""Stages of a load history, as data: what a case's solve walks through in order.

* :class:`PrescribedGrowthStage`: prescribed growth Fg(X, t) applied from t = 0 to ``t_end``
  in adaptive load steps (:func:`~ngincompat.fem.stepping.solve_growth`), or solved at ``t_end`` at
  once from a given start state (the state before a load or a support was removed);
* :class:`CoupledStage`: mechanically coupled growth marched in time
  (:func:`~ngincompat.fem.stepping.solve_coupled`), with growth on or frozen, the enclosed volume
  and a dead traction driven linearly between two values (inflation, hold, deflation),
  checkpointed after every step when given a checkpoint file;
* :class:`FallbackStage`: one stage, and where it fails another from the same start;
* :class:`ContactControlStage`: after an expander's inflation, the expander's volume corrected
  until the volume under the skin is the target.

The relaxation to an equilibrium at held growth and the march that passes its snaps by it
are in :mod:`ngincompat.fem.relaxation`.

Each has a ``name`` and ``run(progress) -> SolverHistory`` (the
:class:`Stage` protocol).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, runtime_checkable

import ngsolve as ngs
import numpy as np

from ngincompat import config
from ngincompat.atomic import atomic_path
from ngincompat.errors import ConvergenceError, ParameterError, require
from ngincompat.fem.contact import ExpanderContact
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import NewtonOptions, NewtonSolver, SolverHistory, StepRecord
from ngincompat.fem.stepping import solve_coupled, solve_growth
from ngincompat.fem.terms import DeadTraction, VolumeHolder
from ngincompat.progress import Progress


@runtime_checkable
class Stage(Protocol):
    """One part of a load history: inflation, a week of growth, a release, ..."""

    @property
    def name(self) -> str: ...

    def run(self, progress: Progress) -> SolverHistory:
        """March the stage to its end; raise ConvergenceError (state: last converged step)
        or Interrupted."""


@dataclass(eq=False)
class PrescribedGrowthStage:
    """Prescribed growth: ``time`` (the Parameter that Fg depends on) from ``t_start`` to
    ``t_end``.

    With a ``start`` (a displacement, as a CoefficientFunction) the equilibrium at ``t_end``
    is first sought by Newton (``start_options``) from that state at once: where a body in
    equilibrium loses a load or a support (the skin's expander taken out, then its clamp),
    the state before is the physical path's start and a far better guess than u = 0. Only if
    Newton fails from there is the growth applied in load steps from the problem's state
    before the stage (the history then holds the failed attempt first).
    """

    name: str
    problem: GrowthMechanics
    time: ngs.Parameter
    options: NewtonOptions = field(default_factory=NewtonOptions)
    t_start: float = 0.0
    t_end: float = 1.0
    start: ngs.CoefficientFunction | None = None
    start_options: NewtonOptions = field(default_factory=lambda: NewtonOptions(max_iter=50))

    def run(self, progress: Progress) -> SolverHistory:
        attempt = None
        if self.start is not None:
            attempt = self._from_start(progress)
            if attempt.converged:
                return attempt
        self.time.Set(self.t_start)
        history = solve_growth(self.problem, self.time, self.options, self.t_end,
                               progress=progress, stage=self.name)
        if attempt is not None:
            history.steps[:0] = attempt.steps
        return history

    def _from_start(self, progress: Progress) -> SolverHistory:
        """Newton at ``t_end`` from ``start``; on failure the problem's state is restored."""
        label, u = progress.stage_label(self.name), self.problem.u
        before = u.vec.CreateVector()
        before.data = u.vec
        u.Set(self.start)
        self.time.Set(self.t_end)
        record = StepRecord(t=self.t_end, dt=self.t_end - self.t_start, converged=False)
        started = time.perf_counter()
        with config.task_manager():
            record.converged = NewtonSolver(self.problem, self.start_options).minimise(record)
        record.seconds = time.perf_counter() - started
        history = SolverHistory(steps=[record], converged=record.converged,
                                t_reached=self.t_end if record.converged else self.t_start)
        if record.converged:
            progress.line(f"{label}: equilibrium from the start state in "
                          f"{record.iterations} Newton iterations")
        else:
            u.vec.data = before
            progress.line(f"{label}: from the start state {record.reason}; applying the "
                          "growth in load steps instead")
        return history


@dataclass(eq=False)
class CoupledStage:
    """Coupled growth (:class:`~ngincompat.fem.coupled.CoupledProblem`) from ``t_start`` to
    ``t_end`` in steps of ``dt`` (halved where Newton needs it).

    Attributes
    ----------
    grow : bool
        Growth evolves (implicit Euler with the step as dt); False freezes it (dt = 0), as
        during a quasi-static inflation: Newton then works on the problem's
        :meth:`~ngincompat.fem.coupled.CoupledProblem.frozen` form where it has one (the
        displacement alone, a symmetric tangent).
    volume : tuple of float, optional
        Target of the volume that the problem's term ``holder`` holds (a
        :class:`~ngincompat.fem.terms.VolumeConstraint` or an
        :class:`~ngincompat.fem.contact.ExpanderContact`) at ``t_start`` and ``t_end``,
        linear in between; None as the first: the target the term has when the stage starts.
    checkpoint : Path, optional
        File that receives the state after every converged step (atomically).
    traction : tuple of float, optional
        Scale of the dead traction ``dead_load`` (a :class:`~ngincompat.fem.terms.DeadTraction`
        of the problem) at ``t_start`` and ``t_end``, linear in between.
    start : callable, optional
        ``start()`` as the stage begins, before its first load (e.g. a load handed over
        from one kind to another).
    observe : callable, optional
        ``observe(t)`` after every converged step (after the checkpoint): measures the state;
        returning True ends the stage there.
    unit : str
        Unit of the marching parameter, for the progress report.
    """

    name: str
    problem: CoupledProblem
    t_end: float
    dt: float
    t_start: float = 0.0
    grow: bool = True
    volume: tuple[float | None, float] | None = None
    holder: VolumeHolder | None = None
    traction: tuple[float, float] | None = None
    dead_load: DeadTraction | None = None
    start: Callable[[], object] | None = None
    options: NewtonOptions = field(default_factory=lambda: NewtonOptions(max_iter=20))
    checkpoint: Path | None = None
    observe: Callable[[float], object] | None = None
    unit: str = ""
    _loaded: float = field(default=float("inf"), init=False, repr=False)

    def __post_init__(self) -> None:
        require(self.volume is None or self.holder is not None, "holder", self.holder,
                "the term that holds the volume, for a stage that drives a volume")
        require(self.traction is None or self.dead_load is not None, "dead_load",
                self.dead_load, "the dead traction, for a stage that drives a traction")

    def load(self, t: float) -> None:
        """Set the loads of time ``t``: the volume target, the dead traction's scale and, if
        frozen, dt = 0. Moving forward from the last converged time (not back to it after a
        failed step), the state is lifted with an expander
        (:meth:`~ngincompat.fem.contact.ExpanderContact.set_target`)."""
        if not self.grow:
            self.problem.dt.Set(0.0)
        span = self.t_end - self.t_start
        s = 1.0 if span <= 0 else (t - self.t_start) / span
        if self.volume is not None and self.holder is not None:
            v0, v1 = self.volume
            assert v0 is not None, "run() sets the volume at the start"
            self.holder.set_target(v0 + (v1 - v0) * s, lift=t > self._loaded)
        if self.traction is not None and self.dead_load is not None:
            s0, s1 = self.traction
            self.dead_load.scale.Set(s0 + (s1 - s0) * s)
        self._loaded = t

    def save(self, t: float) -> None:
        """Write the state at time ``t`` to the checkpoint, if there is one."""
        if self.checkpoint is not None:
            save_checkpoint(self.problem, self.checkpoint, t)

    def after_step(self, t: float) -> bool:
        """Checkpoint and observe the state of time ``t``; True ends the stage."""
        self.save(t)
        return self.observe is not None and bool(self.observe(t))

    def run(self, progress: Progress) -> SolverHistory:
        if self.start is not None:
            self.start()
        if self.volume is not None and self.volume[0] is None and self.holder is not None:
            self.volume = (self.holder.target.Get(), self.volume[1])
        self.load(self.t_start)
        self.save(self.t_start)
        # frozen: Newton on the displacement alone where the terms allow it (the same steps)
        problem = self.problem if self.grow else self.problem.frozen() or self.problem
        return solve_coupled(problem, self.t_end, self.dt, self.options,
                             t_start=self.t_start, schedule=self.load, on_step=self.after_step,
                             progress=progress, stage=self.name, unit=self.unit)


@dataclass(eq=False)
class FallbackStage:
    """``first``; where it does not converge, ``reset()`` (back to the state it started
    from) and ``second`` instead, under ``first``'s name. The history holds the failed
    attempt's steps first."""

    first: Stage
    second: Stage
    reset: Callable[[], object]

    @property
    def name(self) -> str:
        return self.first.name

    def run(self, progress: Progress) -> SolverHistory:
        label = progress.stage_label(self.name)
        try:
            return self.first.run(progress)
        except ConvergenceError as err:
            progress.line(f"{label}: {err}; starting again on the other path")
            self.reset()
            history = self.second.run(progress)
            if err.history is not None:
                history.steps[:0] = err.history.steps
            return history


@dataclass(eq=False)
class ContactControlStage:
    """Volume control of an expander in contact (the term ``contact``, an
    :class:`~ngincompat.fem.contact.ExpanderContact` of the problem, growth frozen), from an
    equilibrium (the end of the inflation): the expander's own volume V_e is corrected until
    the volume V under the skin is ``target`` to ``rtol``.

    Each round that finds V out of tolerance takes a secant step on V(V_e) = target (the
    first one V_e target / V: the volume under the skin is nearly proportional to the
    expander's), lifts the skin with the expander and solves the equilibrium (Newton),
    halving the step where Newton fails (at most ``max_cuts`` times). The converged start is
    not solved again (at 50 cc such a Newton step from the inflation's converged end failed:
    no acceptable step). The record's ``t`` is the round, its ``dt`` the expander's change.

    Raises
    ------
    ConvergenceError
        Newton fails in a round, or ``max_rounds`` rounds do not reach the tolerance.
    """

    name: str
    problem: CoupledProblem
    contact: ExpanderContact
    target: float
    rtol: float = 1e-4
    max_rounds: int = 20
    max_cuts: int = 5
    options: NewtonOptions = field(default_factory=lambda: NewtonOptions(max_iter=20))

    def run(self, progress: Progress) -> SolverHistory:
        contact, label = self.contact, progress.stage_label(self.name)
        self.problem.dt.Set(0.0)
        solver = NewtonSolver(self.problem.frozen() or self.problem, self.options)
        history = SolverHistory()
        previous = None
        for k in range(self.max_rounds + 1):
            expander, volume = contact.target.Get(), contact.volume()
            progress.line(f"{label}: round {k}, volume {volume:.7g} (target "
                          f"{self.target:g}, expander {expander:.7g})")
            if abs(volume - self.target) <= self.rtol * self.target:
                history.converged = True
                return history
            if k == self.max_rounds:
                break
            slope = volume / expander
            if previous is not None and volume != previous[1]:
                secant = (volume - previous[1]) / (expander - previous[0])
                slope = secant if 0.2 * slope < secant < 5 * slope else slope
            previous = expander, volume
            self._resize(solver, history, k + 1, expander, (self.target - volume) / slope)
            progress.line(f"{label}: round {k + 1} in {history.steps[-1].iterations} "
                          "Newton iterations")
        raise ConvergenceError(f"the volume is not within {self.rtol:g} of {self.target:g} "
                               f"after {self.max_rounds} rounds", history=history,
                               t_converged=history.t_reached)

    def _resize(self, solver: NewtonSolver, history: SolverHistory, k: int, expander: float,
                change: float) -> None:
        """Round ``k``: the expander's volume from ``expander`` by ``change``, halved (from
        the round's start) until Newton converges, at most ``max_cuts`` times."""
        problem, contact = self.problem, self.contact
        saved = problem.state.vec.CreateVector()
        saved.data = problem.state.vec
        for _ in range(self.max_cuts + 1):
            contact.set_target(expander + change, lift=True)
            record = StepRecord(t=float(k), dt=change, converged=False)
            with config.task_manager():
                record.converged = solver.minimise(record)
            history.steps.append(record)
            if record.converged:
                history.t_reached = float(k)
                return
            problem.state.vec.data = saved
            contact.set_target(expander)
            change /= 2
        raise ConvergenceError(f"round {k}: {record.reason}, also after {self.max_cuts} "
                               "halvings of the resize", history=history,
                               t_converged=history.t_reached)


def save_checkpoint(problem: CoupledProblem, path: Path, t: float) -> None:
    """Write the state of a coupled problem (its unknowns and what its terms keep: the
    previous growth, a volume target) atomically."""
    arrays = {"t": t, "state": problem.state.vec.FV().NumPy(), **problem.saved()}
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **arrays)


def restore_checkpoint(problem: CoupledProblem, path: Path) -> float | None:
    """Load a checkpoint into the problem; returns its time, or None if there is none.

    Raises
    ------
    ParameterError
        The checkpoint was written for another mesh or order.
    """
    if not path.is_file():
        return None
    data = np.load(path)
    if data["state"].shape != problem.state.vec.FV().NumPy().shape:
        raise ParameterError(f"{path} does not fit this mesh and order: cannot resume (run "
                             "with the settings of the interrupted run, or without resume)")
    problem.state.vec.FV().NumPy()[:] = data["state"]
    problem.restore(data)
    return float(data["t"])
