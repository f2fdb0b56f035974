"""ngincompat.fem.rigid: the rigid motions of a body, at points and in a displacement space."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem
from netgen.geom2d import unit_square

from ngincompat.fem.rigid import rigid_body_modes, rigid_modes


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
