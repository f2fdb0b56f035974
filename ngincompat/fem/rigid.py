"""The rigid motions of a body, t + w x X: at points, and as coefficient vectors in a
displacement space. They are what the rigid-body pins of a body without supports remove
(:func:`~ngincompat.fem.problem.rigid_pins`) and the near-nullspace of elasticity that an
algebraic multigrid is built from (:mod:`ngincompat.fem.amg`).
"""

import ngsolve as ngs
import numpy as np


def vertex_dofs(fes: ngs.FESpace) -> tuple[np.ndarray, np.ndarray]:
    """The vertices of ``fes``'s mesh (n, d) and the dofs of the d displacement components at
    each (n, d), ``fes`` the displacement space or a compound space whose first component
    it is."""
    mesh = fes.mesh
    d = mesh.dim
    pts = np.array([v.point for v in mesh.vertices]).reshape(-1, d)
    dofs = np.array([fes.GetDofNrs(ngs.NodeId(ngs.VERTEX, v))[:d]
                     for v in range(len(pts))], dtype=int).reshape(-1, d)
    return pts, dofs


def rigid_modes(pts: np.ndarray) -> np.ndarray:
    """The rigid motions t + w x X at the points ``pts`` (n, d): an array (n, d, m), mode k's
    component c at point i in [i, c, k]; m = 6 in 3-D (three translations, then the
    rotations about e1, e2, e3), 3 in plane strain (two translations, the rotation about
    e3). The rotations are taken about the points' centroid and scaled by their extent, so
    that every mode is of order one."""
    d = pts.shape[1]
    size = max(np.ptp(pts, axis=0).max(), 1e-300)
    centred = (pts - pts.mean(axis=0)) / size
    rotations = ([np.cross(np.eye(3)[k], centred) for k in range(3)] if d == 3 else
                 [np.column_stack([-centred[:, 1], centred[:, 0]])])
    modes = np.zeros((len(pts), d, d + len(rotations)))
    for c in range(d):
        modes[:, c, c] = 1.0
        for k, rotation in enumerate(rotations):
            modes[:, c, d + k] = rotation[:, c]
    return modes


def rigid_body_modes(fes: ngs.FESpace) -> np.ndarray:
    """The coefficient vectors of the rigid motions (:func:`rigid_modes`) in ``fes``, the
    displacement space or a compound space whose first component it is: an array
    (fes.ndof, m). A rigid motion is linear, so its vertex dofs carry it and every other
    dof is zero (the hierarchical bases of NGSolve's H1 spaces)."""
    pts, dofs = vertex_dofs(fes)
    modes = rigid_modes(pts)
    vectors = np.zeros((fes.ndof, modes.shape[2]))
    for c in range(pts.shape[1]):
        vectors[dofs[:, c]] = modes[:, c]
    return vectors
