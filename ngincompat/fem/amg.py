"""Smoothed-aggregation algebraic multigrid (PyAMG) as a preconditioner of CG for the tangent of
an energy minimisation on a displacement space.

The near-nullspace of elasticity is the rigid motions: the hierarchy is built from them
(:func:`~ngincompat.fem.rigid.rigid_body_modes`, restricted to the free dofs), so that its
coarse levels carry the smooth modes a pointwise smoother cannot reduce (Vanek, Mandel and
Brezina, Computing 56 (1996) 179). One V-cycle applied to a residual approximates K^-1; CG
with it needs a number of iterations that stays about the same as the mesh is refined, and
the hierarchy's memory is a small multiple of the matrix's, where a sparse factorisation of a
3-D problem grows far faster (``docs/performance.md``, "One Newton step against problem size
and linear solver").
"""

import ngsolve as ngs
import numpy as np
import pyamg

from ngincompat.fem.sparse_lu import FreeBlockOperator, free_block, free_indices

#: The largest coarsest level, which PyAMG solves by a sparse LU factorisation: small beside
#: the fine level's unknowns, large enough that the hierarchy has few levels.
MAX_COARSE = 2000


class SmoothedAggregation(FreeBlockOperator):
    """One V-cycle of PyAMG's smoothed-aggregation hierarchy for the free block of
    ``matrix`` (an assembled NGSolve sparse matrix, symmetric positive definite on the dofs
    set in ``freedofs``), built with the near-nullspace ``modes`` (ndof, m); applied like an
    NGSolve preconditioner (zero on the other dofs). ``levels``: the hierarchy's levels."""

    def __init__(self, matrix: ngs.BaseMatrix, freedofs: ngs.BitArray,
                 modes: np.ndarray) -> None:
        free = free_indices(freedofs)
        hierarchy = pyamg.smoothed_aggregation_solver(
            free_block(matrix, free), B=np.ascontiguousarray(modes[free]),
            symmetry="hermitian", strength=("symmetric", {"theta": 0.0}),
            max_coarse=MAX_COARSE, coarse_solver="splu")
        self.levels = len(hierarchy.levels)
        super().__init__(matrix, free, hierarchy.aspreconditioner(cycle="V").matvec)
