"""The energy form's rules: exactness of the symmetric tetrahedral rules, the cube on them,
and the errors of a rule that cannot be used."""

import math
import sys

import ngsolve as ngs
import pytest

from geometries import cube
from ngincompat.errors import ParameterError
from ngincompat.fem import quadrature
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.stepping import solve_growth
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.scenes.cube import CubeScene
from ngincompat.studies.bench import CUBE_ENERGY


def monomial_integral(a, b, c):
    """int x^a y^b z^c over {x, y, z >= 0, x + y + z <= 1} = a! b! c! / (a + b + c + 3)!."""
    return (math.factorial(a) * math.factorial(b) * math.factorial(c)
            / math.factorial(a + b + c + 3))


@pytest.mark.parametrize("degree", range(1, quadrature.SYMMETRIC_MAX_DEGREE + 1))
def test_symmetric_rule_integrates_every_monomial_of_its_degree(degree):
    """The NGSolve rule built from basix's points and weights integrates x^a y^b z^c,
    a + b + c <= degree, exactly on NGSolve's reference tetrahedron (closed form); one degree
    more it does not (so the test would see a rule of the wrong degree)."""
    rule = quadrature.symmetric_rule(degree)
    points, weights = list(rule.points), list(rule.weights)

    def apply(a, b, c):
        return sum(w * x ** a * y ** b * z ** c for (x, y, z), w in zip(points, weights,
                                                                          strict=True))

    for n in range(degree + 1):
        for a in range(n + 1):
            for b in range(n - a + 1):
                c = n - a - b
                assert apply(a, b, c) == pytest.approx(monomial_integral(a, b, c),
                                                       rel=1e-12, abs=1e-15)
    worst = max(abs(apply(a, degree + 1 - a, 0) - monomial_integral(a, degree + 1 - a, 0))
                for a in range(degree + 2))
    assert worst > 1e-14


def test_a_form_on_the_symmetric_rule_assembles_on_mapped_elements(unit_cube_tet):
    """On a tetrahedral mesh, the energy int |Grad u|^2 of a polynomial displacement of order
    p (degree 2 p - 2 integrand) on the symmetric rule equals its exact value (NGSolve's rule
    of degree 2 p + 4), and its tangent is the same matrix."""
    order = 4
    V = ngs.VectorH1(unit_cube_tet, order=order)
    gf = ngs.GridFunction(V)
    gf.Set(ngs.CF((ngs.x ** 4 - ngs.y * ngs.z, ngs.x * ngs.y ** 2 * ngs.z, ngs.z ** 3)))
    u = V.TrialFunction()
    exact = ngs.Integrate(ngs.InnerProduct(ngs.Grad(gf), ngs.Grad(gf)), unit_cube_tet,
                          order=2 * order + 4)
    forms = {}
    for name in quadrature.QUADRATURES:
        dx = quadrature.volume_measure(unit_cube_tet, order, name)
        forms[name] = ngs.BilinearForm(V)
        forms[name] += ngs.Variation(ngs.InnerProduct(ngs.Grad(u), ngs.Grad(u)) * dx)
        assert forms[name].Energy(gf.vec) == pytest.approx(exact, rel=1e-12)
        forms[name].AssembleLinearization(gf.vec)
    difference = forms["gauss"].mat.CreateMatrix()
    difference.AsVector().data = forms["gauss"].mat.AsVector() - forms["symmetric"].mat.AsVector()
    assert difference.AsVector().Norm() < 1e-12 * forms["gauss"].mat.AsVector().Norm()


def test_the_default_rule_is_ngsolves_own():
    """The rule of degree 2 order - 2 is the one NGSolve picks for the energy on tetrahedra
    (the symmetric rule replaces it at the same degree): the same energy, bit for bit."""
    mesh = cube(maxh=0.5, elements="tet")
    order = 4
    V = ngs.VectorH1(mesh, order=order)
    gf = ngs.GridFunction(V)
    gf.Set(ngs.CF((0.1 * ngs.sin(ngs.x * ngs.y), 0.05 * ngs.exp(ngs.z), 0.1 * ngs.x)))
    u = V.TrialFunction()
    F = ngs.Id(3) + ngs.Grad(u)
    energies = []
    for dx in (ngs.dx, ngs.dx(intrules={ngs.TET: ngs.IntegrationRule(
            ngs.TET, quadrature.degree(order))})):
        form = ngs.BilinearForm(V)
        form += ngs.Variation(ngs.log(ngs.Det(F)) ** 2 * ngs.InnerProduct(F, F) * dx)
        energies.append(form.Energy(gf.vec))
    assert energies[0] == energies[1]


def test_cube_on_the_symmetric_rule_has_the_energy_of_the_gauss_rule():
    """The cube (tetrahedra of order 3): on either rule Newton takes the same iterations, and
    the solutions' energies, each by its own rule or integrated again at degree 16, differ
    by less than a hundredth of the discretisation error (against the cube's reference
    energy); the scene reports the re-integrated energy of the symmetric rule."""
    energies, iterations = {}, {}
    for name in quadrature.QUADRATURES:
        case = CubeScene(elements="tet", order=3, maxh=0.5, quadrature=name).build()
        problem = case.mechanics()
        history = solve_growth(problem, case.time)
        assert history.converged
        energies[name] = (problem.strain_energy(),
                          problem.strain_energy(quadrature.CHECK_DEGREE))
        iterations[name] = history.newton_iterations
    error = abs(energies["gauss"][1] - CUBE_ENERGY)
    assert error > 1e-3 * CUBE_ENERGY                      # order 3 on 28 elements: coarse
    for rule in (0, 1):
        assert abs(energies["symmetric"][rule] - energies["gauss"][rule]) < 1e-2 * error
    assert iterations["symmetric"] == iterations["gauss"]
    scene = CubeScene(elements="tet", order=3, maxh=0.5, g_order=3, outputs="none",
                      quadrature="symmetric")
    assert scene.run().metrics["strain_energy"] == pytest.approx(energies["symmetric"][1],
                                                                rel=1e-9)


@pytest.mark.parametrize("elements, order, rule", [
    ("tet", 5, "gauss"), ("tet", 6, "symmetric"), ("tet", 8, "symmetric"), ("tet", 9, "gauss"),
    ("hex", 6, "gauss")])
def test_auto_takes_the_symmetric_rule_where_it_has_half_the_points(elements, order, rule):
    """auto: the symmetric rule on tetrahedra from order 6 (74 points against NGSolve's 216)
    to 8 (its last degree), NGSolve's below (44 against 46 points at order 5) and on
    hexahedra; the problem records the rule it took."""
    mesh = cube(maxh=1.0, elements=elements)
    assert quadrature.resolve("auto", mesh, order) == rule
    symmetric = len(quadrature.symmetric_rule(quadrature.degree(6)).points)
    assert 2 * symmetric <= len(ngs.IntegrationRule(ngs.ET.TET, quadrature.degree(6)).points)
    if order <= 6:
        problem = GrowthMechanics(mesh, IsotropicGrowth(1 + 0.25 * ngs.x),
                                  NeoHookean.paper_idealized(), order=order, quadrature="auto")
        assert problem.quadrature == rule


def test_the_cube_defaults_to_the_symmetric_rule_and_reports_the_checked_energy():
    """The cube's defaults (tetrahedra of order 6, auto) run on the symmetric rule, whose
    energy is integrated again at degree 16; hexahedra on auto take NGSolve's rule."""
    scene = CubeScene()
    assert (scene.elements, scene.order, scene.quadrature) == ("tet", 6, "auto")
    assert scene.build().mechanics().quadrature == "symmetric"
    hexahedra = CubeScene(elements="hex", order=2, maxh=0.5)
    assert hexahedra.build().mechanics().quadrature == "gauss"


def test_bad_quadrature_values_name_the_parameter():
    with pytest.raises(ParameterError, match="quadrature.*auto, gauss, symmetric"):
        CubeScene(elements="tet", quadrature="lobatto")
    with pytest.raises(ParameterError, match="quadrature.*gauss or auto with elements=hex"):
        CubeScene(elements="hex", quadrature="symmetric")
    with pytest.raises(ParameterError, match="quadrature.*order <= 8"):
        CubeScene(elements="tet", order=9, quadrature="symmetric")


def test_the_symmetric_rule_refuses_other_elements(unit_cube_hex):
    """GrowthMechanics on a hexahedral mesh: a ParameterError naming the setting, not a rule
    that NGSolve would silently ignore."""
    growth = IsotropicGrowth(1 + 0.25 * ngs.x)
    with pytest.raises(ParameterError, match="quadrature.*HEX"):
        GrowthMechanics(unit_cube_hex, growth, NeoHookean.paper_idealized(), order=2,
                        quadrature="symmetric")


def test_without_basix_the_error_says_what_to_install(monkeypatch):
    """Before anything is computed: the scene's settings are refused."""
    monkeypatch.setitem(sys.modules, "basix", None)
    with pytest.raises(ParameterError, match="fenics-basix.*quadrature=gauss"):
        CubeScene(elements="tet", quadrature="symmetric")
    with pytest.raises(ParameterError, match="fenics-basix.*quadrature=gauss"):
        quadrature.symmetric_rule(10)
    CubeScene(elements="tet", quadrature="gauss")
