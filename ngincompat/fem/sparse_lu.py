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
    matrix, as a SciPy CSR matrix."""
    rows, cols, values = matrix.COO()
    full = sp.csr_matrix((np.asarray(values), (np.asarray(rows), np.asarray(cols))),
                         shape=(matrix.height, matrix.width))
    return full[free][:, free]


class SuperLUInverse(ngs.BaseMatrix):
    """The inverse of ``matrix`` (an assembled NGSolve sparse matrix) restricted to the dofs
    set in ``freedofs``, factorised once by SuperLU; applied like an NGSolve inverse (zero on
    the other dofs).

    Raises
    ------
    RuntimeError
        SuperLU found the free block exactly singular.
    """

    def __init__(self, matrix: ngs.BaseMatrix, freedofs: ngs.BitArray) -> None:
        super().__init__()
        self._matrix = matrix
        self._free = np.flatnonzero(np.fromiter(freedofs, dtype=bool, count=len(freedofs)))
        self._lu = splu(free_block(matrix, self._free).tocsc())

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
        solution = np.zeros(self._matrix.height)
        solution[self._free] = self._lu.solve(x.FV().NumPy()[self._free])
        y.FV().NumPy()[:] = solution
