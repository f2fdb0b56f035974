"""The distributional Einstein tensor of a Regge metric: curvature of computed growth fields.

The growth metric Cg = Fg^T Fg is interpolated into the Regge space (NGSolve's
``HCurlCurl``: piecewise polynomial symmetric matrices of degree k whose tangential-tangential
components are continuous across facets) by its canonical interpolant. A Regge metric is
smooth inside elements only; its curvature is a distribution with three parts (Gawlik &
Neunteufel, "Finite element approximation of the Einstein tensor", IMA J. Numer. Anal. 2025,
doi:10.1093/imanum/draf004), acting on a symmetric matrix field phi::

    G~(phi) = sum_T int_T <Ein, phi> omega_T                      (element term)
            + sum_F int_F <[[II - H g_F]], phi|_F> omega_F        (jump of the trace-reversed
                                                                   second fundamental form)
            - sum_E int_E Theta_E phi(t_g, t_g) omega_E           (angle defect)

with omega_T = sqrt(det g), omega_F = sqrt(cof(g) n.n), omega_E = sqrt(g(t, t)), II the second
fundamental form of a facet in g, H = tr_g II its mean curvature, [[.]] the sum over the two
sides with outward normals, Theta_E = 2 pi - sum_T (g-dihedral angle of T at E) the angle
defect and t_g the g-unit tangent of the edge. For a Regge metric of degree k >= 1, G~
converges to the Einstein tensor of the smooth metric as h^(k+1) in H^-2; the element term
alone converges as h^(k-1) in L2.

Free boundaries. On the body's boundary the one-sided facet and edge terms measure how the
boundary surface bends in the metric g (its extrinsic curvature), not an incompatibility of
the growth: a flat metric on a ball has them, and a stress-free state of a free body exists
regardless of them. They are left out: only interior facets and interior edges contribute,
so the functional is consistent (its lift converges to Ein of the smooth metric up to the
boundary) for test functions that do not vanish there.

Output. The functional is lifted to Lagrange elements of degree p, component by component
(six scalar mass-matrix solves): (E_h, v) = G~(v), E_h ~ sqrt(det g) g^-1 Ein g^-1; the
covariant Einstein tensor is then g E_h g / sqrt(det g). In 3-D tr_g Ein = -S/2 gives the
scalar curvature.
"""

from dataclasses import dataclass
from typing import TypeAlias

import ngsolve as ngs

#: Component pairs (i, j), i <= j, of a symmetric 3x3 tensor.
CF: TypeAlias = ngs.CoefficientFunction
_PAIRS = tuple((i, j) for i in range(3) for j in range(i, 3))


def regge_interpolant(g: CF, mesh: ngs.Mesh, order: int,
                      bonus_intorder: int = 4) -> ngs.GridFunction:
    """The canonical Regge interpolant of a metric g, degree ``order`` (tt-moments on edges
    and facets, inner moments), as a GridFunction of ``HCurlCurl``."""
    gh = ngs.GridFunction(ngs.HCurlCurl(mesh, order=order))
    gh.Set(g, dual=True, bonus_intorder=bonus_intorder)
    return gh


def _interior_indicators(mesh: ngs.Mesh) -> tuple[CF, CF]:
    """1 on interior facets and interior edges, 0 on the body's boundary.

    Facets: a lowest-order FacetFESpace function, one value per facet. Edges: a quadratic H1
    function whose only nonzero coefficients are the edge bubbles of boundary edges; its trace
    on an edge depends on that edge's coefficients and its two vertices' alone, so it is
    nonzero inside exactly the boundary edges.
    """
    facets = ngs.GridFunction(ngs.FacetFESpace(mesh, order=0))
    edges = ngs.GridFunction(ngs.H1(mesh, order=2))
    for el in mesh.Elements(ngs.BND):
        for face in el.faces:
            for dof in facets.space.GetDofNrs(face):
                facets.vec[dof] = 1.0
        for edge in el.edges:
            for dof in edges.space.GetDofNrs(edge):
                edges.vec[dof] = 1.0
    return 1 - facets, ngs.IfPos(edges * edges - 1e-12, 0.0, 1.0)


@dataclass(frozen=True, eq=False)
class DistributionalEinstein:
    """The three densities of G~ for a Regge metric ``gh`` (contravariant, densitised).

    ``volume``, ``facet`` and ``edge`` are 3x3 CFs to be paired with a test field and
    integrated over ``dx``, ``dx(element_boundary=True)`` and ``dx(element_vb=BBND)``.
    """

    gh: ngs.GridFunction
    volume: ngs.CoefficientFunction
    facet: ngs.CoefficientFunction
    edge: ngs.CoefficientFunction

    @classmethod
    def of(cls, gh: ngs.GridFunction) -> "DistributionalEinstein":
        mesh = gh.space.mesh
        g_inv = ngs.Inv(gh)
        # element term: sqrt(det g) g^-1 Ein g^-1
        volume = ngs.sqrt(ngs.Det(gh)) * g_inv * gh.Operator("Einstein") * g_inv
        # facet term: II^ij - H g_F^ij with nu the g-unit outward normal,
        # II(X, Y) = -g(nabla_X Y, nu) = -Gamma_ijk X^i Y^j nu^k
        n = ngs.specialcf.normal(3)
        nu = g_inv * n / ngs.sqrt(ngs.InnerProduct(g_inv * n, n))
        g_F_inv = g_inv - ngs.OuterProduct(nu, nu)
        II = g_F_inv * (-(gh.Operator("christoffel") * nu)) * g_F_inv
        H = ngs.InnerProduct(gh, II)
        omega_F = ngs.sqrt(ngs.InnerProduct(ngs.Cof(gh) * n, n))
        interior_facet, interior_edge = _interior_indicators(mesh)
        facet = interior_facet * omega_F * (II - H * g_F_inv)
        # edge term: this element's share of the angle defect, Euclidean minus g-dihedral
        # angle, with g-unit conormals in the two faces (in-face vectors projected
        # g-orthogonally to the edge)
        t = ngs.specialcf.tangential(3, True)
        in_face = ngs.specialcf.EdgeFaceTangentialVectors(3)
        g_tt = ngs.InnerProduct(gh * t, t)

        def conormal(w: CF) -> CF:
            w = w - ngs.InnerProduct(gh * w, t) / g_tt * t
            return w / ngs.sqrt(ngs.InnerProduct(gh * w, w))

        m0, m1 = conormal(in_face[:, 0]), conormal(in_face[:, 1])
        defect = (ngs.acos(ngs.InnerProduct(in_face[:, 0], in_face[:, 1]))
                  - ngs.acos(ngs.InnerProduct(gh * m0, m1)))
        t_g = t / ngs.sqrt(g_tt)
        edge = -interior_edge * ngs.sqrt(g_tt) * defect * ngs.OuterProduct(t_g, t_g)
        return cls(gh=gh, volume=volume, facet=facet, edge=edge)

    def apply(self, phi: CF, order: int | None = None) -> float:
        """G~(phi) for a symmetric 3x3 test field phi (an integral)."""
        mesh = self.gh.space.mesh
        opts = {} if order is None else {"bonus_intorder": order}
        return (ngs.Integrate(ngs.InnerProduct(self.volume, phi) * ngs.dx(**opts), mesh)
                + ngs.Integrate(ngs.InnerProduct(self.facet, phi)
                                * ngs.dx(element_boundary=True, **opts), mesh)
                + ngs.Integrate(ngs.InnerProduct(self.edge, phi)
                                * ngs.dx(element_vb=ngs.BBND, **opts), mesh))

    def lift(self, order: int) -> CF:
        """E_h in Lagrange elements of degree ``order``: (E_h, v) = G~(v) componentwise.

        Returns the covariant Einstein tensor g_h E_h g_h / sqrt(det g_h) as a 3x3 CF.
        """
        mesh = self.gh.space.mesh
        space = ngs.H1(mesh, order=order)
        u, v = space.TnT()
        mass = ngs.BilinearForm(u * v * ngs.dx).Assemble()
        inverse = mass.mat.Inverse(inverse="sparsecholesky")
        parts = {}
        for i, j in _PAIRS:
            rhs = ngs.LinearForm(space)
            rhs += self.volume[i, j] * v * ngs.dx
            rhs += self.facet[i, j] * v * ngs.dx(element_boundary=True)
            rhs += self.edge[i, j] * v * ngs.dx(element_vb=ngs.BBND)
            rhs.Assemble()
            gf = ngs.GridFunction(space)
            gf.vec.data = inverse * rhs.vec
            parts[i, j] = parts[j, i] = gf
        E = ngs.CF(tuple(parts[i, j] for i in range(3) for j in range(3)), dims=(3, 3))
        return self.gh * E * self.gh / ngs.sqrt(ngs.Det(self.gh))


@dataclass(frozen=True, eq=False)
class DiscreteCurvature:
    """Curvature of a Regge metric: the element-wise and the lifted distributional Einstein
    tensor, and the scalar curvature S = -2 tr_g Ein of the lift (3-D)."""

    gh: ngs.GridFunction
    einstein_elementwise: ngs.CoefficientFunction
    einstein: ngs.CoefficientFunction
    scalar: ngs.CoefficientFunction


def discrete_curvature(g: CF, mesh: ngs.Mesh, order: int = 2,
                       lift_order: int | None = None) -> DiscreteCurvature:
    """The curvature of the Regge interpolant of degree ``order`` of a metric g.

    Parameters
    ----------
    g : CoefficientFunction
        The metric (e.g. Cg of a projected or computed Fg), 3x3.
    mesh : ngsolve.Mesh
        Tetrahedral mesh.
    order : int
        Regge degree k >= 1 (k = 0, Regge calculus, does not converge in 3-D).
    lift_order : int, optional
        Lagrange degree of the lift (default k: degree k + 1 does not converge in 3-D).
    """
    gh = regge_interpolant(g, mesh, order)
    einstein = DistributionalEinstein.of(gh).lift(order if lift_order is None else lift_order)
    return DiscreteCurvature(gh=gh, einstein_elementwise=gh.Operator("Einstein"),
                             einstein=einstein,
                             scalar=-2 * ngs.InnerProduct(einstein, ngs.Inv(gh)))
