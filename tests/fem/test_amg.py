"""ngincompat.fem.amg: CG preconditioned by smoothed-aggregation multigrid built from the rigid
motions."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem

from ngincompat.fem.amg import SmoothedAggregation
from ngincompat.fem.rigid import rigid_body_modes
from ngincompat.fem.solver import NewtonSolver
from ngincompat.scenes.cube import CubeScene


def _solve_with_amg(maxh):
    """CG with one V-cycle of the hierarchy on the grown cube's first tangent: (its
    direction, the direct solver's, CG iterations, the hierarchy's levels)."""
    problem, time = cube_problem(maxh=maxh, order=2, elements="tet")
    time.Set(1.0)
    problem.u.vec.data = problem.compatible_displacement(problem.growth_load())
    direct = NewtonSolver(problem)
    r = direct.residual()
    direct.factorise()
    expected = direct.direction().FV().NumPy().copy()
    problem.form.AssembleLinearization(problem.u.vec)
    pre = SmoothedAggregation(problem.form.mat, problem.freedofs,
                              rigid_body_modes(problem.fes))
    cg = ngs.krylovspace.CGSolver(problem.form.mat, pre, tol=1e-10, maxiter=200)
    rhs = r.CreateVector()
    rhs.data = r + problem.form.harmonic_extension_trans * r
    du = rhs.CreateVector()
    du.data = cg * rhs
    du.data += problem.form.harmonic_extension * du
    du.data += problem.form.inner_solve * rhs
    return du.FV().NumPy(), expected, len(cg.residuals) - 1, pre.levels


def test_cg_with_the_multigrid_gives_the_direct_direction_in_iterations_that_stay_flat():
    """On the grown cube's tangent (tetrahedra of order 2, rigid pins) CG preconditioned by the
    hierarchy finds the direct solver's Newton direction to 1e-7, on two meshes whose
    unknowns differ fourfold, with multigrid levels below the finest and CG iterations
    that do not double: the near-nullspace is right."""
    iterations = []
    for maxh in (0.25, 0.15):
        ours, theirs, its, levels = _solve_with_amg(maxh)
        assert levels >= 2
        assert np.linalg.norm(ours - theirs) <= 1e-7 * np.linalg.norm(theirs)
        iterations.append(its)
    assert iterations[1] < 2 * iterations[0], iterations
    assert iterations[1] < 60


def test_newton_with_amg_gives_the_direct_solvers_metrics():
    """The cube solved with linear_solver = amg: every direction a CG solve, the Newton
    iterations and the metrics the direct solver's (1e-8 relative)."""
    settings = {"order": 2, "maxh": 0.25, "outputs": "none"}
    direct = CubeScene(**settings, linear_solver="direct").run()
    amg = CubeScene(**settings, linear_solver="amg").run()
    steps = amg.solver["growth"].steps
    assert all(len(s.linear_iterations) == s.iterations > 0 for s in steps)
    assert amg.newton_iterations == direct.newton_iterations
    compared = [k for k, v in direct.metrics.items() if isinstance(v, float) and abs(v) > 1e-12]
    assert {"strain_energy", "max_principal_stress"} <= set(compared)
    for key in compared:
        assert amg.metrics[key] == pytest.approx(direct.metrics[key], rel=1e-8), key
