"""ngincompat.fem.symmetric: (A + A^T) / 2 on a structurally symmetric sparsity pattern."""

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat.errors import ParameterError
from ngincompat.fem.symmetric import SymmetricPart


def _dense(matrix):
    rows, cols, values = matrix.COO()
    dense = np.zeros((matrix.height, matrix.width))
    dense[np.asarray(rows), np.asarray(cols)] = np.asarray(values)
    return dense


def test_symmetric_part_averages_a_matrix_with_its_transpose():
    """(A + A^T) / 2 on A's pattern, for every matrix of that pattern; a pattern that is not
    structurally symmetric is refused."""
    rows, cols = [0, 0, 1, 1, 1, 2, 2], [0, 1, 0, 1, 2, 1, 2]
    first = ngs.la.SparseMatrixd.CreateFromCOO(rows, cols, [4.0, 1.0, 3.0, 5.0, 7.0, -2.0, 6.0],
                                               3, 3)
    second = ngs.la.SparseMatrixd.CreateFromCOO(rows, cols, [1.0, 0.0, 2.0, 1.0, -1.0, 3.0, 1.0],
                                                3, 3)
    part = SymmetricPart(first)
    for matrix in (first, second):
        expected = (_dense(matrix) + _dense(matrix).T) / 2
        assert np.allclose(_dense(part.of(matrix)), expected, rtol=0, atol=1e-15)
    assert _dense(part.of(first))[0, 1] == 2.0 and _dense(part.of(first))[1, 2] == 2.5
    lopsided = ngs.la.SparseMatrixd.CreateFromCOO([0, 0, 1], [0, 1, 1], [1.0, 1.0, 1.0], 2, 2)
    with pytest.raises(ParameterError, match="structurally symmetric"):
        SymmetricPart(lopsided)


def test_symmetric_part_follows_a_matrix_of_another_pattern():
    """A matrix whose pattern grew (a contact pair coupling new dofs) gets its own (A + A^T)
    / 2, not the old pattern's."""
    first = ngs.la.SparseMatrixd.CreateFromCOO([0, 1, 2], [0, 1, 2], [1.0, 2.0, 3.0], 3, 3)
    grown = ngs.la.SparseMatrixd.CreateFromCOO([0, 0, 1, 2, 2], [0, 2, 1, 0, 2],
                                               [1.0, 4.0, 2.0, 2.0, 3.0], 3, 3)
    part = SymmetricPart(first)
    assert np.allclose(_dense(part.of(first)), np.diag([1.0, 2.0, 3.0]))
    expected = (_dense(grown) + _dense(grown).T) / 2
    assert np.allclose(_dense(part.of(grown)), expected, rtol=0, atol=1e-15)
    assert _dense(part.of(grown))[0, 2] == 3.0


def test_the_symmetric_part_of_a_convection_form_is_its_symmetrised_form(unit_cube_tet):
    """a(u, v) = grad u . grad v + X1 du/dX1 v, assembled: its symmetric part is the matrix of
    grad u . grad v + (X1 du/dX1 v + X1 dv/dX1 u) / 2, assembled on its own."""
    fes = ngs.H1(unit_cube_tet, order=2)
    u, v = fes.TnT()
    diffusion = ngs.grad(u) * ngs.grad(v)
    a = ngs.BilinearForm((diffusion + ngs.x * ngs.grad(u)[0] * v) * ngs.dx).Assemble()
    half = ngs.BilinearForm((diffusion + 0.5 * ngs.x * (ngs.grad(u)[0] * v
                                                       + ngs.grad(v)[0] * u)) * ngs.dx)
    half.Assemble()
    got = _dense(SymmetricPart(a.mat).of(a.mat))
    assert np.abs(_dense(a.mat) - _dense(a.mat).T).max() > 1e-3      # A is not symmetric
    np.testing.assert_allclose(got, _dense(half.mat), rtol=0, atol=1e-13)
    assert np.array_equal(got, got.T)
