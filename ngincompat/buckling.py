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

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.linalg import LinearOperator, eigsh

from .errors import ConvergenceError, require


def _scipy(matrix, free):
    rows, cols, vals = matrix.COO()
    n = matrix.height
    full = sp.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))), shape=(n, n))
    return full[free][:, free]


#: The factorisations of K tried in turn for the shift-invert operator: NGSolve's sparse
#: Cholesky (LDL^T with a nested-dissection ordering, no pivoting: on the default bilayer's
#: 36k dofs the eigenpairs took 1.9 s against 8.9 s with scipy's SuperLU, measured), then its
#: UMFPACK LU (pivoting) should an indefinite K make the pairs inaccurate.
INVERSES = ("sparsecholesky", "umfpack")

#: The largest accepted residual |K w - omega M w| / (|K|_1 |w|) of an eigenpair (relative
#: to the matrix's scale, not to |K w|, which vanishes at a critical point).
RESIDUAL_TOL = 1e-10


def _inverse_operator(matrix, rows, inverse):
    """K^-1 on the dofs ``rows`` of the NGSolve ``matrix`` K, factorised by ``inverse``, as a
    scipy LinearOperator on those dofs."""
    index = np.flatnonzero(rows)
    free = ngs.BitArray(len(rows))
    free.Clear()
    for i in index:
        free.Set(int(i))
    with ngs.TaskManager():
        factor = matrix.Inverse(free, inverse=inverse)
    x, y = matrix.CreateColVector(), matrix.CreateColVector()

    def solve(b):
        x.FV().NumPy()[:] = 0.0
        x.FV().NumPy()[index] = np.ravel(b)
        y.data = factor * x
        return y.FV().NumPy()[index].copy()

    return LinearOperator((len(index), len(index)), matvec=solve, dtype=float)


def _residual(K, M, values, vectors):
    """The largest residual |K w - omega M w| / (|K|_1 |w|) of the pairs."""
    scale = spla.norm(K, 1) * np.linalg.norm(vectors, axis=0)
    return float(np.max(np.linalg.norm(K @ vectors - (M @ vectors) * values, axis=0) / scale))


def smallest_eigenpairs(problem, count=1):
    """The ``count`` smallest eigenvalues omega of K w = omega M w and their modes.

    Parameters
    ----------
    problem : GrowthMechanics or CoupledGrowth
        Its displacement ``u`` (the current state), its tangent at frozen growth
        (``frozen_tangent()``: K is the derivative of the very residual the problem solves,
        with its integration rule; a Hessian integrated more coarsely has spurious modes in a
        nearly incompressible body) and its free dofs (Dirichlet and symmetry conditions,
        rigid-body pins).
    count : int
        How many, >= 1.

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
        No factorisation gives accurate pairs.
    ParameterError
        The displacement space has element-internal dofs (order >= 4 on tetrahedra), which
        the problem's tangent has condensed out.

    Notes
    -----
    Shift-invert Lanczos (ARPACK through ``scipy.sparse.linalg.eigsh``) about omega = 0 finds
    the eigenvalues nearest zero; on a stable or barely unstable branch these are the smallest.
    K is factorised by the first of :data:`INVERSES` whose pairs have a relative residual
    below :data:`RESIDUAL_TOL`.
    """
    require(isinstance(count, int) and count >= 1, "count", count, "an integer >= 1")
    V = problem.u.space
    n = V.ndof
    free = np.array(problem.freedofs, dtype=bool)[:n]
    admissible = np.array(V.FreeDofs(), dtype=bool)
    admissible[list(problem.pinned)] = False
    require(np.array_equal(free, admissible), "order", problem.order,
            "one without element-internal displacement dofs (<= 3 on tetrahedra), which the "
            "condensed tangent leaves out")
    with ngs.TaskManager():
        tangent = problem.frozen_tangent()
    rows = np.zeros(tangent.height, dtype=bool)
    rows[:n] = free
    u, v = V.TnT()
    mass = ngs.BilinearForm(V)
    mass += ngs.InnerProduct(u, v) * ngs.dx
    mass.Assemble()
    K, M = _scipy(tangent, rows), _scipy(mass.mat, free)
    K = (K + K.T) / 2                    # symmetric up to round-off; ARPACK wants it exactly
    for inverse in INVERSES:
        values, vectors = eigsh(K, k=count, M=M, sigma=0.0, which="LM",
                                OPinv=_inverse_operator(tangent, rows, inverse),
                                v0=np.random.default_rng(0).standard_normal(K.shape[0]))
        if _residual(K, M, values, vectors) <= RESIDUAL_TOL:
            break
    else:
        raise ConvergenceError(f"the smallest eigenpairs of the tangent have a relative "
                               f"residual above {RESIDUAL_TOL:g} with every factorisation "
                               f"({', '.join(INVERSES)})")
    order = np.argsort(values)
    modes = []
    for i in order:
        mode = ngs.GridFunction(V, name="buckling mode")
        w = vectors[:, i]
        mode.vec.FV().NumPy()[free] = w * np.sign(w[np.argmax(np.abs(w))])
        mode.vec.data *= 1.0 / np.sqrt(ngs.Integrate(ngs.InnerProduct(mode, mode), V.mesh))
        modes.append(mode)
    return values[order], modes


def zero_crossing(loads, values):
    """The load at which ``values`` (sampled at increasing ``loads``) first turns negative,
    linearly interpolated between the last positive sample and the first negative one; None if
    it never does.

    Only the bracketing pair is used: the smallest eigenvalue passes from one mode to another
    as the load grows (a slowly falling long mode, then the steeply falling wrinkles), so
    samples further back may belong to another mode's curve."""
    loads, values = np.asarray(loads, float), np.asarray(values, float)
    negative = np.flatnonzero(values < 0)
    if len(negative) == 0 or negative[0] == 0:
        return None
    i = negative[0]
    a, b = values[i - 1], values[i]
    return float(loads[i - 1] + a / (a - b) * (loads[i] - loads[i - 1]))


def wavelength(x, w):
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
