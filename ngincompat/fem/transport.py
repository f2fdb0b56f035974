"""Transport of a misfolded protein: the Fisher-Kolmogorov (Fisher-KPP) equation.

The normalised concentration c(X, t) in [0, 1] of misfolded protein on the reference body
(Weickenmeier, Jucker, Goriely & Kuhl, J. Mech. Phys. Solids 124 (2019) 264; the driver of
the brain atrophy of Lee et al. 2021, section 3.5) obeys

    dc/dt = Div(D Grad c) + alpha c (1 - c)   in B0,     (D Grad c) . N = 0 on dB0,
    D = d_ext I + d_axn n (x) n,

with an isotropic extracellular diffusivity d_ext and a faster one d_axn along the axonal
direction n (white matter). A time step is backward Euler,

    M (c^{n+1} - c^n) / dt + K c^{n+1} - alpha N(c^{n+1}) = 0,

solved by Newton's method (tangent M / dt + K - alpha M[1 - 2c]). The mass and the reaction
are *lumped* (integrated with the vertex rule of linear elements): every node then carries
the logistic ODE of its own value, so a spatially uniform c follows the backward-Euler
logistic map exactly, and the consistent-mass undershoot below c = 0 at a steep seed is gone.
K is made an M-matrix where the mesh has obtuse elements (see :class:`FisherKPP`), so
0 <= c <= 1 holds on any mesh; the minimum of c is reported all the same.

On a mesh distributed over MPI ranks (:mod:`ngincompat.parallel`) each rank holds the part of
M and K that its elements assemble, and c at its vertices (the same value on every rank that
shares a vertex). The upwinding then asks for the sign of the *summed* entry k_ij (an edge
between two ranks holds a part on each; the parts are summed through a space with one dof per
edge), and removes every rank's part of an entry whose sum is positive, so the ranks' parts
add up to the serial K. The Newton tangent is solved by CG with NGSolve's Jacobi on the
ranks' parts (:class:`ngsolve.la.ParallelMatrix`), GMRES where it is not positive definite.
"""

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from ngsolve.krylovspace import CGSolver, GMResSolver

from ngincompat import parallel
from ngincompat.errors import ConvergenceError, require

#: Vertex rules (exact for linear, and on hexahedra trilinear, functions): the lumped mass
#: of lowest-order elements.
_VERTEX_RULES = {
    ngs.HEX: ngs.IntegrationRule([(i, j, k) for k in (0, 1) for j in (0, 1) for i in (0, 1)],
                                 [1 / 8] * 8),
    ngs.TET: ngs.IntegrationRule([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [1 / 24] * 4),
    ngs.TRIG: ngs.IntegrationRule([(0, 0), (1, 0), (0, 1)], [1 / 6] * 3),
    ngs.SEGM: ngs.IntegrationRule([(0,), (1,)], [1 / 2] * 2),
}


def diffusion_tensor(d_ext: float | ngs.CoefficientFunction,
                     d_axn: float | ngs.CoefficientFunction = 0.0,
                     n: ngs.CoefficientFunction | None = None) -> ngs.CoefficientFunction:
    """D = d_ext I + d_axn n (x) n as a 3x3 CoefficientFunction.

    Parameters
    ----------
    d_ext : float or CoefficientFunction
        Isotropic (extracellular) diffusivity, >= 0.
    d_axn : float or CoefficientFunction
        Additional diffusivity along n, >= 0 (0 where there are no axons).
    n : CoefficientFunction, optional
        Unit axonal direction (3-vector); needed only when d_axn is not 0.
    """
    D = d_ext * ngs.Id(3)
    if n is not None:
        D = D + d_axn * ngs.OuterProduct(n, n)
    return D


class FisherKPP:
    """Backward-Euler time steps of the Fisher-KPP equation, P1 with lumped mass.

    Parameters
    ----------
    mesh : ngsolve.Mesh
        Tetrahedra or hexahedra (3-D), triangles (2-D) or segments (1-D).
    D : CoefficientFunction
        Diffusion tensor (dim x dim), e.g. from :func:`diffusion_tensor`.
    alpha : float
        Reaction (conversion) rate, >= 0.
    c0 : CoefficientFunction or float
        Initial concentration, interpolated at the vertices (a projection would overshoot
        at a steep seed).
    monotone : bool
        Make the stiffness matrix K an M-matrix by discrete upwinding (Kuzmin, J. Comput.
        Phys. 219 (2006) 513): every positive off-diagonal entry k_ij (an obtuse or flat
        element, as in a thin gray-matter shell) is removed symmetrically and added to the
        diagonal, which keeps the row sums zero (no flux through the surface, uniform
        states unchanged) and adds diffusion of order h only where the mesh needs it. With
        the lumped mass, backward Euler then keeps 0 <= c <= 1 at any time step. Without it,
        flat elements let c fall far below 0, where the reaction drives it to -inf.
    """

    def __init__(self, mesh: ngs.Mesh, D: ngs.CoefficientFunction, alpha: float,
                 c0: ngs.CoefficientFunction | float,
                 monotone: bool = True) -> None:
        require(alpha >= 0, "alpha", alpha, ">= 0 (conversion rate)")
        self.mesh = mesh
        self.fes = ngs.H1(mesh, order=1)
        self.c = ngs.GridFunction(self.fes, name="c")
        if mesh.nv:           # (rank 0 of a distributed mesh holds no vertices)
            pts = np.array([v.point for v in mesh.vertices]).T
            pts = np.vstack([pts, np.zeros((3 - len(pts), pts.shape[1]))])[:mesh.dim]
            # P1: the dof of vertex k is k; nodal interpolation keeps 0 <= c0 <= 1
            self.c.vec.FV().NumPy()[:] = np.asarray(ngs.CF(c0)(mesh(*pts))).ravel()
        self.alpha = alpha
        u, v = self.fes.TnT()
        mass = ngs.BilinearForm(u * v * ngs.dx(intrules=dict(_VERTEX_RULES))).Assemble()
        self.mass = _csr(mass.mat).diagonal()
        # on its space: D = 0 (no diffusion, c grows in place) makes the integrand zero,
        # which a form built from the integrand alone refuses (it has no trial function)
        stiffness = ngs.BilinearForm(self.fes)
        stiffness += ngs.InnerProduct(D * ngs.grad(u), ngs.grad(v)) * ngs.dx
        K = _csr(stiffness.Assemble().mat)
        if monotone:
            K = _upwind(K, _summed_over_ranks(self.fes, K))
        self.K = K
        self.t = 0.0

    def step(self, dt: float, rtol: float = 1e-10, max_iter: int = 20) -> int:
        """Advance c by one backward-Euler step of length ``dt``; returns Newton iterations.

        Newton starts from c^n. Converged when the update is below ``rtol`` in the max norm
        (c is of order one).

        Raises
        ------
        ConvergenceError
            No convergence in ``max_iter`` iterations; c is left at c^n.
        """
        require(dt > 0, "dt", dt, "> 0")
        c_old = self.c.vec.FV().NumPy().copy()
        c = c_old.copy()
        m = self.mass
        for it in range(1, max_iter + 1):
            r = m * (c - c_old) / dt + self.K @ c - self.alpha * m * c * (1 - c)
            diagonal = m / dt - self.alpha * m * (1 - 2 * c)
            spd = parallel.total(self.mesh, np.count_nonzero(diagonal <= 0)) == 0
            dc = self._solve(self.K + sp.diags(diagonal), r, spd)
            c -= dc
            if parallel.maximum(self.mesh, np.max(np.abs(dc), initial=0.0)) < rtol:
                self.c.vec.FV().NumPy()[:] = c
                self.t += dt
                return it
        raise ConvergenceError(f"Fisher-KPP step dt = {dt:g} at t = {self.t:g}: no "
                               f"convergence in {max_iter} Newton iterations")

    def minimum(self) -> float:
        """The smallest nodal value of c."""
        return -parallel.maximum(self.mesh, np.max(-self.c.vec.FV().NumPy(), initial=-np.inf))

    def maximum(self) -> float:
        """The largest nodal value of c."""
        return parallel.maximum(self.mesh, np.max(self.c.vec.FV().NumPy(), initial=-np.inf))

    def integral(self) -> float:
        """int c dV with the lumped mass (the quantity the scheme balances)."""
        return parallel.total(self.mesh, self.mass @ self.c.vec.FV().NumPy())

    def _solve(self, A: sp.spmatrix, b: np.ndarray, spd: bool) -> np.ndarray:
        """A^-1 b for the tangent A (scipy; on a distributed mesh this rank's part of it and
        of b, and the result is c's update at this rank's vertices)."""
        if not parallel.distributed(self.mesh):
            return _solve(A, b, spd)
        pardofs, op = self.fes.ParallelDofs(), ngs.la.ParallelMatrix.PARALLEL_OP
        matrix = ngs.la.ParallelMatrix(_sparse(A), pardofs, pardofs, op.C2D)
        diagonal = self.c.vec.CreateVector()
        diagonal.FV().NumPy()[:] = A.diagonal()
        diagonal.SetParallelStatus(ngs.la.PARALLEL_STATUS.DISTRIBUTED)
        diagonal.Cumulate()                 # the summed diagonal at this rank's vertices
        jacobi = ngs.la.ParallelMatrix(_sparse(sp.diags(1.0 / diagonal.FV().NumPy())),
                                       pardofs, pardofs, op.C2C)
        rhs, x = self.c.vec.CreateVector(), self.c.vec.CreateVector()
        rhs.FV().NumPy()[:] = b
        rhs.SetParallelStatus(ngs.la.PARALLEL_STATUS.DISTRIBUTED)
        krylov = CGSolver if spd else GMResSolver
        solver = krylov(matrix, jacobi, tol=1e-13, maxiter=10 * self.fes.ndofglobal)
        x.data = solver * rhs
        x.Cumulate()
        return x.FV().NumPy().copy()


def _solve(A: sp.spmatrix, b: np.ndarray, spd: bool) -> np.ndarray:
    """A^-1 b: conjugate gradients with a Jacobi preconditioner where A is symmetric positive
    definite (K an M-matrix plus a positive diagonal: the case alpha dt < 1, some twenty
    times faster than a sparse LU at a few thousand unknowns), else a sparse LU."""
    if spd:
        x, info = spla.cg(A, b, rtol=1e-13, atol=0.0, M=sp.diags(1.0 / A.diagonal()),
                          maxiter=10 * A.shape[0])
        if info == 0:
            return x
    return spla.splu(A.tocsc()).solve(b)


def _csr(matrix: ngs.BaseMatrix) -> sp.csr_matrix:
    """An assembled NGSolve sparse matrix as scipy CSR (of a parallel one: this rank's part)."""
    matrix = getattr(matrix, "local_mat", matrix)
    values, cols, rows = matrix.CSR()
    return sp.csr_matrix((np.array(values), np.array(cols), np.array(rows)),
                         shape=(matrix.height, matrix.width))


def _summed_over_ranks(fes: ngs.FESpace, K: sp.spmatrix) -> np.ndarray:
    """The entries of K's upper triangle (in the order of ``sp.triu(K, k=1).tocoo()``) on
    the P1 space ``fes``, summed over the ranks that share their pair of vertices; K's own
    entries on a serial mesh. Only a pair of two shared vertices can have parts on several
    ranks; such pairs are matched across the ranks by their points (the same numbers on
    every rank), whatever couples them: an edge of a tetrahedron, the diagonal of a
    hexahedron's face."""
    mesh = fes.mesh
    off = sp.triu(K, k=1).tocoo()
    if not parallel.distributed(mesh):
        return off.data
    dofs = fes.ParallelDofs()                           # P1: the dof of vertex k is k
    shared = np.array([len(dofs.Dof2Proc(k)) > 0 for k in range(mesh.nv)], dtype=bool)
    points = np.array([v.point for v in mesh.vertices]).reshape(-1, 3)
    both = np.flatnonzero(shared[off.row] & shared[off.col])
    keys = [tuple(sorted((tuple(points[off.row[k]]), tuple(points[off.col[k]]))))
            for k in both]
    total: dict[tuple, float] = {}
    for part_keys, part_values in mesh.comm.mpi4py.allgather((keys, off.data[both])):
        for key, value in zip(part_keys, part_values, strict=True):
            total[key] = total.get(key, 0.0) + value
    summed = off.data.copy()
    summed[both] = [total[key] for key in keys]
    return summed


def _sparse(A: sp.spmatrix) -> ngs.la.SparseMatrixd:
    """A scipy sparse matrix as an NGSolve one."""
    A = sp.coo_matrix(A)
    return ngs.la.SparseMatrixd.CreateFromCOO(A.row.tolist(), A.col.tolist(), A.data.tolist(),
                                              *A.shape)


def _upwind(K: sp.spmatrix, summed: np.ndarray) -> sp.csr_matrix:
    """K plus the discrete diffusion that removes its off-diagonal entries whose ``summed``
    value (over the ranks, :func:`_summed_over_ranks`) is positive, keeping symmetry and zero
    row sums."""
    off = sp.triu(K, k=1).tocoo()
    bad = summed > 0
    i, j, k = off.row[bad], off.col[bad], off.data[bad]
    n = K.shape[0]
    fix = sp.coo_matrix((np.concatenate([-k, -k, k, k]),
                         (np.concatenate([i, j, i, j]), np.concatenate([j, i, i, j]))),
                        shape=(n, n))
    return (K + fix).tocsr()


def logistic(t: float | np.ndarray, c0: float, alpha: float) -> np.ndarray:
    """The logistic solution c(t) = c0 e^(alpha t) / (1 - c0 + c0 e^(alpha t)): the
    spatially uniform solution of the Fisher-KPP equation."""
    e = np.exp(alpha * np.asarray(t, float))
    return c0 * e / (1 - c0 + c0 * e)


def logistic_integral(t: float | np.ndarray, c0: float, alpha: float) -> np.ndarray:
    """int_0^t c ds = ln(1 - c0 + c0 e^(alpha t)) / alpha for the logistic solution."""
    return np.log(1 - c0 + c0 * np.exp(alpha * np.asarray(t, float))) / alpha


def minimal_front_speed(D: float, alpha: float) -> float:
    """The speed 2 sqrt(D alpha) that fronts from compact seeds approach (from below)."""
    return 2.0 * np.sqrt(D * alpha)
