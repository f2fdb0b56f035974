"""ngincompat.fem.rigid and ngincompat.fem.amg: the rigid motions of a displacement space, and
CG preconditioned by smoothed-aggregation multigrid built from them."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem
from netgen.geom2d import unit_square

from ngincompat.fem.amg import SmoothedAggregation
from ngincompat.fem.rigid import rigid_body_modes, rigid_modes
from ngincompat.fem.solver import NewtonSolver
from ngincompat.scenes.cube import CubeScene


def _motion(pts, mode):
    """Mode ``mode`` of :func:`rigid_modes`, written out: a translation along e_mode, else
    the rotation about e_(mode - d) of X centred and scaled as rigid_modes takes it."""
    d = pts.shape[1]
    centre, size = pts.mean(axis=0), np.ptp(pts, axis=0).max()
    if mode < d:
        return ngs.CF(tuple(1.0 if c == mode else 0.0 for c in range(d)))
    x = [(ngs.x - centre[0]) / size, (ngs.y - centre[1]) / size]
    if d == 2:
        return ngs.CF((-x[1], x[0]))
    x.append((ngs.z - centre[2]) / size)
    w = np.eye(3)[mode - 3]
    return ngs.CF(tuple(w[(c + 1) % 3] * x[(c + 2) % 3] - w[(c + 2) % 3] * x[(c + 1) % 3]
                        for c in range(3)))


@pytest.mark.parametrize("dim", [2, 3])
def test_the_rigid_modes_are_the_interpolants_of_the_rigid_motions(dim, unit_cube_tet):
    """Each column of rigid_body_modes is the coefficient vector of t + w x X in VectorH1 of
    order 3 (six motions on a tetrahedral cube, three on a square in plane strain): what
    NGSolve's interpolation of the motion gives, every dof that is not a vertex's zero."""
    mesh = unit_cube_tet if dim == 3 else ngs.Mesh(unit_square.GenerateMesh(maxh=0.3))
    space = ngs.VectorH1(mesh, order=3)
    modes = rigid_body_modes(space)
    pts = np.array([v.point for v in mesh.vertices])
    assert modes.shape == (space.ndof, 6 if dim == 3 else 3)
    assert rigid_modes(pts).shape == (mesh.nv, dim, modes.shape[1])
    gf = ngs.GridFunction(space)
    for k in range(modes.shape[1]):
        gf.Set(_motion(pts, k))
        assert np.allclose(modes[:, k], gf.vec.FV().NumPy(), atol=1e-12), k
    assert np.count_nonzero(np.abs(modes).sum(axis=1)) == dim * mesh.nv


def test_the_rigid_modes_are_the_nullspace_of_the_unsupported_tangent():
    """The tangent of the free cube at rest is linear elasticity, whose kernel is exactly the
    rigid motions: K b = 0 for every mode b, to round-off against |K| |b|."""
    problem, _ = cube_problem(maxh=0.5, elements="tet")
    problem.form.AssembleLinearization(problem.u.vec)
    modes = rigid_body_modes(problem.fes)
    vector = problem.u.vec.CreateVector()
    product = problem.u.vec.CreateVector()
    scale = max(abs(v) for v in problem.form.mat.AsVector().FV().NumPy())
    for k in range(modes.shape[1]):
        vector.FV().NumPy()[:] = modes[:, k]
        product.data = problem.form.mat * vector
        assert np.abs(product.FV().NumPy()).max() < 1e-10 * scale * np.abs(modes[:, k]).max()


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
