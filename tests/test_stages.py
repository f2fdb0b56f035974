"""Stages of a load history: prescribed growth in parts, the coupled stage's loads, and its
checkpoints."""

from dataclasses import dataclass, field
from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem

from geometries import cube
from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.solver import NewtonOptions, SolverHistory, StepRecord
from ngincompat.fem.stages import (
    CoupledStage,
    PrescribedGrowthStage,
    RelaxationStage,
    SnappingMarch,
    restore_checkpoint,
    save_checkpoint,
)
from ngincompat.fem.terms import GrowthEnergy, VolumeConstraint
from ngincompat.mechanics.laws import StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.progress import SILENT


def test_growth_in_two_stages_reaches_the_state_of_one():
    """t from 0 to 1 in one stage, or from 0 to 0.4 then 0.4 to 1: the same equilibrium."""
    problem, time = cube_problem(order=2)
    PrescribedGrowthStage("growth", problem, time).run(SILENT)
    one = problem.strain_energy()
    problem, time = cube_problem(order=2)
    first = PrescribedGrowthStage("first", problem, time, t_end=0.4).run(SILENT)
    assert first.t_reached == pytest.approx(0.4) and time.Get() == pytest.approx(0.4)
    second = PrescribedGrowthStage("second", problem, time, t_start=0.4).run(SILENT)
    assert second.converged
    assert [(s.t, s.dt) for s in second.steps] == [(1.0, pytest.approx(0.6))]
    assert problem.strain_energy() == pytest.approx(one, rel=1e-9)
    assert one > 1e-8


def test_growth_from_a_start_state_is_solved_at_once_and_falls_back_to_load_steps():
    """With a start, the equilibrium at t_end is solved from it at once: the unique
    equilibrium of the load-stepped path, in one step. Where Newton fails from the start,
    the state before the stage is restored and the growth applied in load steps."""
    problem, time = cube_problem(order=2)
    stepped = PrescribedGrowthStage("growth", problem, time).run(SILENT)
    reference = problem.u.vec.CreateVector()
    reference.data = problem.u.vec

    # a start near the equilibrium: 90 % of its displacement; the rigid-body pins keep
    # the start's values, so the two states are compared by C = F^T F
    equilibrium = ngs.GridFunction(problem.u.space)
    equilibrium.vec.data = reference
    start = ngs.GridFunction(problem.u.space)
    start.vec.data = 0.9 * reference
    problem.u.vec[:] = 0.0
    time.Set(0.0)
    direct = PrescribedGrowthStage("growth", problem, time, start=start).run(SILENT)
    assert direct.converged and len(direct.steps) == 1
    assert direct.steps[0].t == 1.0 and direct.steps[0].dt == 1.0

    def cauchy_green(u):
        F = ngs.Id(3) + ngs.Grad(u)
        return F.trans * F

    change = cauchy_green(problem.u) - cauchy_green(equilibrium)
    strain = cauchy_green(equilibrium) - ngs.Id(3)
    mesh = problem.u.space.mesh
    assert ngs.Integrate(ngs.InnerProduct(change, change), mesh) <= \
        1e-16 * ngs.Integrate(ngs.InnerProduct(strain, strain), mesh)

    # Newton limited to one iteration cannot converge from u = 0 at full growth
    problem, time = cube_problem(order=2)
    zero = ngs.CoefficientFunction((0, 0, 0))
    fallback = PrescribedGrowthStage("growth", problem, time, start=zero,
                                     start_options=NewtonOptions(max_iter=1)).run(SILENT)
    assert not fallback.steps[0].converged and fallback.steps[0].dt == 1.0
    assert fallback.converged and fallback.t_reached == pytest.approx(1.0)
    assert [(s.t, s.iterations) for s in fallback.steps[1:]] == \
        [(s.t, s.iterations) for s in stepped.steps]
    difference = problem.u.vec.CreateVector()
    difference.data = problem.u.vec - reference
    assert difference.Norm() <= 1e-12 * reference.Norm()


def _holder():
    """A stand-in for a term that holds a volume: its target and the lifts asked for."""
    holder = SimpleNamespace(target=ngs.Parameter(0.0), lifts=[])

    def set_target(volume, lift=False):
        holder.target.Set(volume)
        holder.lifts.append(lift)

    holder.set_target = set_target
    return holder


def test_coupled_stage_drives_the_volume_linearly_and_freezes_growth():
    problem, holder = SimpleNamespace(dt=ngs.Parameter(0.25)), _holder()
    stage = CoupledStage("inflation", problem, t_end=3.0, dt=1.0, t_start=1.0, grow=False,
                         volume=(10.0, 50.0), holder=holder)
    for t, expected in ((1.0, 10.0), (2.0, 30.0), (2.5, 40.0), (3.0, 50.0)):
        stage.load(t)
        assert holder.target.Get() == pytest.approx(expected)
    assert problem.dt.Get() == 0.0
    # the state moves with the expander only going forward, not back after a failed step
    stage.load(2.0)
    assert holder.lifts == [False, True, True, True, False]
    growing = SimpleNamespace(dt=ngs.Parameter(0.25))
    CoupledStage("hold", growing, t_end=7.0, dt=0.5).load(3.0)
    assert growing.dt.Get() == 0.25


def test_coupled_stage_ramps_a_dead_traction_after_its_start():
    """``traction`` scales the problem's dead load linearly over the stage (the contact
    expander's deflation: 1 -> 0), and ``start`` runs once, before the first load."""
    problem = SimpleNamespace(dt=ngs.Parameter(0.25))
    load = SimpleNamespace(scale=ngs.Parameter(0.0))
    started = []

    class Started(Exception):
        pass

    def start():
        started.append(load.scale.Get())
        raise Started

    stage = CoupledStage("deflation", problem, t_end=1.0, dt=0.25, grow=False,
                         traction=(1.0, 0.0), dead_load=load, start=start)
    with pytest.raises(Started):
        stage.run(SILENT)
    assert started == [0.0]
    for t, expected in ((0.0, 1.0), (0.25, 0.75), (0.6, 0.4), (1.0, 0.0)):
        stage.load(t)
        assert load.scale.Get() == pytest.approx(expected)


@pytest.mark.parametrize("missing", [dict(volume=(0.0, 1.0)), dict(traction=(1.0, 0.0))])
def test_a_coupled_stage_that_drives_a_load_needs_its_term(missing):
    with pytest.raises(ParameterError, match="^holder = None|^dead_load = None"):
        CoupledStage("stage", SimpleNamespace(dt=ngs.Parameter(0.0)), t_end=1.0, dt=1.0,
                     **missing)


def _coupled(mesh, order=1):
    """A coupled problem with growth and a volume held under the cube's bottom face."""
    growth = GrowthEnergy("isotropic", None, StrainDrivenLaw(tau=1.0, theta_max=2.0),
                          NeoHookean.from_nu(1.0, 0.3))
    volume = VolumeConstraint("bottom")
    return CoupledProblem(mesh, [growth, volume], order=order, dirichlet="left"), growth, volume


def test_checkpoint_restores_the_state_and_refuses_another_mesh(tmp_path):
    mesh = cube(maxh=1.0)
    problem, growth, volume = _coupled(mesh)
    rng = np.random.default_rng(0)
    problem.state.vec.FV().NumPy()[:] = rng.normal(size=problem.fes.ndof)
    growth.theta_old.vec.FV().NumPy()[:] = 1 + rng.uniform(size=growth.theta_old.space.ndof)
    volume.target.Set(41.5)
    path = tmp_path / "checkpoint.npz"
    assert restore_checkpoint(problem, path) is None
    save_checkpoint(problem, path, 2.5)
    fresh, fresh_growth, fresh_volume = _coupled(mesh)
    assert restore_checkpoint(fresh, path) == 2.5
    assert fresh_volume.target.Get() == 41.5     # an expander's controlled size
    np.testing.assert_array_equal(fresh.state.vec.FV().NumPy(), problem.state.vec.FV().NumPy())
    np.testing.assert_array_equal(fresh_growth.theta_old.vec.FV().NumPy(),
                                  growth.theta_old.vec.FV().NumPy())
    with pytest.raises(ParameterError, match="does not fit this mesh and order"):
        restore_checkpoint(_coupled(mesh, order=2)[0], path)


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
    from ngincompat.fem import stages

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
    monkeypatch.setattr(stages, "NewtonSolver", Flow)
    monkeypatch.setattr(stages.buckling, "smallest_eigenpairs", smallest)
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
    ``t_end`` from the last of them; every piece's start is logged in ``starts``."""

    problem: object
    fails: tuple
    starts: list
    name: str = "buckling"
    t_start: float = 0.0
    t_end: float = 10.0
    options: NewtonOptions = field(default_factory=lambda: NewtonOptions(min_step=0.1))
    sticky: bool = False
    min_steps: list = field(default_factory=list)

    def run(self, progress):
        self.starts.append(self.t_start)
        self.min_steps.append(self.options.min_step)
        history = SolverHistory(t_reached=self.t_start)
        history.steps.append(StepRecord(t=self.t_start + 1.0, dt=1.0, converged=True,
                                        iterations=4))
        ahead = [t for t in self.fails if t > self.t_start or self.sticky]
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


def _snapping(fails, sticky=False, **relaxation):
    state = ngs.GridFunction(ngs.H1(cube(maxh=1.0), order=1))
    accepted = []
    problem = SimpleNamespace(state=state, accept_step=lambda: accepted.append(
        state.vec.FV().NumPy()[0]))
    starts = []
    stage = SnappingMarch(_FakeMarch(problem, fails, starts, sticky=sticky),
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


def test_a_march_that_fails_again_where_it_relaxed_ends_there():
    """A piece that fails at the very time of the last relaxation has made no progress: the
    march ends with its error instead of relaxing the same state again."""
    stage, problem, starts, _ = _snapping((3.0,), sticky=True)
    with pytest.raises(ConvergenceError, match="min_step") as err:
        stage.run(SILENT)
    assert stage.snaps == [3.0] and starts == [0.0, 3.0]
    assert err.value.t_converged == 3.0


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
    from there with its first step again; the next equilibrium is stable. Without ``kick``
    the state goes back to before the saddle and the flow goes on with its step."""
    stage, history, accepted = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1,
                                                  eigenvalues=(-5.0, 1.0), kick=0.25)
    frozen = [i for i, step in enumerate(history.steps) if step.dt == 0]
    assert history.converged and len(frozen) == 2 and stage.eigenvalue == 1.0
    assert not history.steps[frozen[0]].converged
    assert "unstable: smallest eigenvalue -5" in history.steps[frozen[0]].reason
    assert history.steps[frozen[0] + 1].dt == 1.0       # the first step again
    assert np.all(stage.problem.state.vec.FV().NumPy() == 0.25)
    _, plain, _ = _relax_a_fake_flow(monkeypatch, lambda tau: False, 0.1,
                                     eigenvalues=(-5.0, 1.0))
    first = next(i for i, step in enumerate(plain.steps) if step.dt == 0)
    assert plain.converged and plain.steps[first + 1].dt == 2 * plain.steps[first - 1].dt
    with pytest.raises(ParameterError, match="kick"):
        RelaxationStage("release", None, None, viscosity=1.0, dt=1.0, kick=-1.0)
