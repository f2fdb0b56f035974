"""The equilibrium at held growth, reached from a state that is not one, and the march that
uses it to pass its snaps: stages of a load history (:mod:`ngincompat.fem.stages`).

* :class:`RelaxationStage`: at frozen growth, from a state that is not an equilibrium (a
  viscous march's end, a body whose constraints were just removed), a viscous gradient flow
  (one Newton step per pseudo-time step) to a stable equilibrium, finished by Newton
  without the viscosity;
* :class:`SnappingMarch`: a viscous march whose snaps (steps cut below its shortest) are
  passed by such a relaxation at held growth.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat import config
from ngincompat.errors import ConvergenceError, require
from ngincompat.fem import buckling
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.solver import NewtonOptions, NewtonSolver, SolverHistory, StepRecord
from ngincompat.fem.stages import CoupledStage
from ngincompat.fem.terms import ViscousRegularisation
from ngincompat.progress import Progress

if TYPE_CHECKING:
    import ngsolve as ngs


@dataclass(eq=False)
class RelaxationStage:
    """The equilibrium at frozen growth of a :class:`~ngincompat.fem.coupled.CoupledProblem`
    with a :class:`~ngincompat.fem.terms.ViscousRegularisation` ``viscous``, reached by a
    gradient flow in pseudo time and then solved without the viscosity.

    Each pseudo-time step tau holds the growth (``problem.growing`` = 0) and makes one
    Newton step on

        Phi(u) = Pi(u) + eta / (2 tau) int |u - u_n|^2 dV,     eta = ``viscosity``,

    (:meth:`~ngincompat.fem.coupled.CoupledProblem.energy`; Pi its value at frozen growth,
    :meth:`~ngincompat.fem.coupled.CoupledProblem.frozen_energy`) from u_n, in full:

        u_n+1 = u_n - (K + eta / tau M)^-1 r(u_n),

    K the elastic tangent at u_n, M the mass matrix of :mod:`ngincompat.fem.buckling`, r the
    residual without viscosity: the linearly implicit Euler step of the flow, a pseudo-
    transient continuation (Kelley and Keyes, SIAM J. Numer. Anal. 35 (1998) 508), whose
    step is Newton's as tau grows and a short gradient step (tau / eta M^-1 r) as it falls.
    Solving each step of the flow to convergence instead (an implicit Euler step) cost 3-6
    Newton iterations a step and crept along the soft bending mode of a released bilayer,
    over pseudo times of a thousand days, without reaching its equilibrium
    (``docs/measurements/folding.md``, "The release in contact").

    A step is accepted where Phi(u_n+1) <= Pi(u_n) (beyond round-off, ``1e-12 |Pi|``): while
    K + eta / tau M is positive definite its stationary point is the minimiser of Phi, so the
    energy falls. Along an unstable mode (K w = omega M w, omega < 0) a step tau > eta /
    |omega| breaks this: in the linear model Phi(u_n+1) - Pi(u_n) = |omega| a^2 c /
    (2 (c - 1)), c = tau |omega| / eta, for a mode amplitude a, positive for c > 1, where the
    step goes back toward the saddle. Where the full step raises Phi above Pi(u_n), or its
    state is not finite (an element inverted), the state moves along the same direction by
    1/2, 1/4, ... of it (at most ``options.max_backtracks`` halvings), the first length
    alpha at which Phi falls below Pi(u_n): a line search, an energy per try instead of a
    tangent, and the next tau is alpha tau. Where no length does, the step is rejected and
    retried at half the size. Pi(u_n) is the energy as the terms define it after the last
    accepted step: a
    :class:`~ngincompat.fem.self_contact.SelfContact` pairs its points anew there, which
    changes the energy of the same state where its walls touch, and the next step's Phi is
    made of the new pairs. After an accepted full step tau doubles, unless it is one of
    the ``options.step_hold`` accepted steps after a rejected or shortened one. The flow so
    leaves the saddles it passes near and settles in a stable equilibrium (one it reaches
    itself it leaves only if kicked, below).

    The residual without viscosity at u_n+1 is r(u_n+1). Once it is below ``switch`` times
    its value at the start (:attr:`initial_residual`), Newton solves the equilibrium
    without viscosity (a frozen step, dt = 0, with a line search: full steps from a state
    still far from it invert elements; a step is accepted where it lowers the strain
    energy, of which the frozen residual at no load is the derivative, or the residual
    norm) from there, to ``options.rtol`` of the residual at the start of the relaxation
    (rtol of its own start may lie below what round-off lets a residual reach, where the
    flow has nearly arrived); if that fails the flow goes on, and tries again once the
    residual has fallen ``switch``-fold more. An equilibrium Newton finds is kept only if
    it is stable, the smallest eigenvalue of its tangent at frozen growth
    (:func:`~ngincompat.fem.buckling.smallest_eigenpairs`) >= 0: started close to a
    saddle, Newton returns to the saddle; the flow then goes on from the state before, or,
    with ``kick`` > 0, from the saddle moved along its unstable mode by ``kick`` (at the
    mode's largest dof; a saddle met again, the other way), with the first pseudo-time
    step ``dt`` again, or half of eta / |omega| if that is shorter (omega the saddle's
    smallest eigenvalue): a flow that has reached a saddle itself does not leave it (seen
    on the folding bilayer: a residual of 5e-10 at the saddle, the smallest eigenvalue
    -1.8e4, tau doubled to 1e98), and one kicked off it in steps tau > eta / |omega| goes
    back: its linearly implicit step runs up the unstable mode toward the saddle, and the
    energy test accepts it where the other modes' descent outweighs the climb (the
    concentric bilayer at 62.8 days, kick after kick either way, energies repeating to ten
    digits). In steps below eta / |omega| the mode grows at each step, as the flow's own
    does.
    :attr:`final_residual` is the residual without viscosity at the end, :attr:`eigenvalue`
    the smallest eigenvalue there (of ``eigenpairs`` computed). The history's steps are
    the pseudo-time steps (``t`` the pseudo time, ``dt`` tau; one Newton iteration each)
    and last the frozen step (``dt`` = 0), whose ``residuals`` end with the residual of the
    equilibrium. The problem is left frozen (dt = 0, ``growing`` = 1).

    Raises
    ------
    ConvergenceError
        No equilibrium after ``max_steps`` accepted steps (a rejected try, retried with half
        the step, does not count), or tau below ``options.min_step``.
    """

    name: str
    problem: CoupledProblem
    viscous: ViscousRegularisation
    viscosity: float
    dt: float
    switch: float = 0.1
    max_steps: int = 60
    options: NewtonOptions = field(default_factory=lambda: NewtonOptions(max_iter=12))
    unit: str = ""
    eigenpairs: int = 1
    kick: float = 0.0
    initial_residual: float = field(default=float("nan"), init=False)
    final_residual: float = field(default=float("nan"), init=False)
    eigenvalue: float = field(default=float("nan"), init=False)
    _kicked: list = field(default_factory=list, init=False)

    def __post_init__(self) -> None:
        require(self.max_steps >= 1, "max_steps", self.max_steps, ">= 1")
        require(self.kick >= 0, "kick", self.kick, ">= 0 (a displacement)")

    def run(self, progress: Progress) -> SolverHistory:
        problem, label = self.problem, progress.stage_label(self.name)
        solver = NewtonSolver(problem, self.options)
        history = SolverHistory()
        problem.growing.Set(0.0)
        self.viscous.restart(self.viscosity)
        saved = problem.state.vec.CreateVector()
        saved.data = problem.state.vec
        self.initial_residual = self._residual(solver)
        energy, t, tau, accepted, held = problem.frozen_energy(), 0.0, self.dt, 0, 0
        attempt = self.initial_residual
        progress.line(f"{label}: residual without viscosity {self.initial_residual:.3g}")
        try:
            with config.task_manager():
                while accepted < self.max_steps:
                    problem.dt.Set(tau)
                    record = StepRecord(t=t + tau, dt=tau, converged=False)
                    alpha = solver.step(record, functools.partial(self._lowers, energy))
                    if alpha > 0:
                        record.converged, record.energy = True, problem.frozen_energy()
                    history.steps.append(record)
                    if not record.converged:
                        problem.state.vec.data = saved
                        progress.line(f"{label}: step {tau:.3g} failed ({record.reason})"
                                      f"; retrying with {tau / 2:.3g}")
                        tau /= 2
                        held = self.options.step_hold
                        if tau < self.options.min_step:
                            break
                        continue
                    t, accepted = t + tau, accepted + 1
                    problem.accept_step()
                    # Pi(u_n) of the next step's terms: a self-contact's new pairs change it
                    energy = problem.frozen_energy()
                    saved.data = problem.state.vec
                    residual = self._residual(solver)
                    progress.line(f"{label}: pseudo time {t:.4g}{self._unit} (step "
                                  f"{tau:.3g}), energy {energy:.10g}, residual without "
                                  f"viscosity {residual:.3g}")
                    history.t_reached = t
                    if residual <= self.switch * attempt:
                        outcome = self._equilibrium(history, saved, progress)
                        if outcome == "stable":
                            history.converged = True
                            return history
                        attempt = residual
                        if outcome == "kicked":     # from beside the saddle, in short steps
                            problem.accept_step()
                            energy = problem.frozen_energy()
                            saved.data = problem.state.vec
                            attempt = self._residual(solver)
                            tau = min(self.dt, 0.5 * self.viscosity / abs(self.eigenvalue))
                            held = 0
                            continue
                    if alpha < 1:
                        tau *= alpha
                        held = self.options.step_hold
                        if tau < self.options.min_step:
                            break
                    elif held:
                        held -= 1
                    else:
                        tau *= 2
        finally:
            problem.dt.Set(0.0)
            problem.growing.Set(1.0)
        raise ConvergenceError(f"{self.name}: no equilibrium after {accepted} pseudo-time "
                               f"steps (last step {tau:.3g})", history=history,
                               t_converged=history.t_reached)

    @property
    def _unit(self) -> str:
        return f" {self.unit}" if self.unit else ""

    def _lowers(self, energy: float) -> bool:
        """Is Phi at the current state finite and at most ``energy`` (Pi(u_n)), beyond
        round-off?"""
        phi = self.problem.energy()
        return math.isfinite(phi) and phi <= energy + 1e-12 * abs(energy)

    def _residual(self, solver: NewtonSolver) -> float:
        """The norm of the residual without viscosity at the current state."""
        dt = self.problem.dt.Get()
        self.problem.dt.Set(0.0)
        norm = solver.residual().Norm()
        self.problem.dt.Set(dt)
        return norm

    def _equilibrium(self, history: SolverHistory, saved: ngs.BaseVector,
                     progress: Progress) -> str:
        """Newton without viscosity from the current state: "stable" where it converges to
        a stable equilibrium; "kicked" where it converges to a saddle, the state moved off
        it (:meth:`_kick`); else "refused", the state restored to ``saved``."""
        label = progress.stage_label(self.name)
        self.problem.dt.Set(0.0)
        record = StepRecord(t=history.t_reached, dt=0.0, converged=False)
        atol = max(self.options.atol, self.options.rtol * self.initial_residual)
        solver = NewtonSolver(self.problem, replace(self.options, line_search=True, atol=atol),
                              energy=self.problem.frozen_energy)
        kicked = False
        if solver.minimise(record):
            values, modes = buckling.smallest_eigenpairs(self.problem, count=self.eigenpairs)
            self.eigenvalue = float(values[0])
            record.converged = self.eigenvalue >= 0
            if not record.converged:
                record.reason = f"unstable: smallest eigenvalue {self.eigenvalue:.3g}"
                kicked = self._kick(modes[0])
        history.steps.append(record)
        progress.line(f"{label}: without viscosity "
                      + (f"{record.iterations} Newton iterations, residual "
                         f"{record.residuals[-1]:.3g}, smallest eigenvalue "
                         f"{self.eigenvalue:.3g}" if record.converged else
                         f"not accepted ({record.reason}); relaxing on"))
        if not (record.converged or kicked):
            self.problem.state.vec.data = saved
        self.final_residual = record.residuals[-1]
        return "stable" if record.converged else "kicked" if kicked else "refused"

    def _kick(self, mode: ngs.GridFunction) -> bool:
        """Move the state (a saddle Newton converged to) along its unstable ``mode`` by
        ``kick`` at the mode's largest dof; True if it did (``kick`` > 0). A saddle met
        again in this relaxation (its energy at frozen growth equal to a kicked one's to
        1e-10) is left the other way, then the first way again, ...: a flow from the
        concentric bilayer's saddle at 62.8 days with the hand-over at a quarter step
        returned to it after each kick along +w, its energies repeating to ten digits
        (``docs/measurements/folding.md``, "The march's failed steps")."""
        if self.kick <= 0:
            return False
        energy = self.problem.frozen_energy()
        again = sum(1 for e in self._kicked if math.isclose(e, energy, rel_tol=1e-10))
        self._kicked.append(energy)
        w = mode.vec.FV().NumPy()
        self.problem.u.vec.data += ((-1) ** again * self.kick / np.max(np.abs(w))) * mode.vec
        return True


@dataclass(eq=False)
class SnappingMarch:
    """A viscous march (``march``, a :class:`CoupledStage`) whose snaps are passed at frozen
    growth, under the march's name.

    Where a growing state loses stability along a steep mode (K w = omega M w, omega << 0:
    a fold snapping, a surface creasing), the viscous march follows the mode's growth at
    the rate |omega| / eta, and its implicit Euler steps converge only below eta / |omega|:
    thousandths of a day, dozens of steps for one event. Where the march's step is cut
    below its ``options.min_step`` (set to a fraction of its longest step), the growth is
    held at the last converged time t and ``relax()`` (a :class:`RelaxationStage`) lets the
    state fall to a stable equilibrium of that growth: its pseudo-time steps grow where the
    march's could not, the growth held for the event's duration (the axons' growth over
    it, G_axn dt, is what is neglected). The march then goes on from t, the viscous term's
    reference state being that equilibrium. Where the relaxation finds none (a creased
    state in contact whose energy falls by less than round-off), the state goes back to
    the march's last step and the march follows the snap in steps down to ``shortest``,
    as it would without relaxations. Where a piece makes no progress after a relaxation
    (the cut that called it came before the snap, whose start still needs shorter steps),
    the march goes on from there in steps down to ``finer`` times the shortest it had,
    again and again while it makes none; the shortest step it is given back after the
    next relaxation. It ends with the error of its last piece where that would be below
    ``shortest``, or after ``max_snaps`` relaxations; the state is then the last converged
    step of the march.

    The history holds the march's steps and, for each relaxation, its steps at the march's
    time t with dt = 0 (growth held); :attr:`snaps` the times of the relaxations."""

    march: CoupledStage
    relax: Callable[[], RelaxationStage]
    max_snaps: int = 50
    shortest: float = 1e-6
    finer: float = 0.25
    snaps: list = field(default_factory=list, init=False)

    @property
    def name(self) -> str:
        return self.march.name

    def run(self, progress: Progress) -> SolverHistory:
        label = progress.stage_label(self.name)
        history = SolverHistory(t_reached=self.march.t_start)
        march = self.march
        problem = march.problem
        while True:
            failure: ConvergenceError | None
            try:
                piece = march.run(progress)
            except ConvergenceError as err:
                piece, failure = err.history, err
            else:
                failure = None
            history.steps += piece.steps
            history.t_reached = piece.t_reached
            if failure is None:
                history.converged = True
                return history
            t = failure.t_converged
            if len(self.snaps) >= self.max_snaps:
                raise ConvergenceError(str(failure), history=history, t_converged=t)
            if self.snaps and t <= self.snaps[-1]:      # no progress since the relaxation
                shortest = march.options.min_step * self.finer
                if shortest < self.shortest:
                    raise ConvergenceError(str(failure), history=history, t_converged=t)
                progress.line(f"{label}: no step from t = {t:.6g} after the relaxation; "
                              f"marching on in steps down to {shortest:g}")
                march = replace(self.march, t_start=t,
                                options=replace(self.march.options, min_step=shortest))
                continue
            progress.line(f"{label}: the step was cut below {march.options.min_step:g} at "
                          f"t = {t:.6g}: relaxing at that growth")
            saved = problem.state.vec.CreateVector()
            saved.data = problem.state.vec
            relaxation = self.relax()
            try:
                relaxed = relaxation.run(progress)
            except ConvergenceError as err:
                problem.state.vec.data = saved
                problem.accept_step()       # the viscous term's reference: that state again
                history.steps += [replace(s, t=t, dt=0.0) for s in err.history.steps]
                progress.line(f"{label}: no equilibrium there ({err}); marching on in steps "
                              f"down to {self.shortest:g}")
                self.snaps.append(t)
                march = replace(self.march, t_start=t,
                                options=replace(self.march.options, min_step=self.shortest))
                continue
            history.steps += [replace(s, t=t, dt=0.0) for s in relaxed.steps]
            problem.accept_step()           # the viscous term's reference: the equilibrium
            self.snaps.append(t)
            march = replace(self.march, t_start=t)
