"""Stability of a grown equilibrium: the smallest eigenvalues of the elastic tangent at frozen
growth, where they cross zero, and the wavelength of a buckling mode.

An equilibrium u of the energy Pi(u) = int Jg Psi(F Fg^-1) dV (section 2.4) at a given growth
is stable while the Hessian K = d^2 Pi / du^2 is positive definite on the admissible
displacements. A perfect growing bilayer stays on its flat (homogeneous) branch past the
critical growth, where Newton's method still converges; the instability shows only in K: its
smallest eigenvalue crosses zero, and the eigenvector there is the buckling mode. The
eigenvalues are those of the pencil

    K w = omega M w,      M = int w . v dV  (the L2 mass matrix),

so omega has the unit stress / length^2 and does not depend on the mesh; growth is held fixed
(the instability of the mechanical equilibrium at the current growth), so K is the symmetric
Hessian even when the growth is coupled to the stretch.
"""

from collections.abc import Sequence

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.linalg import LinearOperator, eigsh

from ngincompat import config
from ngincompat.errors import ConvergenceError, require
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.sparse_lu import free_block
from ngincompat.fem.work import part

#: The factorisations of K - sigma M tried in turn for the shift-invert operator. First
#: SuperLU in symmetric mode (:func:`_symmetric_lu`: an LDL^T factorisation, whose D gives
#: the number of eigenvalues below sigma at no extra cost; on the default bilayer's 36k dofs
#: its factorisation took 1.5 s and the six pairs 3.9 s, as with NGSolve's Cholesky), then
#: NGSolve's sparse Cholesky (LDL^T with a nested-dissection ordering, no pivoting) and its
#: UMFPACK LU (pivoting) should an indefinite K - sigma M make the pairs inaccurate.
INVERSES = ("superlu", "sparsecholesky", "umfpack")

#: The largest accepted residual |K w - omega M w| / (|K|_1 |w|) of an eigenpair (relative
#: to the matrix's scale, not to |K w|, which vanishes at a critical point).
RESIDUAL_TOL = 1e-10

#: The most shifts tried in search of one below every eigenvalue.
MAX_SHIFTS = 16

#: The factor by which that search moves the shift down each time: the shift it stops at is at
#: most this many times farther from 0 than the smallest eigenvalue, which so stays near the
#: shift beside the eigenvalues near 0.
SHIFT_GROWTH = 4


def _symmetric_lu(A: sp.spmatrix) -> spla.SuperLU:
    """SuperLU of the symmetric sparse A with a symmetric permutation and diagonal pivots
    (minimum degree on the pattern of A^T + A, pivot threshold 0, symmetric mode):
    P A P^T = L U with U = D L^T, an LDL^T factorisation."""
    try:
        lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options=dict(SymmetricMode=True))
    except RuntimeError as error:               # "Factor is exactly singular"
        raise ConvergenceError(f"the shifted tangent K - sigma M is singular ({error})") \
            from error
    if not np.array_equal(lu.perm_r, lu.perm_c):
        raise ConvergenceError("the symmetric LU of K - sigma M needed an off-diagonal pivot "
                               "(a zero diagonal pivot): its inertia is not that of D")
    return lu


def _negatives(lu: spla.SuperLU) -> int:
    """The number of negative pivots D of an LU from :func:`_symmetric_lu`."""
    return int(np.count_nonzero(lu.U.diagonal() < 0))


def count_below(K: sp.spmatrix, M: sp.spmatrix, sigma: float = 0.0) -> int:
    """The number of eigenvalues omega < sigma of the pencil K w = omega M w (K symmetric, M
    symmetric positive definite; scipy sparse matrices).

    Sylvester's law of inertia: K - sigma M = M^(1/2) (M^-1/2 K M^-1/2 - sigma) M^(1/2) has
    as many negative eigenvalues as M^-1/2 K M^-1/2 has below sigma, and P (K - sigma M) P^T
    = L D L^T as many as D has negative entries. D is the diagonal of U of
    :func:`_symmetric_lu`. ConvergenceError if K - sigma M is singular (sigma is an
    eigenvalue) or needed an off-diagonal pivot."""
    return _negatives(_symmetric_lu(K - sigma * M))


def _inverse_operator(A: sp.spmatrix, inverse: str, lu: spla.SuperLU) -> LinearOperator:
    """A^-1 factorised by ``inverse`` ("superlu": ``lu``; else NGSolve's factorisation of that
    name) as a scipy LinearOperator."""
    if inverse == "superlu":
        return LinearOperator(A.shape, matvec=lu.solve, dtype=float)
    coo = sp.coo_matrix(A)
    matrix = ngs.la.SparseMatrixd.CreateFromCOO(coo.row, coo.col, coo.data, *A.shape)
    with config.task_manager():
        factor = matrix.Inverse(inverse=inverse)
    x, y = matrix.CreateColVector(), matrix.CreateColVector()

    def solve(b: np.ndarray) -> np.ndarray:
        x.FV().NumPy()[:] = np.ravel(b)
        y.data = factor * x
        return y.FV().NumPy().copy()

    return LinearOperator(A.shape, matvec=solve, dtype=float)


def _residual(K: sp.spmatrix, M: sp.spmatrix, values: np.ndarray, vectors: np.ndarray) -> float:
    """The largest residual |K w - omega M w| / (|K|_1 |w|) of the pairs."""
    scale = spla.norm(K, 1) * np.linalg.norm(vectors, axis=0)
    return float(np.max(np.linalg.norm(K @ vectors - (M @ vectors) * values, axis=0) / scale))


def _pairs_about(K: sp.spmatrix, M: sp.spmatrix, sigma: float, count: int | np.integer,
                 A: sp.spmatrix,
                 lu: spla.SuperLU) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` eigenpairs of the pencil nearest sigma: shift-invert Lanczos from a seeded
    start with A = K - sigma M factorised by the first of :data:`INVERSES` whose pairs are
    accurate (``lu``: A's :func:`_symmetric_lu`)."""
    for inverse in INVERSES:
        values, vectors = eigsh(K, k=count, M=M, sigma=sigma, which="LM",
                                OPinv=_inverse_operator(A, inverse, lu),
                                v0=np.random.default_rng(0).standard_normal(K.shape[0]))
        if _residual(K, M, values, vectors) <= RESIDUAL_TOL:
            return values, vectors
    raise ConvergenceError(f"the smallest eigenpairs of the tangent have a relative "
                           f"residual above {RESIDUAL_TOL:g} with every factorisation "
                           f"({', '.join(INVERSES)})")


def _smallest(K: sp.spmatrix, M: sp.spmatrix, count: int,
              negative: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` smallest eigenpairs of the pencil (with ``negative``: at least all the
    negative ones and the smallest other), proven by the inertia.

    Shift-invert about 0 finds the pairs nearest 0, all those in the disc |omega| <= r of
    the farthest found. If as many of them are negative as the pencil has negative
    eigenvalues (:func:`count_below`), they are the smallest. Otherwise the m missing ones
    lie below -r, the smallest of the spectrum: the shift moves to sigma = -2 r, -8 r, -32
    r, ... (:data:`SHIFT_GROWTH`), an inertia count each, to the first sigma below every
    eigenvalue; there the m pairs nearest sigma are the m smallest, and they must lie below
    -r. Only those m are computed there: asked for ``count``, Lanczos about a far shift also
    has to separate the pairs near 0, whose shifted-inverted values 1 / (omega - sigma)
    nearly coincide (a contact's eigenvalue of -1.5e4 beside a cluster at 3-11 took 1,333
    Lanczos iterations per call and 34-40 s; ``docs/measurements/folding.md``, "The
    march's failed steps"). On a stable branch one factorisation (sigma = 0) gives the pairs
    and their proof."""
    A = sp.csc_matrix(K)
    lu = _symmetric_lu(A)
    below = _negatives(lu)
    if negative:
        count = max(count, below + 1)
    values, vectors = _pairs_about(K, M, 0.0, count, A, lu)
    missing = below - np.count_nonzero(values < 0)
    if missing == 0:
        return values, vectors
    r = float(np.max(np.abs(values)))
    sigma = -2 * r
    for _ in range(MAX_SHIFTS):
        A = sp.csc_matrix(K - sigma * M)
        lu = _symmetric_lu(A)
        if _negatives(lu) == 0:
            low, low_vectors = _pairs_about(K, M, sigma, missing, A, lu)
            if np.all(low < -r):
                values = np.concatenate([low, values])
                vectors = np.hstack([low_vectors, vectors])
                order = np.argsort(values)[:count]
                return values[order], vectors[:, order]
            raise ConvergenceError(f"the {missing} eigenpairs below the shift "
                                   f"{sigma:.3g} are not the ones missing below {-r:.3g}")
        sigma *= SHIFT_GROWTH
    raise ConvergenceError(f"no shift of {MAX_SHIFTS} lies below every eigenvalue of the "
                           f"tangent")


@part("eigenpairs")
def smallest_eigenpairs(problem: GrowthMechanics | CoupledProblem, count: int = 1,
                        negative: bool = False) -> tuple[np.ndarray, list[ngs.GridFunction]]:
    """The ``count`` smallest eigenvalues omega of K w = omega M w and their modes.

    Parameters
    ----------
    problem : GrowthMechanics or CoupledProblem
        Its displacement ``u`` (the current state), its tangent at frozen growth
        (``frozen_tangent()``: K is the derivative of the very residual the problem solves,
        with its integration rule; a Hessian integrated more coarsely has spurious modes in a
        nearly incompressible body) and its free dofs (Dirichlet and symmetry conditions,
        rigid-body pins).
    count : int
        How many, >= 1.
    negative : bool
        Return at least every negative eigenvalue and the smallest non-negative one (more
        than ``count`` pairs if need be): the pairs not returned are then >= 0.

    Returns
    -------
    values : numpy.ndarray
        The eigenvalues in ascending order (stress / length^2).
    modes : list of ngsolve.GridFunction
        The eigenvectors in the displacement space, each of unit L2 norm and signed so that
        its largest dof is positive. With Lanczos started from a fixed (seeded) vector, the
        same state gives the same modes: a buckled branch seeded by a mode is reproducible
        (with a random start the folds of one run came out in the opposite phase of
        another's).

    Raises
    ------
    ConvergenceError
        No factorisation gives accurate pairs, or no shift gives the smallest.
    ParameterError
        The displacement space has element-internal dofs (order >= 4 on tetrahedra), which
        the problem's tangent has condensed out.

    Notes
    -----
    Shift-invert Lanczos (ARPACK through ``scipy.sparse.linalg.eigsh``) finds the eigenvalues
    nearest the shift sigma, which past a buckling onset need not be the smallest: the
    wrinkling modes fall steeply and the pairs nearest zero miss the most negative. The
    number of eigenvalues below sigma, from the inertia of the LDL^T factorisation of
    K - sigma M (:func:`count_below`), proves the pairs found the smallest or moves the shift
    below them (:func:`_smallest`). K - sigma M is factorised by the first of
    :data:`INVERSES` whose pairs have a relative residual below :data:`RESIDUAL_TOL`.
    """
    require(isinstance(count, int) and count >= 1, "count", count, "an integer >= 1")
    V = problem.u.space
    n = V.ndof
    free = np.array(problem.freedofs, dtype=bool)[:n]
    admissible = np.array(V.FreeDofs(), dtype=bool)
    admissible[list(problem.pinned)] = False
    require(np.array_equal(free, admissible), "order", problem.order,
            "one without element-internal displacement dofs (<= 2 on triangles, <= 3 on "
            "tetrahedra), which the condensed tangent leaves out")
    with config.task_manager():
        tangent = problem.frozen_tangent()
    rows = np.zeros(tangent.height, dtype=bool)
    rows[:n] = free
    K, M = free_block(tangent, rows), free_block(_mass(V), free)
    K = (K + K.T) / 2                    # symmetric up to round-off; ARPACK wants it exactly
    values, vectors = _smallest(K, M, count, negative)
    order = np.argsort(values)
    modes = []
    for i in order:
        mode = ngs.GridFunction(V, name="buckling mode")
        mode.vec.FV().NumPy()[free] = vectors[:, i]
        modes.append(_normalised(mode))
    return values[order], modes


def _normalised(mode: ngs.GridFunction) -> ngs.GridFunction:
    """``mode`` scaled to unit L2 norm and signed so that its largest dof is positive."""
    w = mode.vec.FV().NumPy()
    sign = np.sign(w[np.argmax(np.abs(w))])
    mode.vec.data *= sign / np.sqrt(ngs.Integrate(ngs.InnerProduct(mode, mode),
                                                  mode.space.mesh))
    return mode


def combine(modes: Sequence[ngs.GridFunction],
            x: Sequence[float] | np.ndarray) -> ngs.GridFunction:
    """The mode sum_j x_j v_j of the ``modes`` v_j, of unit L2 norm, its largest dof
    positive."""
    mode = ngs.GridFunction(modes[0].space, name="buckling mode")
    for xj, v in zip(x, modes, strict=True):
        mode.vec.data += float(xj) * v.vec
    return _normalised(mode)


def _mass(V: ngs.FESpace) -> ngs.BaseMatrix:
    """The L2 mass matrix int w . v dV of the space V."""
    u, v = V.TnT()
    mass = ngs.BilinearForm(V)
    mass += ngs.InnerProduct(u, v) * ngs.dx
    mass.Assemble()
    return mass.mat


def overlaps(first: Sequence[ngs.GridFunction],
             second: Sequence[ngs.GridFunction]) -> np.ndarray:
    """The L2 inner products int w_i . v_j dV of the modes ``first`` (w_i) and ``second``
    (v_j), GridFunctions of one space: an (len(first), len(second)) array."""
    matrix = _mass(first[0].space)
    tmp = matrix.CreateColVector()
    result = np.empty((len(first), len(second)))
    for j, v in enumerate(second):
        tmp.data = matrix * v.vec
        for i, w in enumerate(first):
            result[i, j] = ngs.InnerProduct(w.vec, tmp)
    return result


def mode_crossings(loads: tuple[float, float], previous: Sequence[float] | np.ndarray,
                   values: Sequence[float] | np.ndarray,
                   overlap: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the modes of two samples of the pencil cross zero, by the Rayleigh quotients of
    the modes of both samples interpolated linearly between them.

    Parameters
    ----------
    loads : (float, float)
        The loads of the two samples, l0 < l1.
    previous : array of m floats
        The m smallest eigenvalues at l0 (all positive), of M-orthonormal modes w_i.
    values : array of k floats
        The k smallest eigenvalues omega_j at l1 (every negative one among them), of
        M-orthonormal modes v_j.
    overlap : (m, k) array
        c_ij = (w_i, v_j)_M.

    Returns
    -------
    crossings : numpy.ndarray
        m + k loads, first for the w_i, then for the v_j: l0 + a / (a - b) (l1 - l0), a and
        b the vector's Rayleigh quotients at l0 and l1, where b < 0; NaN where b >= 0.
    held : numpy.ndarray
        The part of each vector that the other sample's pairs hold: sum_j c_ij^2 for w_i,
        sum_i c_ij^2 for v_j.

    Notes
    -----
    A mode's Rayleigh quotient at its own sample is its eigenvalue. At the other one, with
    the other's modes completed to an M-orthonormal eigenbasis, w_i . K(l1) w_i =
    sum_j c_ij^2 omega_j + the rest, and the eigenvalues not found are >= the largest found,
    so sum_j c_ij^2 omega_j + (1 - held) max omega is that quotient where held = 1 and a
    lower bound otherwise (likewise for v_j at l0): the crossing is then the earliest it can
    be. Both samples' modes are tried because past the onset the wrinkling modes of nearly
    equal eigenvalues mix: a mode at l0 can be split between two modes at l1 that each hold
    half of it (and half of a mode that was not among the pairs at l0), and the other way
    round. The fixed vector's quotient is linear in the load where K is; it is >= the
    smallest eigenvalue, so where it crosses zero K has a negative eigenvalue."""
    l0, l1 = loads
    previous, values = np.asarray(previous, float), np.asarray(values, float)
    c2 = np.asarray(overlap, float) ** 2
    held = np.concatenate([c2.sum(axis=1), c2.sum(axis=0)])
    missing = np.clip(1 - held, 0, None)
    m = len(previous)
    start = np.concatenate([previous, previous @ c2 + missing[m:] * previous.max()])
    end = np.concatenate([c2 @ values + missing[:m] * values.max(), values])
    crossings = np.full(len(start), np.nan)
    negative = end < 0
    crossings[negative] = l0 + start[negative] / (start[negative] - end[negative]) * (l1 - l0)
    return crossings, held


def earliest_crossing(loads: tuple[float, float], previous: Sequence[float] | np.ndarray,
                      values: Sequence[float] | np.ndarray,
                      overlap: np.ndarray) -> tuple[float, np.ndarray, float] | None:
    """The earliest of :func:`mode_crossings` (same arguments): the load, the mode there as
    coefficients x of the modes v_j at l1 (unit length: a mode w_i at l0 as its part in their
    span, sum_j c_ij v_j, normalised) and the part of it the other sample held; None if
    none crosses."""
    crossings, held = mode_crossings(loads, previous, values, overlap)
    if np.all(np.isnan(crossings)):
        return None
    first = int(np.nanargmin(crossings))
    m = len(previous)
    if first < m:
        x = np.asarray(overlap, float)[first]
        x = x / np.linalg.norm(x)
    else:
        x = np.zeros(len(values))
        x[first - m] = 1.0
    return float(crossings[first]), x, float(held[first])


def wavelength(x: Sequence[float] | np.ndarray, w: Sequence[float] | np.ndarray) -> float:
    """The wavelength of an undulation w(x) sampled at increasing x: twice the mean distance
    between its consecutive zero crossings (linearly interpolated); NaN with fewer than two.

    For w = cos(k x) it is 2 pi / k, whatever the phase and the sampling, up to the
    interpolation error of the crossings."""
    x, w = np.asarray(x, float), np.asarray(w, float)
    i = np.flatnonzero(np.sign(w[:-1]) * np.sign(w[1:]) < 0)
    if len(i) < 2:
        return float("nan")
    crossings = x[i] - w[i] * (x[i + 1] - x[i]) / (w[i + 1] - w[i])
    return float(2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1))
