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

from collections.abc import Sequence

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


class FreeBlockOperator(ngs.BaseMatrix):
    """An operator on the dofs set in ``freedofs`` of the assembled NGSolve sparse matrix
    ``matrix``, zero on the other dofs, applied like an NGSolve inverse or preconditioner:
    a subclass maps the free entries of x to those of y (:meth:`FreeBlockOperator.apply`)."""

    def __init__(self, matrix: ngs.BaseMatrix, freedofs: ngs.BitArray) -> None:
        super().__init__()
        self._matrix = matrix
        self._free = np.flatnonzero(np.fromiter(freedofs, dtype=bool, count=len(freedofs)))

    def apply(self, x: np.ndarray) -> np.ndarray:
        """y_f for x_f (the free entries)."""
        raise NotImplementedError

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
        result[self._free] = self.apply(x.FV().NumPy()[self._free])
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
        super().__init__(matrix, freedofs)
        self._lu = splu(free_block(matrix, self._free).tocsc())

    def apply(self, x: np.ndarray) -> np.ndarray:
        return self._lu.solve(x)
