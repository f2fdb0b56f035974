"""Intrinsic incompatibility: the curvature of the growth metric Cg = Fg^T Fg.

G (eq. 10) vanishes only when Fg is a gradient; the growth is *compatible* (a stress-free
state exists, simply connected body) exactly when the Riemann tensor of the metric
Cg = Fg^T Fg vanishes. In 3-D the Weyl tensor is zero, so Riemann = 0 <=> Ricci = 0 <=>
Einstein = 0. Two paths lead to the curvature:

* **exact** (:func:`curvature_exact`): for an analytic Fg, the Christoffel symbols, Riemann,
  Ricci, scalar curvature and Einstein tensor of Cg by symbolic differentiation (``CF.Diff``);
  exact to round-off;
* **discrete** (:mod:`ngincompat.incompatibility.regge`): Cg interpolated into the Regge
  space and its distributional Einstein tensor; the path for computed growth fields.

Conventions
-----------
Cartesian reference coordinates X, metric g = Cg, and the sign convention of Lee,
*Introduction to Riemannian manifolds*, which NGSolve's ``HCurlCurl`` operators use::

    Gamma_ijk   = 1/2 (d_i g_jk + d_j g_ik - d_k g_ij)                (first kind)
    Gamma_ij^k  = g^kl Gamma_ijl                                       (second kind)
    R_ijkl      = d_i Gamma_jkl - d_j Gamma_ikl
                  + Gamma_ik^p Gamma_jlp - Gamma_jk^p Gamma_ilp
    Ric_ij      = g^kl R_kijl,   S = g^ij Ric_ij,   Ein = Ric - S/2 g

so that a sphere of radius r has S = 6 / r^2 (3-D) and Ric = 2 / r^2 g. The derivative part
of Riemann is written with the incompatibility operator,
d_i Gamma_jkl - d_j Gamma_ikl = 1/2 eps_ija eps_klb inc(g)^ab with
inc(g)^ab = eps_amn eps_bpq d_m d_p g_nq, so that for g = I + 2 eps the linearisation is
Ein = inc(eps) + O(eps^2): Kröner's relation inc(sym H) = Curl(G - tr(G)/2 I) + O(|H|^2) for
Fg = I + H (the paper's Curl, eq. 7).

Frame-invariant outputs: the scalar curvature S, the g-norm |Ein|_g = sqrt(Ein : g^-1 Ein g^-1)
and the Einstein tensor pushed to the intermediate configuration,
Fg^-T Ein Fg^-1 (orthonormal components in the frame in which G is written). Curvature has
units 1/length^2.
"""

from dataclasses import dataclass
from typing import TypeAlias

import ngsolve as ngs
from ngsolve.fem import Einsum

from ngincompat import config
from ngincompat.incompatibility import regge
from ngincompat.incompatibility.operators import gradient_exact, levi_civita
from ngincompat.sampling import maximum

CF: TypeAlias = ngs.CoefficientFunction
_COORDS = (ngs.x, ngs.y, ngs.z)


@dataclass(frozen=True, eq=False)
class Curvature:
    """The curvature of a metric g on a 3-D body, as CoefficientFunctions.

    The Riemann tensor (81 components) is built only when asked for (:attr:`riemann`); the
    scene outputs need S and Ein alone, which the 3-D curvature operator gives at a fraction
    of the cost.

    Attributes
    ----------
    metric : CF (3x3)
        g.
    christoffel : CF (3x3x3)
        Gamma_ijk, first kind.
    christoffel2 : CF (3x3x3)
        Gamma_ij^k, second kind (the raised index last).
    incompatibility : CF (3x3)
        inc(g) + E with E^ab = eps_akl eps_bmn Gamma_km^q Gamma_lnq: the curvature operator
        Q = -(inc(g) + E) / (2 det g), R_ijkl = det(g) eps_ija eps_klb Q^ab (3-D).
    scalar : CF
        S = 2 g : Q = -g : (inc(g) + E) / det g.
    einstein : CF (3x3)
        Ein = -g Q g = g (inc(g) + E) g / (2 det g), covariant components in reference
        coordinates; equal to Ric - S/2 g.
    """

    metric: ngs.CoefficientFunction
    christoffel: ngs.CoefficientFunction
    christoffel2: ngs.CoefficientFunction
    incompatibility: ngs.CoefficientFunction
    scalar: ngs.CoefficientFunction
    einstein: ngs.CoefficientFunction

    @property
    def riemann(self) -> CF:
        """R_ijkl = d_i Gamma_jkl - d_j Gamma_ikl + Gamma_ik^p Gamma_jlp - Gamma_jk^p Gamma_ilp,
        from the coordinate formula (the derivative part as 1/2 eps_ija eps_klb inc(g)^ab)."""
        eps = levi_civita()
        chr1, chr2 = self.christoffel, self.christoffel2
        return (0.5 * Einsum("ija,klb,ab->ijkl", eps, eps, inc(self.metric))
                + Einsum("ikp,jlp->ijkl", chr2, chr1) - Einsum("jkp,ilp->ijkl", chr2, chr1))

    @property
    def ricci(self) -> CF:
        """Ric = Ein + S/2 g."""
        return self.einstein + 0.5 * self.scalar * self.metric

    def einstein_norm(self) -> CF:
        """|Ein|_g = sqrt(Ein_ij g^ik g^jl Ein_kl), frame-invariant."""
        return einstein_norm(self.einstein, self.metric)


def inc(g: CF) -> CF:
    """inc(g)^ab = eps_amn eps_bpq d_m d_p g_nq of an analytic symmetric 3x3 CF.

    Second derivatives by symbolic differentiation; for a row-wise curl this is
    curl((curl g)^T), the Saint-Venant incompatibility operator.
    """
    d2g = ngs.CF(tuple(g[n, q].Diff(_COORDS[m]).Diff(_COORDS[p])
                       for m in range(3) for p in range(3)
                       for n in range(3) for q in range(3)), dims=(3, 3, 3, 3))
    eps = levi_civita()
    return Einsum("amn,bpq,mpnq->ab", eps, eps, d2g)


def curvature_exact(g: CF) -> Curvature:
    """The curvature of an analytic metric g (3x3 CF of x, y, z) by ``CF.Diff``.

    Parameters
    ----------
    g : CoefficientFunction
        A symmetric positive definite 3x3 field, e.g. Cg = Fg^T Fg.

    Returns
    -------
    Curvature
    """
    dg = gradient_exact(g)                       # dg[j, k, i] = d_i g_jk
    chr1 = 0.5 * (Einsum("jki->ijk", dg) + Einsum("ikj->ijk", dg) - dg)
    chr2 = Einsum("ijp,pk->ijk", chr1, ngs.Inv(g))
    eps = levi_civita()
    total = inc(g) + Einsum("akl,bmn,kmq,lnq->ab", eps, eps, chr2, chr1)
    det = ngs.Det(g)
    return Curvature(metric=g, christoffel=chr1, christoffel2=chr2, incompatibility=total,
                     scalar=-ngs.InnerProduct(g, total) / det,
                     einstein=(0.5 / det) * (g * total * g))


def growth_metric(Fg: CF) -> CF:
    """Cg = Fg^T Fg, the metric that growth gives the reference body."""
    return Fg.trans * Fg


def einstein_norm(einstein: CF, g: CF) -> CF:
    """|Ein|_g = sqrt(Ein : g^-1 Ein g^-1), frame-invariant (1/length^2)."""
    g_inv = ngs.Inv(g)
    return ngs.sqrt(ngs.InnerProduct(g_inv * einstein * g_inv, einstein))


def einstein_intermediate(einstein: CF, Fg: CF) -> CF:
    """Fg^-T Ein Fg^-1: the Einstein tensor of Cg in the intermediate configuration.

    The growth coframe Fg dX is Cg-orthonormal, so these are orthonormal components, in the
    frame in which G = (1/Jg) Fg Curl Fg (eq. 10) is written; their Frobenius norm is
    |Ein|_g.
    """
    Fg_inv = ngs.Inv(Fg)
    return Fg_inv.trans * einstein * Fg_inv


def growth_curvature(Fg: CF) -> Curvature:
    """The exact curvature of the growth metric Cg = Fg^T Fg of an analytic Fg."""
    return curvature_exact(growth_metric(Fg))


#: Round-off level of the exact path: curvature below ROUNDOFF * |G|^2 (the size curvature
#: built from the incompatibility G would have) is zero in double precision.
ROUNDOFF = 1e-10


def measure(einstein: CF, scalar: CF, g: CF, mesh: ngs.Mesh, G: CF, mirror: float = 1,
            order: int = 6, reference: CF | None = None) -> tuple[dict, dict]:
    """Fields and metrics of a curvature for a scene's results.

    Parameters
    ----------
    einstein, scalar : CoefficientFunction
        Ein (covariant, reference coordinates) and S of the metric ``g``.
    g : CoefficientFunction
        The metric (Cg, or its Regge interpolant).
    mesh : ngsolve.Mesh
    G : CoefficientFunction
        The incompatibility tensor (eq. 10), for the round-off scale.
    mirror : int
        Mirror copies of the mesh that make the body (integrals are of the whole body).
    order : int
        Quadrature order of the L2 norm; the estimate of its error compares with order + 4.
    reference : CoefficientFunction, optional
        A less accurate Einstein tensor of the same metric (the discrete path one degree
        lower): ||Ein - reference||_g is added to the error estimate, a conservative estimate
        of the discretisation error.

    Returns
    -------
    fields : dict
        ``scalar_curvature`` (S) and ``einstein_norm_g`` (|Ein|_g), 1/length^2.
    metrics : dict
        ``scalar_curvature_min``, ``scalar_curvature_max``, ``einstein_norm_L2``
        (||Ein||_g over the reference body, 1/length^(1/2)) and ``einstein_norm_L2_error``:
        the quadrature error of that norm, the difference from ``reference`` and the
        round-off level ROUNDOFF ||G (x) G||_L2.
    """
    norm = einstein_norm(einstein, g)

    def l2(cf: CF, o: int) -> float:
        return (mirror * max(float(ngs.Integrate(cf * cf, mesh, order=o)), 0.0)) ** 0.5

    value = l2(norm, order)
    GG = ngs.InnerProduct(G, G)
    error = abs(value - l2(norm, order + 4)) + ROUNDOFF * l2(GG, order)
    if reference is not None:
        error += l2(einstein_norm(einstein - reference, g), order)
    return ({"scalar_curvature": scalar, "einstein_norm_g": norm},
            {"scalar_curvature_min": -maximum(-scalar, mesh),
             "scalar_curvature_max": maximum(scalar, mesh),
             "einstein_norm_L2": value, "einstein_norm_L2_error": error})


def measure_growth(Fg: CF, mesh: ngs.Mesh, G: CF, exact: bool = True, mirror: float = 1,
                   regge_order: int = 2) -> tuple[dict, dict]:
    """Curvature fields and metrics (:func:`measure`) of the growth metric Cg = Fg^T Fg.

    ``exact``: Fg is analytic (a CF of x, y, z) and the exact path applies; otherwise the
    Regge path of degree ``regge_order`` (:mod:`ngincompat.incompatibility.regge`, tetrahedral
    meshes), its
    error estimated against degree ``regge_order - 1``.
    """
    if exact:
        curv = growth_curvature(Fg)
        return measure(curv.einstein, curv.scalar, curv.metric, mesh, G, mirror=mirror)
    config.ensure_heap(10**8)
    g = growth_metric(Fg)
    discrete = regge.discrete_curvature(g, mesh, order=regge_order)
    lower = regge.discrete_curvature(g, mesh, order=regge_order - 1).einstein
    return measure(discrete.einstein, discrete.scalar, discrete.gh, mesh, G, mirror=mirror,
                   reference=lower)
