"""ngincompat.fem.stepping: adaptive steps cut, doubled and held; the last converged state kept."""

import numpy as np
import pytest
from conftest import cube_problem
from fem.test_coupled import LAW, _stretched_bar

from ngincompat.errors import ConvergenceError, Interrupted
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_coupled, solve_growth


class Recorder:
    """A progress whose stage report records what it hears, and raises KeyboardInterrupt
    (a Ctrl-C) when told of the step that reaches ``interrupt_at``."""

    def __init__(self, interrupt_at=None):
        self.steps, self.cuts, self.closed, self.interrupt_at = [], [], 0, interrupt_at

    def march(self, stage, t_start, t_end, unit=""):
        return self

    def step(self, t, dt, iterations):
        self.steps.append(t)
        if self.interrupt_at is not None and t >= self.interrupt_at - 1e-12:
            raise KeyboardInterrupt

    def cut(self, t, dt, reason):
        self.cuts.append(t + dt)

    def close(self):
        self.closed += 1


def test_failed_step_is_cut_and_last_converged_state_is_kept():
    """With too few Newton iterations allowed, steps are cut; below min_step the solver raises
    and the displacement and time hold the last converged state."""
    problem, time = cube_problem(a=1.0, order=2)
    options = NewtonOptions(max_iter=2, min_step=0.2, predictor=False)
    with pytest.raises(ConvergenceError) as err:
        solve_growth(problem, time, options)
    history = err.value.history
    assert [s.converged for s in history.steps].count(False) >= 2
    t_ok = err.value.t_converged
    assert time.Get() == pytest.approx(t_ok)
    assert t_ok == pytest.approx(history.t_reached)
    # the kept state is an equilibrium at t_ok: its residual is tiny
    r = problem.u.vec.CreateVector()
    problem.form.Apply(problem.u.vec, r)
    free = problem.freedofs
    worst = max(abs(r[i]) for i in range(len(r)) if free[i])
    assert worst < 1e-8


def test_a_march_ends_where_on_step_says_so():
    """on_step returning True (an instability detected) ends the march there, converged."""
    problem, _ = _stretched_bar(LAW)
    seen = []

    def on_step(t):
        seen.append(t)
        return t >= 0.5

    history = solve_coupled(problem, t_end=2.0, dt=0.25, on_step=on_step)
    assert history.converged and history.t_reached == pytest.approx(0.5)
    assert seen == pytest.approx([0.25, 0.5])


def test_a_step_doubles_after_at_most_step_up_newton_iterations():
    """The adaptive march doubles the next step (up to max_step) after a step that took at
    most ``step_up`` Newton iterations, and keeps it otherwise."""
    def steps(**options):
        problem, _ = _stretched_bar(LAW)
        history = solve_coupled(problem, t_end=2.0, dt=0.25,
                                options=NewtonOptions(max_iter=20, **options))
        assert history.converged and all(s.iterations > 1 for s in history.steps)
        return [s.dt for s in history.steps]

    assert steps(step_up=0) == pytest.approx([0.25] * 8)
    assert steps(step_up=20) == pytest.approx([0.25, 0.5, 1.0, 0.25])
    assert steps(step_up=20, max_step=0.5) == pytest.approx([0.25, 0.5, 0.5, 0.5, 0.25])


@pytest.mark.parametrize("hold", [0, 1, 3])
def test_after_a_cut_step_hold_converged_steps_keep_the_step(hold):
    """A step of 0.8 needs 5 Newton iterations to 1e-12, one of 0.4 needs 4: with at most 4
    the first step fails and is halved; the next ``step_hold`` converged steps keep 0.4, the
    one after them doubles it (``step_up`` = 4)."""
    problem, _ = _stretched_bar(LAW)
    solve_coupled(problem, t_end=0.01, dt=0.01, options=NewtonOptions(max_iter=20))
    history = solve_coupled(problem, t_start=0.01, t_end=0.01 + 0.8 * (hold + 2), dt=0.8,
                            options=NewtonOptions(max_iter=4, rtol=1e-12, step_hold=hold))
    steps = [(s.dt, s.converged) for s in history.steps]
    assert history.converged and steps[0] == (pytest.approx(0.8), False)
    assert steps[1:hold + 3] == [(pytest.approx(0.4), True)] * (hold + 1) + [
        (pytest.approx(0.8), True)]


def test_the_load_starts_in_equal_steps_and_doubles_after_easy_ones():
    """``steps`` = 4: the first step is a quarter of the load; with ``step_up`` = 0 every
    step stays a quarter, with a large ``step_up`` each doubles after the one before, the last
    cut to end at t_end. The growth time ends at t_end either way."""
    for step_up, expected in ((0, [0.25] * 4), (100, [0.25, 0.5, 0.25])):
        problem, time = cube_problem(order=1)
        history = solve_growth(problem, time, NewtonOptions(steps=4, step_up=step_up))
        assert history.converged and history.t_reached == pytest.approx(1.0)
        assert [s.dt for s in history.steps] == pytest.approx(expected)
        assert time.Get() == pytest.approx(1.0)


def test_the_report_hears_of_every_converged_and_every_cut_step_and_is_closed():
    problem, time = cube_problem(a=1.0, order=2)
    report = Recorder()
    try:
        history = solve_growth(problem, time, NewtonOptions(max_iter=3, min_step=0.1,
                                                            predictor=False), progress=report)
    except ConvergenceError as err:
        history = err.history
    assert report.cuts, "the march was meant to cut steps"
    assert report.steps == pytest.approx([s.t for s in history.steps if s.converged])
    assert report.cuts == pytest.approx([s.t for s in history.steps if not s.converged])
    assert report.closed == 1


def test_an_interrupted_load_march_keeps_the_last_converged_state_and_time():
    """Ctrl-C after the step to t = 0.5 of four: Interrupted, at t = 0.5, with the state and
    growth time of an uninterrupted march to 0.5, and the report closed."""
    reference, reference_time = cube_problem(order=1)
    solve_growth(reference, reference_time, NewtonOptions(steps=2, step_up=0), t_end=0.5)
    problem, time = cube_problem(order=1)
    report = Recorder(interrupt_at=0.5)
    with pytest.raises(Interrupted, match="interrupted at t = 0.5") as err:
        solve_growth(problem, time, NewtonOptions(steps=4, step_up=0), progress=report)
    assert err.value.t_converged == pytest.approx(0.5)
    assert [s.converged for s in err.value.history.steps] == [True, True]
    assert time.Get() == pytest.approx(0.5)
    np.testing.assert_allclose(problem.u.vec.FV().NumPy(), reference.u.vec.FV().NumPy(),
                               rtol=1e-8, atol=1e-12)
    assert report.closed == 1


def test_an_interrupted_time_march_restores_the_loads_of_the_last_converged_time():
    """Ctrl-C while the loads of the step to t = 0.75 are set (``schedule``): Interrupted at
    t = 0.5, the state that of the march to 0.5, and the loads set back for t = 0.5."""
    options = NewtonOptions(max_iter=20, step_up=0)
    reference, _ = _stretched_bar(LAW)
    solve_coupled(reference, t_end=0.5, dt=0.25, options=options)
    problem, _ = _stretched_bar(LAW)
    scheduled = []

    def schedule(t):
        scheduled.append(t)
        if len(scheduled) == 3:         # the third step's loads
            raise KeyboardInterrupt

    with pytest.raises(Interrupted) as err:
        solve_coupled(problem, t_end=2.0, dt=0.25, options=options, schedule=schedule)
    assert err.value.t_converged == pytest.approx(0.5)
    assert scheduled == pytest.approx([0.25, 0.5, 0.75, 0.5])
    np.testing.assert_allclose(problem.state.vec.FV().NumPy(),
                               reference.state.vec.FV().NumPy(), rtol=1e-10, atol=1e-14)


def test_a_march_interrupted_while_a_step_is_accepted_keeps_that_steps_state():
    """Ctrl-C inside ``on_step`` after the step to t = 0.75 (while a checkpoint is written):
    Interrupted at t = 0.75 with the state of an uninterrupted march to 0.75, not the state
    of the step before under the later time."""
    options = NewtonOptions(max_iter=20, step_up=0)
    reference, _ = _stretched_bar(LAW)
    solve_coupled(reference, t_end=0.75, dt=0.25, options=options)
    problem, _ = _stretched_bar(LAW)

    def on_step(t):
        if t >= 0.75 - 1e-12:
            raise KeyboardInterrupt
        return False

    with pytest.raises(Interrupted) as err:
        solve_coupled(problem, t_end=2.0, dt=0.25, options=options, on_step=on_step)
    assert err.value.t_converged == pytest.approx(0.75)
    np.testing.assert_allclose(problem.state.vec.FV().NumPy(),
                               reference.state.vec.FV().NumPy(), rtol=1e-10, atol=1e-14)
