"""The symmetric part (A + A^T) / 2 of a sequence of sparse matrices of one pattern.

The GMRES solve of a non-symmetric tangent is preconditioned by a factorisation of its
symmetric part (:mod:`ngincompat.fem.solver`); the symmetric part of each new tangent reuses
the transpose permutation of the pattern, found once per pattern.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ngincompat.errors import require

if TYPE_CHECKING:     # the matrices are NGSolve's
    import ngsolve as ngs


class SymmetricPart:
    """The symmetric part (A + A^T) / 2 of sparse matrices A of a structurally symmetric
    sparsity pattern, as an NGSolve sparse matrix of that pattern.

    The pattern's transpose permutation (entry (i, j) -> entry (j, i)) is found from the
    first matrix and kept while the matrices have its pattern; :meth:`of` then only averages
    the values. A matrix of another pattern (e.g. a contact term's pairs coupled new dofs)
    makes it find the permutation anew.

    Raises
    ------
    ParameterError
        The pattern is not structurally symmetric.
    """

    def __init__(self, matrix: ngs.BaseMatrix) -> None:
        self._adopt(matrix)

    def _adopt(self, matrix: ngs.BaseMatrix) -> None:
        rows, cols, _ = matrix.COO()
        rows, cols = np.asarray(rows, np.int64), np.asarray(cols, np.int64)
        n = matrix.height
        key, key_t = rows * n + cols, cols * n + rows
        order = np.argsort(key)
        where = np.minimum(np.searchsorted(key, key_t, sorter=order), len(key) - 1)
        self.transpose = order[where]
        require(np.array_equal(key[self.transpose], key_t), "matrix", "its sparsity pattern",
                "a structurally symmetric one")
        self.key = key
        self.matrix = matrix.CreateMatrix()

    def of(self, matrix: ngs.BaseMatrix) -> ngs.BaseMatrix:
        """(A + A^T) / 2 of ``matrix`` A."""
        rows, cols, _ = matrix.COO()
        key = np.asarray(rows, np.int64) * matrix.height + np.asarray(cols, np.int64)
        if not np.array_equal(key, self.key):
            self._adopt(matrix)
        values = matrix.AsVector().FV().NumPy()
        self.matrix.AsVector().FV().NumPy()[:] = 0.5 * (values + values[self.transpose])
        return self.matrix
