"""ngincompat.scenes.folding.numerics: Newton's options of every stage, the linear solver and
extrapolation they choose, and the analysis' onset that places the steps."""

from types import SimpleNamespace

import numpy as np
import pytest
from scenes.folding.test_scene import SMALL

from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_coupled
from ngincompat.scenes.folding import FoldingScene, numerics
from ngincompat.scenes.folding import case as folding_case


def test_symmetric_gmres_newton_matches_the_lu_factorisation_on_coupled_growth():
    """Newton on the flat branch of a small bilayer with curved axons (a tangent that is not
    symmetric: 0.6 % of its norm on the default bilayer) reaches the same states in the same
    iterations with "symmetric-gmres" (GMRES preconditioned by the Cholesky factorisation of
    the tangent's symmetric part) as with UMFPACK's LU, and GMRES does iterate (the
    preconditioner is not the tangent's inverse)."""
    states, histories = [], []
    for solver in ("direct", "symmetric-gmres"):
        case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1,
                               "axons": "curved"}).build()
        options = NewtonOptions(max_iter=12, line_search=False, linear_solver=solver)
        histories.append(solve_coupled(case.problem, 2.5, 1.25, options))
        states.append(case.problem.state.vec.FV().NumPy().copy())
    direct, gmres = histories
    assert np.linalg.norm(states[1] - states[0]) <= 1e-10 * np.linalg.norm(states[0])
    assert [s.iterations for s in gmres.steps] == [s.iterations for s in direct.steps]
    linear = [n for s in gmres.steps for n in s.linear_iterations]
    assert linear and 2 <= max(linear) <= 30


def test_extrapolated_steps_reach_the_same_states_in_fewer_iterations():
    """Started from the extrapolation in time of the last two converged states, Newton on the
    flat branch of a small bilayer with curved axons reaches the same states (to Newton's
    tolerance) in fewer iterations from the second step on."""
    states, iterations = [], []
    for extrapolate in (False, True):
        case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1,
                               "axons": "curved"}).build()
        options = NewtonOptions(max_iter=12, line_search=False, max_step=2.5,
                                extrapolate=extrapolate)
        history = solve_coupled(case.problem, 10.0, 2.5, options)
        states.append(case.problem.state.vec.FV().NumPy().copy())
        iterations.append([s.iterations for s in history.steps])
    assert np.linalg.norm(states[1] - states[0]) <= 1e-8 * np.linalg.norm(states[0])
    plain, extrapolated = iterations
    assert len(plain) == len(extrapolated) == 4 and extrapolated[0] == plain[0]
    assert all(e < p for e, p in zip(extrapolated[1:], plain[1:], strict=True))


def test_the_newton_options_of_every_stage_and_a_stages_own():
    options = numerics.newton()
    assert (options.max_iter, options.linear_solver, options.krylov_maxiter,
            options.step_hold) == (12, numerics.LINEAR_SOLVER, numerics.KRYLOV_MAXITER,
                                   numerics.STEP_HOLD)
    own = numerics.newton(max_iter=30, step_hold=0, rtol=1e-6)
    assert (own.max_iter, own.step_hold, own.rtol) == (30, 0, 1e-6)
    assert own.linear_solver == numerics.LINEAR_SOLVER


def test_the_placing_onset_is_computed_once_per_bilayer_and_none_without_one(monkeypatch):
    """Scanned in theta_c steps of 0.02; the variants of a scene in its steps or axons share
    the bilayer and so one analysis; an analysis that finds no onset gives None."""
    calls = []

    def analysis(bilayer, length, resolution):
        calls.append((bilayer, length, resolution))
        if length > 10:
            raise ValueError("no onset in the scanned range")
        return SimpleNamespace(growth=1.25)

    numerics.placing_onset.cache_clear()
    monkeypatch.setattr(numerics, "onset", analysis)
    try:
        bilayer = FoldingScene().bifurcation_bilayer()
        assert numerics.placing_onset(bilayer, 3.0) == 1.25
        variant = FoldingScene(axons="none", dt=5.0, onset_dt=5.0).bifurcation_bilayer()
        assert numerics.placing_onset(variant, 3.0) == 1.25
        assert calls == [(bilayer, 3.0, 0.02)]
        assert numerics.placing_onset(bilayer, 20.0) is None
        assert len(calls) == 2
    finally:
        numerics.placing_onset.cache_clear()


def test_the_stages_solve_with_these_settings(monkeypatch):
    """The perfect branch (no analysis' onset: no approach), the march and the relaxations
    take Newton's options of :func:`newton` with the march's tolerance, its stall and its
    snap step, and the relaxations' switch, budget and eigenpairs."""
    monkeypatch.setattr(folding_case, "placing_onset", lambda bilayer, length: None)
    case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2}, buckle=False).build()
    (perfect,) = case.stages()
    assert perfect.options.linear_solver == numerics.LINEAR_SOLVER
    assert perfect.options.krylov_maxiter == numerics.KRYLOV_MAXITER
    assert perfect.options.max_step == case.scene.onset_dt and perfect.options.extrapolate
    case.series["perfect"].update(t=[10.0], eigenvalue=[-1.0])
    march = case.buckling_stage().march.options
    assert (march.rtol, march.stall, march.step_hold) == (numerics.MARCH_RTOL, numerics.STALL,
                                                          numerics.STEP_HOLD)
    assert march.min_step == pytest.approx(march.max_step * numerics.SNAP_STEP)
    relaxation = case.relaxation("equilibrium", case.problem, case.viscous)
    assert (relaxation.switch, relaxation.max_steps, relaxation.eigenpairs) == (
        numerics.RELAXATION_SWITCH, numerics.RELAXATION_STEPS, numerics.EIGENPAIRS)
    assert relaxation.options.linear_solver == numerics.LINEAR_SOLVER
    assert relaxation.viscosity == case.eta == case.scene.viscosity * case.scene.mu_white
