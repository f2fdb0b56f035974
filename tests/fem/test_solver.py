"""ngincompat.fem.solver: Newton's convergence, line searches, stalls, the linear solvers."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem
from netgen.geom2d import unit_square

from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.fem import solver as solver_module
from ngincompat.fem.problem import displacement_space, wirebasket
from ngincompat.fem.solver import (
    BACKTRACKS,
    NewtonOptions,
    NewtonSolver,
    StepRecord,
    _at_roundoff,
    _stalled,
    resolve_linear_solver,
)
from ngincompat.fem.stepping import solve_growth
from ngincompat.scenes.cube import CubeScene


def _orders(residuals):
    """Estimated convergence orders q_k = log(r_k+1 / r_k) / log(r_k / r_k-1)."""
    r = np.log(np.asarray(residuals))
    return (r[2:] - r[1:-1]) / (r[1:-1] - r[:-2])


def test_newton_converges_quadratically_near_the_solution():
    """From the recorded residuals of the cube (order 3): once in the quadratic range the
    residual about squares each iteration, r_k+1 ~ C r_k^2 with C nearly constant while 1/r_k
    grows by orders of magnitude (linear convergence would make C grow like 1/r_k)."""
    problem, time = cube_problem(maxh=0.5, order=3)
    history = solve_growth(problem, time)
    (step,) = history.steps
    res = np.asarray(step.residuals)
    assert step.converged and res[-1] < 1e-10 * res[0]
    above_roundoff = res[res > 1e-13 * res[0]]
    assert len(above_roundoff) >= 4
    orders = _orders(above_roundoff[-3:])
    assert np.all(orders > 1.6), (res, orders)
    C = above_roundoff[2:] / above_roundoff[1:-1] ** 2
    growth_of_inverse = above_roundoff[1] / above_roundoff[-2]
    assert C.max() / C.min() < 0.1 * growth_of_inverse, (res, C)


def test_full_step_converges_where_plain_newton_fails():
    """theta = 1 + X1 t in one step from u = 0 at order 3: plain Newton (full steps, no
    predictor) leaves Je > 0 and produces NaN; the robust solver converges in one load step."""
    plain = NewtonOptions(predictor=False, line_search=False, min_step=1.0)
    problem, time = cube_problem(a=1.0, order=3)
    with pytest.raises(ConvergenceError, match="not finite"):
        solve_growth(problem, time, plain)
    problem, time = cube_problem(a=1.0, order=3)
    history = solve_growth(problem, time)
    assert history.converged
    assert len(history.steps) == 1
    assert history.newton_iterations <= 10


def test_line_search_alone_also_rescues_the_full_step():
    problem, time = cube_problem(a=1.0, order=3)
    history = solve_growth(problem, time, NewtonOptions(predictor=False))
    assert history.converged
    assert any(alpha < 1 for s in history.steps for alpha in s.line_search) or \
        len(history.steps) > 1


def test_finite_backtracking_takes_a_full_step_that_raises_the_residual():
    """The "finite" line search asks a trial state only to be finite: a state of higher energy
    and residual than the start is accepted by it and refused by "descent"; an inverted
    state (Je < 0 somewhere: infinite energy) by neither."""
    problem, time = cube_problem(a=1.0, order=2)
    time.Set(0.5)
    start = problem.u.vec.CreateVector()
    start.data = problem.u.vec
    verdicts = {}
    for backtrack in BACKTRACKS:
        solver = NewtonSolver(problem, NewtonOptions(backtrack=backtrack))
        problem.u.vec.data = start
        E, r = solver.energy(problem.u.vec), solver.residual().Norm()
        verdicts[backtrack] = []
        for u in ((0.3 * ngs.sin(3 * ngs.x), 0.2 * ngs.y * ngs.z, 0), (-2 * ngs.x, 0, 0)):
            problem.u.Set(ngs.CF(u))
            E_new = solver.energy(problem.u.vec)
            if np.isfinite(E_new):
                assert E_new > E and solver.residual().Norm() > r
            verdicts[backtrack].append(solver._acceptable(E, E_new, 1.0, -1.0, r, None)[0])
    assert verdicts == {"descent": [False, False], "finite": [True, False]}
    with pytest.raises(ParameterError, match="backtrack"):
        NewtonOptions(backtrack="armijo")


def test_a_newton_iteration_evaluates_the_residual_once(monkeypatch):
    """The line search's residual at the state it accepts is the next iteration's: each
    iteration assembles one residual (with "finite" it was three: the line search's merit,
    its finiteness test and the next iteration's), and both line searches converge to the
    same state."""
    problem, time = cube_problem(a=1.0, order=2)
    time.Set(0.5)
    start = problem.u.vec.CreateVector()
    start.data = problem.u.vec
    ends = []
    for backtrack in BACKTRACKS:
        problem.u.vec.data = start
        solver = NewtonSolver(problem, NewtonOptions(backtrack=backtrack))
        calls = []
        residual = solver.residual
        monkeypatch.setattr(solver, "residual",
                            lambda vec=None, calls=calls, residual=residual:
                            calls.append(1) or residual(vec))
        record = StepRecord(t=0.5, dt=0.5, converged=False)
        assert solver.minimise(record)
        assert record.iterations >= 3
        assert len(calls) == 1 + record.iterations, (backtrack, len(calls), record.iterations)
        assert record.residuals[-1] < 1e-9 * record.residuals[0]
        ends.append(problem.u.vec.FV().NumPy().copy())
    assert np.allclose(ends[0], ends[1], rtol=0, atol=1e-12 * np.abs(ends[0]).max())


def test_one_newton_step_is_taken_as_far_as_it_is_acceptable():
    """:meth:`NewtonSolver.step` (a pseudo-time step of a relaxation): from u = 0 under a
    small growth the full step is acceptable and leaves a residual far below the start's
    (Newton's, nearly linear there); under theta = 1 + X1 at order 3 the full step inverts
    elements, and the step is shortened to a finite state; where nothing is acceptable the
    state is given back exactly as it was."""
    def finite():
        return np.isfinite(solver.energy(problem.u.vec))

    for a, order, acceptable, length in ((0.02, 2, "finite", 1.0), (1.0, 3, "finite", "< 1"),
                                         (1.0, 3, "never", 0.0)):
        problem, time = cube_problem(a=a, order=order)
        time.Set(1.0)
        solver = NewtonSolver(problem, NewtonOptions(predictor=False, max_backtracks=8))
        start = problem.u.vec.FV().NumPy().copy()
        record = StepRecord(t=1.0, dt=1.0, converged=False)
        alpha = solver.step(record, finite if acceptable == "finite" else lambda: False)
        assert record.iterations == 1 and record.tangents == 1
        moved = np.abs(problem.u.vec.FV().NumPy() - start).max()
        if length == 1.0:
            assert alpha == 1.0
            assert solver.residual().Norm() < 1e-2 * record.residuals[0]
        elif length == "< 1":
            assert 2 ** -8 <= alpha < 1 and finite() and moved > 0
            problem.u.vec.FV().NumPy()[:] = start - (start - problem.u.vec.FV().NumPy()) / alpha
            assert not finite()                 # the full step inverts elements
        else:
            assert alpha == 0.0 and moved == 0.0 and "acceptable" in record.reason


def test_an_infinite_residual_at_the_start_is_no_convergence():
    """A growth so steep that the first residual overflows (theta = 1 + 1e300 X1 t) never
    counts as converged: the tolerance max(rtol r0, atol) is infinite there, and inf <= inf
    must not pass. The steps are cut to min_step and the solver raises, at t = 0."""
    problem, time = cube_problem(a=1e300, order=1)
    with pytest.raises(ConvergenceError) as err:
        solve_growth(problem, time, NewtonOptions(min_step=0.25))
    steps = err.value.history.steps
    assert steps and not any(s.converged for s in steps)
    assert all("not finite" in s.reason for s in steps)
    assert err.value.t_converged == 0.0 and time.Get() == 0.0


def test_reused_tangents_reach_the_same_state_with_fewer_assemblies():
    solutions = {}
    for reuse in (False, True):
        problem, time = cube_problem(order=3)
        history = solve_growth(problem, time, NewtonOptions(reuse_tangent=reuse))
        solutions[reuse] = (problem.strain_energy(), history)
    (e_full, h_full), (e_reuse, h_reuse) = solutions[False], solutions[True]
    assert h_full.tangent_assemblies == h_full.newton_iterations
    assert h_reuse.tangent_assemblies < h_full.tangent_assemblies
    assert e_reuse == pytest.approx(e_full, rel=1e-9)


#: Residual norms of two steps of the folding bilayer's march at 65.7 days (curved axons):
#: one that cycles without converging in 12 iterations, and one that converges.
CYCLING = [1.5e-4, 2.2e-4, 1.2e-5, 3.0e-5, 3.2e-5, 1.4e-4, 8.8e-6, 2.9e-5, 2.6e-4, 4.6e-2,
           4.5e-2, 1.4e-2, 1.0e-1]
CONVERGING = [2.7e-4, 1.7e-3, 9.8e-6, 1.5e-6, 1.6e-11, 1.2e-15]
SLOW = [1.6e-4, 4.2e-3, 9.9e-05, 4.3e-3, 7.0e-5, 1.0e-1, 4.9e-5, 8.0e-7, 2.0e-8, 1.0e-10]
#: A growth step of the folding bilayer at 80,794 unknowns: its residual falls to the
#: round-off of the assembly (2.9e-14), above 1e-9 of its start (1.6e-14), and stays.
ROUNDOFF_FLOOR = [1.62e-05, 1.64e-04, 6.55e-10, 2.91e-14, 2.83e-14, 2.80e-14, 2.92e-14]


@pytest.mark.parametrize("stall, iteration", [(3, 5), (2, 5), (4, 10)])
def test_a_step_stalls_once_its_residual_stays_above_its_best_for_stall_iterations(
        stall, iteration):
    stalled = [k for k in range(1, len(CYCLING) + 1) if _stalled(CYCLING[:k + 1], stall)]
    assert stalled and stalled[0] == iteration


def test_a_converging_step_never_stalls_nor_any_step_without_stall():
    for k in range(1, len(CONVERGING)):
        assert not _stalled(CONVERGING[:k + 1], 3)
    for k in range(1, len(SLOW)):          # above its best for 2 iterations only
        assert not _stalled(SLOW[:k + 1], 3)
        assert not _stalled(CYCLING[:k + 1], 0)
    with pytest.raises(ParameterError, match="stall"):
        NewtonOptions(stall=-1)


def test_a_residual_that_stops_falling_at_round_off_is_converged():
    """The residual at the round-off floor is converged at the first iteration that does not
    lower it (the fourth); a quadratically converging, a slow and a cycling step are not
    taken for one at any iteration."""
    at = [k for k in range(1, len(ROUNDOFF_FLOOR)) if _at_roundoff(ROUNDOFF_FLOOR[:k + 1])]
    assert at and at[0] == 4
    for residuals in (CONVERGING, SLOW, CYCLING):
        assert not any(_at_roundoff(residuals[:k + 1]) for k in range(1, len(residuals)))


#: The cube of the distributed runs (tests/base/test_parallel.py): 3 hexahedra per edge.
CUBE = {"order": 2, "maxh": 0.34, "elements": "hex", "outputs": "none"}


@pytest.mark.parametrize("linear_solver", ["cg", "gmres"])
def test_newton_with_bddc_matches_the_direct_solver(linear_solver):
    settings = CUBE
    direct = CubeScene(**settings).run()
    iterative = CubeScene(**settings, linear_solver=linear_solver).run()
    assert iterative.metrics["strain_energy"] == pytest.approx(
        direct.metrics["strain_energy"], rel=1e-10)
    steps = iterative.solver["growth"].steps
    assert [len(s.linear_iterations) for s in steps] == [s.iterations for s in steps]
    assert all(n >= 3 for s in steps for n in s.linear_iterations)
    assert iterative.newton_iterations == direct.newton_iterations


def test_auto_takes_the_problems_iterative_solver_from_its_size_on(unit_cube_tet):
    """"auto" is the direct solver below ITERATIVE_NDOF unknowns and the problem's iterative
    solver from there on; a problem without one (a non-symmetric tangent) stays direct; a
    named solver is taken as it is."""
    n = solver_module.ITERATIVE_NDOF
    assert resolve_linear_solver("auto", unit_cube_tet, n - 1, "cg") == "direct"
    assert resolve_linear_solver("auto", unit_cube_tet, n, "cg") == "cg"
    assert resolve_linear_solver("auto", unit_cube_tet, 10 * n, None) == "direct"
    assert resolve_linear_solver("gmres", unit_cube_tet, 1, None) == "gmres"
    assert resolve_linear_solver("direct", unit_cube_tet, 10 * n, "cg") == "direct"


def test_a_problem_above_the_switch_is_solved_by_cg_with_the_direct_answer(monkeypatch):
    """With the switch below the cube's size, "auto" means CG with the multigrid and Newton
    solves by it (every direction a CG solve); its metrics are the direct solver's within
    1e-6. The mixed formulation stays direct under "auto"; asked for by name, CG with BDDC
    and CG with the multigrid solve its condensed tangent to the direct answer too."""
    monkeypatch.setattr(solver_module, "ITERATIVE_NDOF", 100)
    assert CubeScene(**CUBE).build().mechanics().linear_solver == "amg"
    for formulation, solver in (("displacement", "auto"), ("mixed", "cg"), ("mixed", "amg")):
        settings = {**CUBE, "formulation": formulation, "nu": 0.49}
        direct = CubeScene(**settings, linear_solver="direct").run()
        switched = CubeScene(**settings, linear_solver=solver).run()
        steps = switched.solver["growth"].steps
        assert all(len(s.linear_iterations) == s.iterations > 0 for s in steps)
        assert not any(s.linear_iterations for s in direct.solver["growth"].steps)
        compared = [k for k, v in direct.metrics.items()
                    if isinstance(v, float) and abs(v) > 1e-12]
        assert {"strain_energy", "max_principal_stress"} <= set(compared)
        for key in compared:
            assert switched.metrics[key] == pytest.approx(direct.metrics[key], rel=1e-6), key
    mixed = CubeScene(**{**CUBE, "formulation": "mixed", "nu": 0.49}).run()
    assert not any(s.linear_iterations for s in mixed.solver["growth"].steps)


def test_linear_solver_is_checked():
    with pytest.raises(ParameterError, match="linear_solver"):
        CubeScene(linear_solver="mumps")


def test_bddc_on_the_vertices_alone_meets_the_same_equilibrium_in_more_iterations():
    """BDDC's coarse space ``coarse``: the vertices alone (a coarse problem of three
    unknowns per vertex, which a distributed run factorises on rank 0) give the strain
    energy of the default vertices and edges, with more CG iterations per direction."""
    edges = CubeScene(**CUBE, linear_solver="cg").run()
    vertices = CubeScene(**CUBE, linear_solver="cg", coarse="vertices").run()
    assert vertices.metrics["strain_energy"] == pytest.approx(
        edges.metrics["strain_energy"], rel=1e-10)
    counts = [[n for s in run.solver["growth"].steps for n in s.linear_iterations]
              for run in (edges, vertices)]
    assert min(counts[1]) > max(counts[0]) >= 3


@pytest.mark.parametrize("coarse", ["edges", "vertices"])
def test_the_coarse_space_is_the_wirebasket_of_the_displacement_space(unit_cube_tet, coarse):
    """The wirebasket of VectorH1 of order 2 on tetrahedra: every vertex and edge dof
    ("edges"), or three dofs per vertex ("vertices"); another name is refused."""
    space = displacement_space(unit_cube_tet, 2, coarse=coarse)
    types = [space.CouplingType(i) for i in range(space.ndof)]
    basket = types.count(ngs.COUPLING_TYPE.WIREBASKET_DOF)
    vertices = 3 * unit_cube_tet.nv
    assert basket == (space.ndof if coarse == "edges" else vertices)
    with pytest.raises(ParameterError, match="coarse"):
        displacement_space(unit_cube_tet, 2, coarse="faces")


@pytest.mark.parametrize("coarse", ["edges", "vertices"])
def test_the_coarse_space_of_a_section_and_no_warning_of_ngsolve(coarse, capfd):
    """On a mesh of triangles (NGSolve's default wirebasket there: the vertices alone) the
    edges are added for "edges"; the scalar space of the compatible fit gets the same; and
    building the spaces prints nothing (a flag VectorH1 does not document did, every run)."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.3))
    capfd.readouterr()
    space = displacement_space(mesh, 2, coarse=coarse)
    scalar = wirebasket(ngs.H1(mesh, order=3), coarse)
    for fes, per_vertex in ((space, 2), (scalar, 1)):
        types = [fes.CouplingType(i) for i in range(fes.ndof)]
        basket = types.count(ngs.COUPLING_TYPE.WIREBASKET_DOF)
        edges = per_vertex * (fes.globalorder - 1) * mesh.nedge
        assert basket == per_vertex * mesh.nv + (edges if coarse == "edges" else 0)
    assert capfd.readouterr() == ("", "")


def test_a_step_whose_linear_solves_stop_at_their_limit_says_so():
    """CG held to 2 iterations per direction gives directions that are not the tangent's:
    the step fails, and its reason names the solves that stopped above their tolerance; with
    CG converged the same step does not."""
    problem, time = cube_problem(a=0.5)
    time.Set(1.0)
    record = StepRecord(t=1.0, dt=1.0, converged=False)
    limited = NewtonOptions(max_iter=4, linear_solver="cg", krylov_maxiter=2)
    assert not NewtonSolver(problem, limited).minimise(record)
    assert "stopped at krylov_maxiter = 2 iterations above their tolerance" in record.reason
    problem.u.vec[:] = 0.0
    record = StepRecord(t=1.0, dt=1.0, converged=False)
    assert NewtonSolver(problem, NewtonOptions(max_iter=30, linear_solver="cg")).minimise(record)
    assert "krylov_maxiter" not in record.reason
