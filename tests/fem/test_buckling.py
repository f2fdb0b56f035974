"""The eigenpairs of the stability checks (:mod:`ngincompat.fem.buckling`): the inertia that
proves them the smallest, the shift below the pairs nearest zero when they are not, and the
onset as the earliest zero crossing among the modes of two samples."""

import functools
from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import pytest
import scipy.sparse as sp
from netgen.csg import unit_cube
from scipy.linalg import eigh

from ngincompat.fem import buckling


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


def test_a_far_negative_eigenvalue_is_computed_alone_below_the_spectrum(monkeypatch):
    """A contact's steep mode (-1.5e4) beside a cluster near 3: the pairs nearest zero miss
    it, and Lanczos about the far shift is asked for that one pair only (asked for all six,
    it also had to separate the cluster, whose shifted-inverted values nearly coincide
    there: 1,333 iterations a shift). The shift it is computed about lies below every
    eigenvalue, and the six smallest come back."""
    cluster = 2.9 + 0.01 * np.arange(600)
    values = np.concatenate([[-1.5e4], cluster])
    asked = []
    about = buckling._pairs_about

    def spy(K, M, sigma, count, A, lu):
        asked.append((sigma, count))
        return about(K, M, sigma, count, A, lu)

    monkeypatch.setattr(buckling, "_pairs_about", spy)
    found, _ = buckling.smallest_eigenpairs(prescribed(values), count=6)
    np.testing.assert_allclose(found, np.sort(values)[:6], rtol=1e-9)
    (first, six), (far, one) = asked
    assert (first, six) == (0.0, 6)
    assert one == 1 and far < -1.5e4
    # with ``negative``, that one and the smallest other
    asked.clear()
    found, _ = buckling.smallest_eigenpairs(prescribed(values), count=1, negative=True)
    np.testing.assert_allclose(found, [-1.5e4, 2.9], rtol=1e-9)


def linear_samples(slopes, loads, modes=None, seed=1):
    """The pencil K(l) = Q diag(s_i (l - l_i)) Q^T, M = I (l_i, s_i from ``slopes``: mode i
    crosses zero at l_i) sampled at ``loads``: per sample its eigenvalues and modes (the
    columns of Q), the m smallest at the first sample, at the second the negative ones and
    the next."""
    crossing, slope = np.asarray(slopes, float).T
    n = len(crossing)
    Q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((n, n)))
    samples = []
    for load, m in zip(loads, (modes, None), strict=True):
        values, vectors = eigh(Q @ np.diag(slope * (load - crossing)) @ Q.T)
        m = m or np.count_nonzero(values < 0) + 1
        samples.append((values[:m], vectors[:, :m]))
    (a, w), (b, v) = samples
    return a, b, w.T @ v


def test_onset_is_the_earliest_crossing_not_the_most_negative_mode():
    """Modes that keep their shape, each falling linearly: mode 0 crosses first (1.2812) but
    falls slowly, so at the second sample mode 1 (crossing at 1.2850, falling 20 times
    faster) is the most negative, and a crossing interpolated from the smallest eigenvalue
    alone would be mode 1's at the other's start. The earliest crossing is mode 0's, exactly
    (the quotients are linear)."""
    slopes = [(1.2812, -100.0), (1.2850, -2000.0), (1.2880, -1500.0), (1.31, -50.0),
              (1.40, -10.0), (1.5, -5.0)]
    loads = (1.28, 1.29)
    previous, values, overlap = linear_samples(slopes, loads, modes=6)
    assert values[0] == pytest.approx(-2000 * (1.29 - 1.2850))
    crossings, held = buckling.mode_crossings(loads, previous, values, overlap)
    np.testing.assert_allclose(held[6:], 1.0, rtol=1e-12)      # all modes held before
    assert np.nanmin(crossings[6:]) == pytest.approx(1.2812, rel=1e-12)
    load, x, part = buckling.earliest_crossing(loads, previous, values, overlap)
    assert load == pytest.approx(1.2812, rel=1e-12)
    assert abs(x[np.argmax(np.abs(x))]) == pytest.approx(1.0)
    assert values[np.argmax(np.abs(x))] == pytest.approx(-100 * (1.29 - 1.2812))
    assert part == pytest.approx(1.0)


def test_onset_of_a_mode_split_between_nearly_equal_modes():
    """At the second sample two modes have equal eigenvalues (-13.9), so its eigenvectors are
    any rotation of them: each holds half of mode 0 (among the pairs before, crossing at
    1.2816) and half of mode 1 (not among them: 8.3 at the first sample). Matched from the
    second sample alone the halves cross no earlier than 1.2834; mode 0 of the first sample,
    whose quotient at the second one its pairs hold, gives its own crossing, 1.2816."""
    l0, l1 = 1.28, 1.29
    previous = np.array([2.64, 3.4, 5.0])
    values = np.array([-15.0, -13.9, -13.9, 0.5])
    # the modes: at l0 the unit vectors e0, e2, e3; at l1 e2, (e0 +- e1)/sqrt 2, e4
    w = np.eye(5)[:, [0, 2, 3]]
    r = np.sqrt(0.5)
    v = np.stack([np.eye(5)[2], r * (np.eye(5)[0] + np.eye(5)[1]),
                  r * (np.eye(5)[0] - np.eye(5)[1]), np.eye(5)[4]], axis=1)
    overlap = w.T @ v
    crossings, held = buckling.mode_crossings((l0, l1), previous, values, overlap)
    assert held[3 + 1] == pytest.approx(0.5)
    # the halves' start is bounded below by the largest eigenvalue at l0 for the missing half
    assert crossings[3 + 1] == pytest.approx(l0 + 0.01 * 3.82 / (3.82 + 13.9))
    load, x, part = buckling.earliest_crossing((l0, l1), previous, values, overlap)
    assert load == pytest.approx(l0 + 0.01 * 2.64 / (2.64 + 13.9))
    assert part == pytest.approx(1.0)
    np.testing.assert_allclose(np.abs(x), [0, r, r, 0], atol=1e-12)


def test_a_mode_not_among_the_pairs_before_crosses_no_later_than_said():
    """A mode that was not among the m smallest at the first sample: its quotient there is
    only bounded below (by the largest of them), so its crossing is the earliest it can be,
    before its true one."""
    slopes = [(1.2812, -100.0), (1.30, -3000.0), (1.35, -50.0), (1.40, -10.0)]
    loads = (1.28, 1.31)
    previous, values, overlap = linear_samples(slopes, loads, modes=3)
    crossings, held = buckling.mode_crossings(loads, previous, values, overlap)
    steep = len(previous) + int(np.argmin(values))    # slope -3000, not held before
    assert held[steep] == pytest.approx(0.0, abs=1e-12)
    assert crossings[steep] < 1.30
    assert buckling.earliest_crossing(loads, previous, values, overlap)[0] == pytest.approx(
        1.2812)
    assert buckling.earliest_crossing(loads, previous, np.abs(values), overlap) is None
