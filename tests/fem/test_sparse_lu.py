"""ngincompat.fem.sparse_lu: SuperLU's inverse on the free dofs, applied as NGSolve's inverse."""

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat.fem.sparse_lu import SuperLUInverse, free_block


def _convection(mesh):
    """A non-symmetric matrix: grad u . grad v + X1 du/dX1 v, u = 0 on ``left``."""
    fes = ngs.H1(mesh, order=2, dirichlet="left")
    u, v = fes.TnT()
    form = ngs.BilinearForm(fes)
    form += (ngs.grad(u) * ngs.grad(v) + ngs.x * u.Deriv()[0] * v) * ngs.dx
    form.Assemble()
    return fes, form.mat


def test_superlu_inverse_solves_as_umfpack_does_on_the_free_dofs(unit_cube_tet):
    """SuperLUInverse (the coupled problems' direct solver) of a non-symmetric matrix gives
    UMFPACK's solution on the free dofs and zero on the others."""
    fes = ngs.H1(unit_cube_tet, order=2, dirichlet="left")
    u, v = fes.TnT()
    form = ngs.BilinearForm(fes)
    form += (ngs.grad(u) * ngs.grad(v) + ngs.x * u.Deriv()[0] * v) * ngs.dx
    form.Assemble()
    rhs = form.mat.CreateColVector()
    rhs.FV().NumPy()[:] = np.random.default_rng(1).standard_normal(fes.ndof)
    ours, theirs = rhs.CreateVector(), rhs.CreateVector()
    ours.data = SuperLUInverse(form.mat, fes.FreeDofs()) * rhs
    theirs.data = form.mat.Inverse(fes.FreeDofs(), inverse="umfpack") * rhs
    fixed = ~np.array(list(fes.FreeDofs()), dtype=bool)
    assert fixed.any() and np.all(ours.FV().NumPy()[fixed] == 0)
    assert np.allclose(ours.FV().NumPy(), theirs.FV().NumPy(), rtol=1e-10, atol=1e-12)


def test_the_solution_satisfies_the_free_equations(unit_cube_tet):
    """K_ff du_f = r_f to round-off, du = 0 on the fixed dofs, for a right-hand side that is
    not zero on them either (those entries are ignored)."""
    fes, matrix = _convection(unit_cube_tet)
    free = np.array(list(fes.FreeDofs()), dtype=bool)
    rhs = matrix.CreateColVector()
    rhs.FV().NumPy()[:] = np.random.default_rng(2).standard_normal(fes.ndof)
    du = rhs.CreateVector()
    inverse = SuperLUInverse(matrix, fes.FreeDofs())
    assert (inverse.Height(), inverse.Width()) == (fes.ndof, fes.ndof)
    du.data = inverse * rhs
    residual = rhs.CreateVector()
    residual.data = matrix * du - rhs
    r = residual.FV().NumPy()[free]
    assert np.abs(r).max() < 1e-10 * np.abs(rhs.FV().NumPy()).max()
    assert np.all(du.FV().NumPy()[~free] == 0)


def test_the_free_block_is_the_rows_and_columns_of_the_free_dofs():
    """By indices or by a boolean mask: the submatrix of the free rows and columns."""
    dense = np.array([[4.0, 1.0, 0.0, 2.0], [3.0, 5.0, 7.0, 0.0], [0.0, -2.0, 6.0, 1.0],
                      [1.0, 0.0, 0.0, 9.0]])
    rows, cols = np.nonzero(dense)
    matrix = ngs.la.SparseMatrixd.CreateFromCOO(rows.tolist(), cols.tolist(),
                                                dense[rows, cols].tolist(), 4, 4)
    free = [0, 2, 3]
    np.testing.assert_array_equal(free_block(matrix, free).toarray(), dense[np.ix_(free, free)])
    mask = np.array([True, False, True, True])
    np.testing.assert_array_equal(free_block(matrix, mask).toarray(), dense[np.ix_(free, free)])


def test_an_exactly_singular_free_block_is_refused():
    """A free row of zeros: SuperLU finds the block singular (a RuntimeError); without that
    dof the rest is factorised."""
    matrix = ngs.la.SparseMatrixd.CreateFromCOO([0, 0, 1, 1, 2], [0, 1, 0, 1, 2],
                                                [2.0, 1.0, 1.0, 3.0, 0.0], 3, 3)
    everything = ngs.BitArray(3)
    everything.Set()
    with pytest.raises(RuntimeError, match="singular"):
        SuperLUInverse(matrix, everything)
    first_two = ngs.BitArray(3)
    first_two.Clear()
    first_two.Set(0)
    first_two.Set(1)
    rhs = matrix.CreateColVector()
    rhs.FV().NumPy()[:] = (3.0, 4.0, 5.0)
    x = rhs.CreateVector()
    x.data = SuperLUInverse(matrix, first_two) * rhs
    np.testing.assert_allclose(x.FV().NumPy(), (1.0, 1.0, 0.0), rtol=1e-14)
