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
logistic map exactly, and the consistent-mass undershoot below c = 0 at a steep seed is gone
(the minimum of c is still reported: on meshes with obtuse angles K is not an M-matrix).
"""

import ngsolve as ngs
import numpy as np

from .errors import ConvergenceError, require

#: Vertex rules (exact for linear functions): the lumped mass of P1 elements.
_VERTEX_RULES = {
    ngs.TET: ngs.IntegrationRule([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [1 / 24] * 4),
    ngs.TRIG: ngs.IntegrationRule([(0, 0), (1, 0), (0, 1)], [1 / 6] * 3),
    ngs.SEGM: ngs.IntegrationRule([(0,), (1,)], [1 / 2] * 2),
}


def diffusion_tensor(d_ext, d_axn=0.0, n=None):
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
    """Backward-Euler time steps of the Fisher-KPP equation on a mesh, P1 with lumped mass.

    Parameters
    ----------
    mesh : ngsolve.Mesh
        Tetrahedra (3-D), triangles (2-D) or segments (1-D).
    D : CoefficientFunction
        Diffusion tensor (dim x dim), e.g. from :func:`diffusion_tensor`.
    alpha : float
        Reaction (conversion) rate, >= 0.
    c0 : CoefficientFunction or float
        Initial concentration, interpolated at the vertices.
    """

    def __init__(self, mesh, D, alpha, c0):
        require(alpha >= 0, "alpha", alpha, ">= 0 (conversion rate)")
        self.mesh = mesh
        self.fes = ngs.H1(mesh, order=1)
        self.c = ngs.GridFunction(self.fes, name="c")
        self.c_old = ngs.GridFunction(self.fes)
        self.c.Set(c0)
        self.dt = ngs.Parameter(1.0)
        self.alpha = alpha
        u, v = self.fes.TnT()
        lumped = ngs.dx(intrules=dict(_VERTEX_RULES))
        self.form = ngs.BilinearForm(self.fes, symmetric=False)
        self.form += ((u - self.c_old) / self.dt - alpha * u * (1 - u)) * v * lumped
        self.form += ngs.InnerProduct(D * ngs.grad(u), ngs.grad(v)) * ngs.dx
        self.t = 0.0

    def step(self, dt, rtol=1e-10, max_iter=20):
        """Advance c by one backward-Euler step of length ``dt``; returns Newton iterations.

        Newton starts from c^n. Converged when the update is below ``rtol`` in the max norm
        (c is of order one).

        Raises
        ------
        ConvergenceError
            No convergence in ``max_iter`` iterations; c is restored to c^n.
        """
        require(dt > 0, "dt", dt, "> 0")
        self.dt.Set(dt)
        self.c_old.vec.data = self.c.vec
        r = self.c.vec.CreateVector()
        du = self.c.vec.CreateVector()
        for it in range(1, max_iter + 1):
            self.form.Apply(self.c.vec, r)
            self.form.AssembleLinearization(self.c.vec)
            du.data = self.form.mat.Inverse(self.fes.FreeDofs(), inverse="umfpack") * r
            self.c.vec.data -= du
            if np.max(np.abs(du.FV().NumPy())) < rtol:
                self.t += dt
                return it
        self.c.vec.data = self.c_old.vec
        raise ConvergenceError(f"Fisher-KPP step dt = {dt:g} at t = {self.t:g}: no "
                               f"convergence in {max_iter} Newton iterations")

    def minimum(self):
        """The smallest nodal value of c (0 <= c is not guaranteed on every mesh)."""
        return float(np.min(self.c.vec.FV().NumPy()))

    def maximum(self):
        """The largest nodal value of c."""
        return float(np.max(self.c.vec.FV().NumPy()))

    def integral(self):
        """int c dV (with the lumped mass, the quantity the scheme balances)."""
        return float(ngs.Integrate(self.c * ngs.dx(intrules=dict(_VERTEX_RULES)), self.mesh))


def logistic(t, c0, alpha):
    """The logistic solution c(t) = c0 e^(alpha t) / (1 - c0 + c0 e^(alpha t)): the
    spatially uniform solution of the Fisher-KPP equation."""
    e = np.exp(alpha * np.asarray(t, float))
    return c0 * e / (1 - c0 + c0 * e)


def logistic_integral(t, c0, alpha):
    """int_0^t c ds = ln(1 - c0 + c0 e^(alpha t)) / alpha for the logistic solution."""
    return np.log(1 - c0 + c0 * np.exp(alpha * np.asarray(t, float))) / alpha


def minimal_front_speed(D, alpha):
    """The speed 2 sqrt(D alpha) that fronts from compact seeds approach (from below)."""
    return 2.0 * np.sqrt(D * alpha)
