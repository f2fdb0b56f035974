"""A direct inverse of a sparse NGSolve matrix on its free dofs by SuperLU (SciPy).

The coupled problems (skin, folding) have non-symmetric tangents, which NGSolve factorises
with UMFPACK. SciPy's SuperLU with its COLAMD column ordering factorises the same matrices
several times faster, side by side in one process, with solutions that agree to round-off.
Both bodies are thin (a patch, a slab); on the atrophying brain's symmetric tangent, a
solid, COLAMD fills in far more than the sparse Cholesky factorisation, which
:class:`~ngincompat.fem.problem.GrowthMechanics` keeps. The measurements: documentation,
``docs/measurements/solver-costs.md``, "The coupled scenes: where the time goes".

    K_ff du_f = r_f,  du = 0 on the other dofs,

as NGSolve's ``mat.Inverse(freedofs)`` solves it.
"""

from collections.abc import Callable, Sequence

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu


def free_block(matrix: ngs.BaseMatrix, free: np.ndarray | Sequence[int]) -> sp.csr_matrix:
    """The rows and columns ``free`` (indices or a boolean mask) of an assembled NGSolve sparse
    matrix (full storage), as a SciPy CSR matrix. NGSolve's CSR arrays are read in place:
    the block is the only copy."""
    values, cols, rows = (np.asarray(a) for a in matrix.CSR())
    index = np.int32 if len(values) < 2**31 else np.int64   # one type for both, as SciPy's
    full = sp.csr_matrix((values, cols.astype(index, copy=False), rows.astype(index)),
                         shape=(matrix.height, matrix.width), copy=False)
    return full[free][:, free].tocsr()


def free_indices(freedofs: ngs.BitArray) -> np.ndarray:
    """The indices of the dofs set in ``freedofs``."""
    return np.flatnonzero(np.fromiter(freedofs, dtype=bool, count=len(freedofs)))


class FreeBlockOperator(ngs.BaseMatrix):
    """The operator ``apply`` (x_f -> y_f) on the dofs ``free`` (indices) of the assembled
    NGSolve sparse matrix ``matrix``, zero on the other dofs, applied like an NGSolve inverse
    or preconditioner."""

    def __init__(self, matrix: ngs.BaseMatrix, free: np.ndarray,
                 apply: Callable[[np.ndarray], np.ndarray]) -> None:
        super().__init__()
        self._matrix, self._free, self._apply = matrix, free, apply

    def IsComplex(self) -> bool:
        return False

    def Height(self) -> int:
        return self._matrix.height

    def Width(self) -> int:
        return self._matrix.width

    def CreateColVector(self) -> ngs.BaseVector:
        return self._matrix.CreateColVector()

    def CreateRowVector(self) -> ngs.BaseVector:
        return self._matrix.CreateRowVector()

    def Mult(self, x: ngs.BaseVector, y: ngs.BaseVector) -> None:
        result = np.zeros(self._matrix.height)
        result[self._free] = self._apply(x.FV().NumPy()[self._free])
        y.FV().NumPy()[:] = result


class SuperLUInverse(FreeBlockOperator):
    """The inverse of ``matrix`` (an assembled NGSolve sparse matrix) restricted to the dofs
    set in ``freedofs``, factorised once by SuperLU; applied like an NGSolve inverse (zero on
    the other dofs).

    Raises
    ------
    RuntimeError
        SuperLU found the free block exactly singular.
    """

    def __init__(self, matrix: ngs.BaseMatrix, freedofs: ngs.BitArray) -> None:
        free = free_indices(freedofs)
        super().__init__(matrix, free, splu(free_block(matrix, free).tocsc()).solve)
