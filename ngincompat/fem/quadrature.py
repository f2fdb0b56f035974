"""The integration rule of the energy form: NGSolve's Gauss rules or symmetric rules on
tetrahedra, and "auto", the cheaper of the two for the mesh and order.

The tangent of the energy Pi(u) = int Jg Psi(Fe) dV (eq. 30) multiplies Grad u by Grad u, a
polynomial of degree 2 (p - 1) on a tetrahedron for a displacement of order p, and NGSolve
integrates the energy, its residual and its tangent with its rule of that degree,
2 p - 2 ("gauss"): on tetrahedra a collapsed (Duffy) product of Gauss rules with p^3 points,
216 at order 6. The cost of the tangent's element matrices grows with the points.

"symmetric" integrates the same three with a fully symmetric rule of the same degree
(Xiao & Gimbutas, Comput. Math. Appl. 59, 2010), taken from the library basix of FEniCS
(fenics-basix, a dependency): 74 points at degree 10, 122 at 12. Both rules integrate every
polynomial of degree 2 p - 2 exactly, so on straight-sided tetrahedra the linearised elastic
energy of any displacement of order p is integrated exactly and neither rule has a
displacement mode without energy (a rule of lower degree can: NGSolve's Gauss rule of
degree 9 on order 6 has five points per direction, and a mode vanishing at all of them left
the solution's own energy accurate while its true energy was off by a factor 4500).
Energy, residual and tangent share the rule, so Newton's tangent stays consistent.

The nonlinear energy density is not a polynomial: the two rules give energies that differ by
the quadrature error, of the order of the discretisation error. :data:`CHECK_DEGREE` is the
degree at which the energy of a solution is integrated again to measure it.

"auto" (:func:`resolve`) takes the symmetric rule on a mesh of tetrahedra where it has at most
half of the points of NGSolve's rule of the same degree: from degree 9, where NGSolve's rule on
tetrahedra is a collapsed product (order 6: 74 points against 216; order 7: 122 against 343),
so on tetrahedra of order 6 to 8. Below, NGSolve's rules are symmetric rules of about the same
size (44 against 46 points at degree 8) and "auto" keeps them, so the energies of those
scenes do not move; on hexahedra it is "gauss".
"""

from types import ModuleType

import ngsolve as ngs

from ngincompat import parallel
from ngincompat.errors import ParameterError, require

#: The rules of the energy form ("auto": the cheaper of the other two, :func:`resolve`).
QUADRATURES = ("auto", "gauss", "symmetric")
#: The highest degree basix has a symmetric tetrahedral rule for (Xiao-Gimbutas: 1 to 15).
SYMMETRIC_MAX_DEGREE = 15
#: The degree at which the energy of a solution is integrated again, by NGSolve's Gauss
#: rule, to check a cheaper rule (beyond the rule of order 8 displacements, 2 * 8 - 2 = 14).
CHECK_DEGREE = 16


def degree(order: int) -> int:
    """The degree of the energy form's rule for a displacement of ``order`` on tetrahedra:
    2 order - 2 (at least 1), NGSolve's own choice for a form in the gradients."""
    return max(2 * order - 2, 1)


def check_quadrature(quadrature: str, order: int) -> None:
    """Raise ParameterError unless ``quadrature`` names a rule (:data:`QUADRATURES`) that
    exists for a displacement of ``order`` (symmetric: and basix is installed)."""
    require(quadrature in QUADRATURES, "quadrature", quadrature,
            ", ".join(QUADRATURES[:-1]) + " or " + QUADRATURES[-1])
    if quadrature == "symmetric":
        require(degree(order) <= SYMMETRIC_MAX_DEGREE, "quadrature", quadrature,
                f"gauss for order {order} (symmetric rules of degree 2 order - 2 <= "
                f"{SYMMETRIC_MAX_DEGREE}: order <= {SYMMETRIC_MAX_DEGREE // 2 + 1})")
        _basix()


def _basix() -> ModuleType:
    """The module basix; ParameterError naming the setting if it is not installed."""
    try:
        import basix
    except ImportError:
        raise ParameterError(
            "quadrature = symmetric needs the library basix, a dependency of ngincompat: pip "
            "install fenics-basix; or set quadrature=gauss") from None
    return basix


def symmetric_rule(degree: int) -> ngs.IntegrationRule:
    """The fully symmetric rule of ``degree`` on NGSolve's reference tetrahedron, an
    :class:`ngsolve.IntegrationRule`.

    basix's reference tetrahedron is NGSolve's, {x, y, z >= 0, x + y + z <= 1} (the vertices
    numbered differently, which a symmetric rule does not see), with weights summing to its
    volume 1/6, so points and weights are taken as they are.

    Raises
    ------
    ParameterError
        basix is not installed (``quadrature`` names the setting).
    """
    basix = _basix()
    points, weights = basix.make_quadrature(basix.CellType.tetrahedron, degree,
                                            rule=basix.QuadratureType.xiao_gimbutas)
    return ngs.IntegrationRule([tuple(map(float, p)) for p in points],
                               [float(w) for w in weights])


def _other_shapes(mesh: ngs.Mesh) -> set[str]:
    """The element types of ``mesh`` other than tetrahedra (on this rank)."""
    return {str(el.type) for el in mesh.Elements(ngs.VOL)} - {str(ngs.ET.TET)}


def resolve(quadrature: str, mesh: ngs.Mesh, order: int) -> str:
    """The rule ``quadrature`` stands for on ``mesh`` for a displacement of ``order``:
    "gauss" or "symmetric" as given; "auto" is "symmetric" where the mesh has only tetrahedra
    (on every rank) and the symmetric rule of degree 2 order - 2 has at most half the points
    of NGSolve's, else "gauss"."""
    check_quadrature(quadrature, order)
    if quadrature != "auto":
        return quadrature
    d = degree(order)
    if d > SYMMETRIC_MAX_DEGREE or parallel.total(mesh, len(_other_shapes(mesh))) > 0:
        return "gauss"
    points = len(ngs.IntegrationRule(ngs.ET.TET, d).points)
    return "symmetric" if 2 * len(symmetric_rule(d).points) <= points else "gauss"


def volume_measure(mesh: ngs.Mesh, order: int,
                   quadrature: str = "gauss") -> ngs.comp.DifferentialSymbol:
    """``ngs.dx`` with the rule ``quadrature`` (after :func:`resolve`) for a displacement of
    ``order`` on ``mesh``.

    Raises
    ------
    ParameterError
        ``quadrature`` is unknown, or "symmetric" on a mesh with elements other than
        tetrahedra (the symmetric rules are for tetrahedra only) or beyond its degrees.
    """
    if resolve(quadrature, mesh, order) == "gauss":
        return ngs.dx
    shapes = _other_shapes(mesh)
    require(not shapes, "quadrature", quadrature,
            f"gauss on a mesh with {', '.join(sorted(shapes))} elements (symmetric rules are "
            "for tetrahedra: elements=tet)")
    return ngs.dx(intrules={ngs.TET: symmetric_rule(degree(order))})
