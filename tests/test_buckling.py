"""The eigenpairs of the stability checks (:mod:`ngincompat.buckling`): the inertia that
proves them the smallest, and the shift below the pairs nearest zero when they are not."""

import functools
from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
from netgen.csg import unit_cube
from scipy.linalg import eigh

from ngincompat import buckling


def pencil(n, seed=0):
    """A sparse symmetric indefinite K (a 2D Laplacian shifted down, with a random symmetric
    perturbation) and a sparse SPD M (a 1D mass matrix of each row) of size n x n."""
    side = int(np.sqrt(n))
    lap = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(side, side))
    eye = sp.identity(side)
    K = (sp.kron(lap, eye) + sp.kron(eye, lap)) * side ** 2 - 200.0 * sp.identity(side ** 2)
    rng = np.random.default_rng(seed)
    R = sp.random(side ** 2, side ** 2, density=0.01, random_state=rng)
    K = (K + 10.0 * (R + R.T)).tocsc()
    M = (sp.diags([1.0, 4.0, 1.0], [-1, 0, 1], shape=(side ** 2, side ** 2)) / 6).tocsc()
    return K, M


def test_count_below_is_the_number_of_eigenvalues_below_the_shift():
    """Sylvester's law: the negative pivots of the symmetric LDL^T of K - sigma M count the
    eigenvalues of the pencil below sigma, against a dense solve."""
    K, M = pencil(400)
    exact = eigh(K.toarray(), M.toarray(), eigvals_only=True)
    assert exact[0] < 0 < exact[-1]
    for sigma in (0.0, -150.0, 37.5, float(exact[20] + exact[21]) / 2, 2000.0):
        assert buckling.count_below(K, M, sigma) == np.count_nonzero(exact < sigma)


@functools.cache
def _space():
    return ngs.VectorH1(ngs.Mesh(unit_cube.GenerateMesh(maxh=0.5)), order=1)


def prescribed(values, seed=0):
    """A stand-in for a problem whose tangent K has the pencil eigenvalues ``values`` (with
    M the L2 mass matrix of its space: K = L U diag(values) U^T L^T, M = L L^T, U a random
    orthogonal matrix), with what :func:`buckling.smallest_eigenpairs` reads of it."""
    V = _space()
    n = V.ndof
    u, v = V.TnT()
    mass = ngs.BilinearForm(V)
    mass += ngs.InnerProduct(u, v) * ngs.dx
    mass.Assemble()
    rows, cols, vals = mass.mat.COO()
    M = sp.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))),
                      shape=(n, n)).toarray()
    L = np.linalg.cholesky(M)
    U, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((n, n)))
    K = L @ U @ np.diag(np.resize(values, n)) @ U.T @ L.T
    K = (K + K.T) / 2
    i, j = np.nonzero(np.ones((n, n)))
    tangent = ngs.la.SparseMatrixd.CreateFromCOO(i, j, K[i, j], n, n)
    freedofs = V.FreeDofs()
    return SimpleNamespace(u=ngs.GridFunction(V), freedofs=freedofs, pinned=[], order=1,
                           frozen_tangent=lambda: tangent)


def test_smallest_eigenpairs_are_the_smallest_not_those_nearest_zero():
    """Past a buckling onset the wrinkling modes fall steeply: here the four pairs nearest
    zero (-2, 1, 1.5, 2.0) miss the three smallest (-60, -50, -40). The inertia of K says four
    are negative, the shift moves below the ones found, and the four smallest come back."""
    problem = prescribed(values := np.concatenate([[-60.0, -50.0, -40.0, -2.0],
                                                   np.linspace(1.0, 300.0, 600)]))
    found, modes = buckling.smallest_eigenpairs(problem, count=4)
    np.testing.assert_allclose(found, [-60.0, -50.0, -40.0, -2.0], rtol=1e-9)
    assert len(modes) == 4
    # with ``negative`` every negative eigenvalue and the smallest other one
    found, _ = buckling.smallest_eigenpairs(problem, count=2, negative=True)
    np.testing.assert_allclose(found, np.sort(values)[:5], rtol=1e-9)
    # on a stable pencil the pairs nearest zero are the smallest, the inertia says so
    stable = np.linspace(1.0, 300.0, 600)
    found, _ = buckling.smallest_eigenpairs(prescribed(stable), count=3)
    np.testing.assert_allclose(found, stable[:3], rtol=1e-9)
