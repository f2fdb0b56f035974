"""The relaxation to an equilibrium at held growth (one Newton step per pseudo-time step,
accepted where the flow's energy falls) on stand-in flows, and the march that passes its
snaps by it on stand-in marches."""

from dataclasses import dataclass, field
from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import pytest

from geometries import cube
from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.fem.relaxation import RelaxationStage, SnappingMarch
from ngincompat.fem.solver import NewtonOptions, SolverHistory, StepRecord
from ngincompat.progress import SILENT


@pytest.mark.parametrize("max_steps", [0, -3])
def test_the_relaxation_needs_a_step(max_steps):
    with pytest.raises(ParameterError, match=r"max_steps.*>= 1"):
        RelaxationStage("release", None, None, viscosity=1.0, dt=1.0, max_steps=max_steps)


def _relax_a_fake_flow(monkeypatch, fails, fall, options=None, repair=0.0,
                       length=lambda tau: 1.0, eigenvalues=(1.0,), kick=0.0):
    """Run a :class:`RelaxationStage` whose Newton solver is a stand-in: a step of the flow
    fails where ``fails(tau)`` (as an inverted element), else it is taken to the length
    ``length(tau)`` of its direction;
    each accepted step lowers the energy by 1, and the update after it (new contact pairs)
    raises the energy of the same state by ``repair``; the flow's residual falls by
    ``fall`` of its start per accepted step, and Newton without viscosity converges whenever
    it is tried, to states whose smallest eigenvalues are ``eigenvalues`` in turn (the last
    one after them), the mode 2 at every dof. Returns the stage, its history and the number
    of accepted steps."""
    from ngincompat.fem import relaxation

    state = ngs.GridFunction(ngs.H1(cube(maxh=1.0), order=1))
    accepted = []

    class Flow:
        def __init__(self, problem, options, energy=None):
            pass

        def minimise(self, record):       # without viscosity: the equilibrium
            assert record.dt == 0
            record.residuals = [1e-12]
            return True

        def step(self, record, acceptable):    # one step of the flow, in full or not
            assert record.dt > 0
            record.iterations = 1
            if fails(record.dt):
                record.reason = "residual is not finite"
                return 0.0
            return length(record.dt)

        def residual(self):
            return SimpleNamespace(Norm=lambda: 1.0 - fall * len(accepted))

    mode = ngs.GridFunction(state.space)
    mode.vec[:] = 2.0
    values = list(eigenvalues)

    def smallest(*args, **kwargs):
        return [values.pop(0) if len(values) > 1 else values[0]], [mode]

    problem = SimpleNamespace(growing=ngs.Parameter(1.0), dt=ngs.Parameter(0.0), state=state,
                              u=state,
                              frozen_energy=lambda: (repair - 1.0) * len(accepted),
                              energy=lambda: (repair - 1.0) * len(accepted) - 1.0,
                              accept_step=lambda: accepted.append(True))
    monkeypatch.setattr(relaxation, "NewtonSolver", Flow)
    monkeypatch.setattr(relaxation.buckling, "smallest_eigenpairs", smallest)
    stage = RelaxationStage("release", problem, SimpleNamespace(restart=lambda eta: None),
                            viscosity=1.0, dt=1.0, options=options or NewtonOptions(),
                            kick=kick)
    return stage, stage.run(SILENT), len(accepted)


def test_failed_tries_of_the_relaxation_do_not_use_up_its_steps(monkeypatch):
    """A flow whose every other try fails (an inverted element: the step is halved, and the
    next accepted one doubles it again) reaches its equilibrium after 45 accepted steps, 90
    tries: the budget of 60 counts accepted steps. The flow's residual falls by 0.02 of its
    start per accepted step; Newton without viscosity is tried once it has fallen 10-fold."""
    tries = []

    def every_other(tau):
        tries.append(tau)
        return len(tries) % 2 == 1

    stage, history, accepted = _relax_a_fake_flow(monkeypatch, every_other, 0.02)
    assert history.converged and accepted == 45
    assert sum(not step.converged for step in history.steps) == 45
    assert stage.max_steps == 60 < len(history.steps)


@pytest.mark.parametrize("hold", [0, 2])
def test_after_a_failed_try_the_relaxation_holds_its_step(monkeypatch, hold):
    """A flow whose tries longer than 0.5 fail: after each failure the step is halved to
    0.5 and kept for ``step_hold`` accepted steps before it doubles (and fails) again."""
    _, history, accepted = _relax_a_fake_flow(monkeypatch, lambda tau: tau > 0.5, 0.1,
                                              NewtonOptions(step_hold=hold))
    tries = [(step.dt, step.converged) for step in history.steps if step.dt > 0]
    cycle = [(1.0, False)] + [(0.5, True)] * (hold + 1)
    assert history.converged and accepted == 9
    assert tries[:2 * len(cycle)] == cycle * 2


def test_the_relaxation_compares_a_step_with_the_energy_of_its_own_contact_pairs(monkeypatch):
    """New pairs after each accepted step raise the energy of the same state by 5, more than
    a step lowers it: measured against the energy before the update every step would look
    like a rise; measured against the energy with the new pairs, none does."""
    _, history, accepted = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1, repair=5.0)
    assert history.converged and accepted == 9
    assert all(step.converged for step in history.steps)


def test_a_shortened_step_shortens_the_next_and_holds_it(monkeypatch):
    """Steps longer than 0.5 are acceptable only at a quarter of their direction: the step
    of 1 is taken at 1/4, the next is 1/4 and held for ``step_hold`` = 1 accepted step,
    then it doubles to 1/2, 1 (shortened again), ...; no step is rejected."""
    _, history, accepted = _relax_a_fake_flow(
        monkeypatch, lambda tau: False, 0.1, NewtonOptions(step_hold=1),
        length=lambda tau: 0.25 if tau > 0.5 else 1.0)
    taus = [step.dt for step in history.steps if step.dt > 0]
    assert history.converged and accepted == 9
    assert all(step.converged for step in history.steps)
    assert taus[:6] == [1.0, 0.25, 0.25, 0.5, 1.0, 0.25]


@dataclass(eq=False)
class _FakeMarch:
    """A march whose pieces fail at the times in ``fails`` (the state then holds the last
    converged step, as :func:`~ngincompat.fem.stepping.solve_coupled` leaves it) and reach
    ``t_end`` from the last of them; or, with a ``script``, whose pieces fail in turn at its
    times (shared by the pieces). Every piece's start is logged in ``starts``, its shortest
    step in ``min_steps``."""

    problem: object
    fails: tuple
    starts: list
    name: str = "buckling"
    t_start: float = 0.0
    t_end: float = 10.0
    options: NewtonOptions = field(default_factory=lambda: NewtonOptions(min_step=0.1))
    sticky: bool = False
    min_steps: list = field(default_factory=list)
    script: list | None = None

    def run(self, progress):
        self.starts.append(self.t_start)
        self.min_steps.append(self.options.min_step)
        history = SolverHistory(t_reached=self.t_start)
        history.steps.append(StepRecord(t=self.t_start + 1.0, dt=1.0, converged=True,
                                        iterations=4))
        ahead = ([t for t in self.fails if t > self.t_start or self.sticky]
                 if self.script is None else self.script[:1])
        if self.script:
            self.script.pop(0)
        self.problem.state.vec[:] = ahead[0] if ahead else self.t_end
        if ahead:
            history.steps.append(StepRecord(t=ahead[0] + 0.05, dt=0.05, converged=False,
                                            iterations=3))
            raise ConvergenceError("the step fell below min_step", history=history,
                                   t_converged=ahead[0])
        history.converged, history.t_reached = True, self.t_end
        return history


class _FakeRelaxation:
    """A relaxation of two pseudo-time steps that moves the state by ``shift``, or fails."""

    def __init__(self, problem, shift=0.5, fail=False):
        self.problem, self.shift, self.fail = problem, shift, fail

    def run(self, progress):
        history = SolverHistory()
        history.steps = [StepRecord(t=tau, dt=tau, converged=True, iterations=1)
                         for tau in (0.25, 0.75)]
        self.problem.state.vec.data += self.shift * self.problem.state.vec
        if self.fail:
            raise ConvergenceError("no equilibrium", history=history)
        history.converged = True
        return history


def _snapping(fails, sticky=False, script=None, **relaxation):
    state = ngs.GridFunction(ngs.H1(cube(maxh=1.0), order=1))
    accepted = []
    problem = SimpleNamespace(state=state, accept_step=lambda: accepted.append(
        state.vec.FV().NumPy()[0]))
    starts = []
    stage = SnappingMarch(_FakeMarch(problem, fails, starts, sticky=sticky, script=script),
                          lambda: _FakeRelaxation(problem, **relaxation))
    return stage, problem, starts, accepted


def test_the_snapping_march_relaxes_where_its_step_fails_and_goes_on_from_there():
    """Pieces that fail at t = 3 and t = 6: each time the state of the last converged step
    is relaxed at that growth, made the viscous term's reference (the relaxed state), and
    the march starts again from that time; the history holds every piece's steps and the
    relaxations' steps at the march's time with dt = 0."""
    stage, problem, starts, accepted = _snapping((3.0, 6.0))
    history = stage.run(SILENT)
    assert history.converged and history.t_reached == 10.0
    assert stage.snaps == [3.0, 6.0] and starts == [0.0, 3.0, 6.0]
    assert accepted == [3.0 * 1.5, 6.0 * 1.5]
    assert [(s.t, s.dt) for s in history.steps] == [
        (1.0, 1.0), (3.05, 0.05), (3.0, 0.0), (3.0, 0.0),
        (4.0, 1.0), (6.05, 0.05), (6.0, 0.0), (6.0, 0.0), (7.0, 1.0)]
    assert history.newton_iterations == 3 * 4 + 4 * 1


def test_where_the_relaxation_fails_the_march_follows_the_snap_in_short_steps():
    """Where the relaxation finds no equilibrium, the state goes back to the march's last
    converged step (not the relaxation's last state), that state is the viscous term's
    reference again, and the march goes on from there with steps down to ``shortest``."""
    stage, problem, starts, accepted = _snapping((3.0,), fail=True)
    history = stage.run(SILENT)
    assert history.converged and starts == [0.0, 3.0] and accepted == [3.0]
    assert stage.march.min_steps == [0.1, stage.shortest] and stage.shortest == 1e-6
    assert np.all(problem.state.vec.FV().NumPy() == 10.0)
    assert [(s.t, s.dt) for s in history.steps][1:4] == [(3.05, 0.05), (3.0, 0.0), (3.0, 0.0)]


def test_a_march_that_fails_again_where_it_relaxed_goes_on_in_finer_steps_then_ends():
    """A piece that fails at the very time of the last relaxation has made no progress: the
    march is not relaxed again there but goes on in steps down to a quarter of the shortest
    it had, and a quarter of that, ...; below ``shortest`` it ends with its error."""
    stage, problem, starts, _ = _snapping((3.0,), sticky=True)
    stage.shortest = 1e-3
    with pytest.raises(ConvergenceError, match="min_step") as err:
        stage.run(SILENT)
    assert stage.snaps == [3.0] and starts == [0.0, 3.0, 3.0, 3.0, 3.0]
    np.testing.assert_allclose(stage.march.min_steps, [0.1, 0.1, 0.025, 0.00625, 0.0015625])
    assert err.value.t_converged == 3.0


def test_after_finer_steps_pass_the_snap_the_next_relaxation_gives_the_step_back():
    """The piece after the relaxation at 3 fails at 3 again: steps down to a quarter pass
    it, the march fails at 6, relaxes there, and goes on with its own shortest step."""
    stage, problem, starts, _ = _snapping((), script=[3.0, 3.0, 6.0])
    history = stage.run(SILENT)
    assert history.converged and stage.snaps == [3.0, 6.0]
    assert starts == [0.0, 3.0, 3.0, 6.0]
    np.testing.assert_allclose(stage.march.min_steps, [0.1, 0.1, 0.025, 0.1])


def test_a_step_shortened_below_min_step_ends_the_relaxation(monkeypatch):
    """Steps acceptable only at a quarter of their direction shorten tau fourfold each time:
    below ``min_step`` the relaxation gives up (where the energy no longer falls by more
    than round-off it would otherwise creep on in ever shorter steps)."""
    with pytest.raises(ConvergenceError, match="no equilibrium after 4 pseudo-time steps"):
        _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.01,
                           NewtonOptions(min_step=0.01), length=lambda tau: 0.25)


def test_a_saddle_is_left_along_its_unstable_mode(monkeypatch):
    """Newton's first equilibrium is a saddle (smallest eigenvalue -5): with ``kick`` the
    state moves along the unstable mode by ``kick`` at its largest dof and the flow goes on
    from there with its first step again, or, if that is shorter, half of eta / |omega|
    (here 0.1: eta 1, omega -5), a step in which the unstable mode grows; the next
    equilibrium is stable. Without ``kick`` the state goes back to before the saddle and the
    flow goes on with its step."""
    stage, history, accepted = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1,
                                                  eigenvalues=(-5.0, 1.0), kick=0.25)
    frozen = [i for i, step in enumerate(history.steps) if step.dt == 0]
    assert history.converged and len(frozen) == 2 and stage.eigenvalue == 1.0
    assert not history.steps[frozen[0]].converged
    assert "unstable: smallest eigenvalue -5" in history.steps[frozen[0]].reason
    assert history.steps[frozen[0] + 1].dt == pytest.approx(0.1)   # below eta / |omega|
    assert np.all(stage.problem.state.vec.FV().NumPy() == 0.25)
    _, gentle, _ = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1,
                                      eigenvalues=(-0.2, 1.0), kick=0.25)
    first = next(i for i, step in enumerate(gentle.steps) if step.dt == 0)
    assert gentle.steps[first + 1].dt == 1.0        # the first step, below 0.5 / 0.2
    _, plain, _ = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1,
                                     eigenvalues=(-5.0, 1.0))
    first = next(i for i, step in enumerate(plain.steps) if step.dt == 0)
    assert plain.converged and plain.steps[first + 1].dt == 2 * plain.steps[first - 1].dt
    with pytest.raises(ParameterError, match="kick"):
        RelaxationStage("release", None, None, viscosity=1.0, dt=1.0, kick=-1.0)


def test_a_saddle_met_again_is_left_the_other_way(monkeypatch):
    """Two saddles of the same energy (the flow came back to the one it was kicked off): the
    second kick goes the other way along the mode, so the state is back where the first
    kick started it (0), where two kicks the same way would have left it at 0.5; a third
    equilibrium is stable."""
    stage, history, _ = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1, repair=1.0,
                                           eigenvalues=(-5.0, -5.0, 1.0), kick=0.25)
    frozen = [step for step in history.steps if step.dt == 0]
    assert history.converged and len(frozen) == 3 and stage.eigenvalue == 1.0
    assert np.all(stage.problem.state.vec.FV().NumPy() == 0.0)
