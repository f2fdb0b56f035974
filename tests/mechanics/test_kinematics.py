"""ngincompat.mechanics.kinematics: F = Fe Fg and its measures, and the section in plane strain."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at
from netgen.occ import Glue, OCCGeometry, WorkPlane, X, Y, Z

from geometries import bilayer
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_coupled
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw
from ngincompat.mechanics.materials import NeoHookean, Regional

# A body in plane strain solved on its section (a two-dimensional mesh, the displacement
# (u1, u2), displacement_gradient embedding its gradient with F33 = 1) against the same body
# as a three-dimensional slab of tetrahedra held by u3 = 0 on both faces: an independent
# discretisation of the same solution.

LENGTH, HEIGHT, CORTEX, DEPTH = 1.0, 0.5, 0.1, 0.05


def slab(maxh=0.1, cortex_maxh=0.04):
    """The section extruded through DEPTH along X3, meshed with tetrahedra: boundaries as
    the section's, the two faces X3 = 0, DEPTH ``sides``."""
    parts = []
    for name, low, high in (("subcortex", 0.0, HEIGHT - CORTEX),
                            ("cortex", HEIGHT - CORTEX, HEIGHT)):
        solid = WorkPlane().MoveTo(0, low).Rectangle(LENGTH, high - low).Face().Extrude(
            DEPTH * Z)
        solid.faces.Min(X).name, solid.faces.Max(X).name = "left", "right"
        solid.faces.Min(Z).name = solid.faces.Max(Z).name = "sides"
        solid.faces.Min(Y).name = "bottom" if low == 0 else "interface"
        solid.faces.Max(Y).name = "top" if name == "cortex" else "interface"
        solid.mat(name)
        if name == "cortex":
            solid.maxh = cortex_maxh
        parts.append(solid)
    return ngs.Mesh(OCCGeometry(Glue(parts)).GenerateMesh(maxh=maxh))


def grown(mesh, symmetry):
    """The cortex grown by 10 % along e1, the left end on rollers, the rest of the rigid
    motions pinned: the bilayer bends as a bimetal. The problem and its growth term."""
    material = Regional(mesh, {"cortex": NeoHookean(3.0, 300.0),
                               "subcortex": NeoHookean(1.0, 100.0)})
    f0 = fields.by_region(mesh, {"cortex": fields.constant("e1"),
                                 "subcortex": fields.constant("e2")}, "f0")
    law = RegionalLaw(mesh, {"cortex": ConstantRateLaw(0.1), "subcortex": ConstantRateLaw(0)})
    growth = GrowthEnergy("fiber", f0, law, material)
    problem = CoupledProblem(mesh, [growth], order=2, symmetry=symmetry)
    assert solve_coupled(problem, t_end=1.0, dt=0.5,
                         options=NewtonOptions(rtol=1e-8, line_search=False)).converged
    return problem, growth


@pytest.fixture(scope="module")
def both():
    section = grown(bilayer(length=LENGTH, height=HEIGHT, cortex=CORTEX, maxh=0.1,
                            cortex_maxh=0.025), {"left": "x"})
    solid = grown(slab(), {"left": "x", "sides": "z"})
    return section, solid


def test_the_section_bends_as_the_slab_in_plane_strain(both):
    """The top's deflection along its length and the energy per unit depth of the section
    are the slab's, within the discretisations' difference; the slab's u3 is zero."""
    (section, section_growth), (solid, solid_growth) = both
    x = np.linspace(0.0, LENGTH, 11)
    top2 = np.array([section.u(section.mesh(xi, HEIGHT - 1e-9))[1] for xi in x])
    top3 = np.array([solid.u(solid.mesh(xi, HEIGHT - 1e-9, DEPTH / 2)) for xi in x])
    bend = np.ptp(top2)
    assert bend > 0.01                                      # it bends
    np.testing.assert_allclose(top2 - top2[0], top3[:, 1] - top3[0, 1], atol=0.005 * bend)
    assert np.abs(top3[:, 2]).max() < 1e-3 * bend           # plane strain
    energy2 = section_growth.energy()
    energy3 = solid_growth.energy() / DEPTH
    assert energy2 == pytest.approx(energy3, rel=0.005)


def test_the_embedded_gradient_has_a_zero_third_row_and_column(both):
    (section, _), _ = both
    grad = kinematics.displacement_gradient(section.u)
    F = kinematics.deformation_gradient(section.u)
    values = np.asarray(grad(section.mesh(0.5, 0.45))).reshape(3, 3)
    assert np.abs(values[:2, :2]).max() > 1e-3
    assert np.all(values[2, :] == 0) and np.all(values[:, 2] == 0)
    assert np.asarray(F(section.mesh(0.5, 0.45))).reshape(3, 3)[2, 2] == 1.0


#: A homogeneous deformation gradient H = Grad u and a growth tensor (any invertible one).
H = np.array([[0.10, -0.05, 0.02], [0.03, -0.08, 0.04], [-0.06, 0.01, 0.12]])
FG = np.array([[1.2, 0.1, 0.0], [0.0, 0.9, 0.05], [0.1, 0.0, 1.1]])


def _matrix_cf(m):
    return ngs.CF(tuple(np.asarray(m, float).ravel()), dims=(3, 3))


def test_the_split_of_a_homogeneous_deformation_in_closed_form(unit_cube_tet):
    """u = H X: Grad u = H, F = I + H, Fe = F Fg^-1 (eq. 1), J = det F (eq. 2), and
    Fe Fg = F, Je Jg = J, at every point."""
    u = ngs.GridFunction(ngs.VectorH1(unit_cube_tet, order=1))
    u.Set(_matrix_cf(H) * ngs.CF((ngs.x, ngs.y, ngs.z)))
    F = kinematics.deformation_gradient(u)
    Fe = kinematics.elastic_part(F, _matrix_cf(FG))
    points = random_points(5)
    F_expected = np.eye(3) + H
    np.testing.assert_allclose(values_at(kinematics.displacement_gradient(u), unit_cube_tet,
                                         points).reshape(-1, 3, 3), np.broadcast_to(H, (5, 3, 3)),
                               atol=1e-13)
    np.testing.assert_allclose(values_at(Fe, unit_cube_tet, points).reshape(-1, 3, 3),
                               np.broadcast_to(F_expected @ np.linalg.inv(FG), (5, 3, 3)),
                               atol=1e-13)
    np.testing.assert_allclose(values_at(kinematics.jacobian(F), unit_cube_tet, points)[:, 0],
                               np.linalg.det(F_expected), rtol=1e-13)
    Je = values_at(kinematics.jacobian(Fe), unit_cube_tet, points)[:, 0]
    np.testing.assert_allclose(Je * np.linalg.det(FG), np.linalg.det(F_expected), rtol=1e-13)


def test_a_nonlinear_displacement_has_its_exact_gradient(unit_cube_tet):
    """u quadratic in X, interpolated exactly at order 2: Grad u is its Jacobian matrix."""
    x, y, z = ngs.x, ngs.y, ngs.z
    u = ngs.GridFunction(ngs.VectorH1(unit_cube_tet, order=2))
    u.Set(ngs.CF((0.1 * x * y, 0.2 * z * z - 0.1 * x, 0.05 * x * x + 0.3 * y * z)))
    points = random_points(6, seed=2)
    got = values_at(kinematics.deformation_gradient(u), unit_cube_tet, points).reshape(-1, 3, 3)
    for (px, py, pz), F in zip(points, got, strict=True):
        expected = np.eye(3) + np.array([[0.1 * py, 0.1 * px, 0.0],
                                         [-0.1, 0.0, 0.4 * pz],
                                         [0.1 * px, 0.3 * pz, 0.3 * py]])
        np.testing.assert_allclose(F, expected, atol=1e-12)


def test_the_component_form_is_the_vector_form(unit_cube_tet):
    """F from three scalar fields u_i (row i of Grad u is grad u_i) equals F of the vector
    field (u_1, u_2, u_3)."""
    x, y, z = ngs.x, ngs.y, ngs.z
    exact = (0.1 * x * y, 0.2 * z * z - 0.1 * x, 0.05 * x * x + 0.3 * y * z)
    vector = ngs.GridFunction(ngs.VectorH1(unit_cube_tet, order=2))
    vector.Set(ngs.CF(exact))
    components = []
    for ui in exact:
        gf = ngs.GridFunction(ngs.H1(unit_cube_tet, order=2))
        gf.Set(ui)
        components.append(gf)
    F_components = kinematics.component_deformation_gradient(components)
    F_vector = kinematics.deformation_gradient(vector)
    diff = F_components - F_vector
    assert ngs.Integrate(ngs.InnerProduct(diff, diff), unit_cube_tet) < 1e-24
    assert ngs.Integrate(ngs.InnerProduct(F_vector, F_vector), unit_cube_tet) > 3


def test_a_section_in_plane_strain_has_f33_one_and_its_determinant_in_the_plane():
    """u = (a X1 + b X2, c X1 + d X2) on a section: F = [[1 + a, b, 0], [c, 1 + d, 0],
    [0, 0, 1]] and J = (1 + a)(1 + d) - b c."""
    a, b, c, d = 0.1, -0.2, 0.05, 0.3
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    u = ngs.GridFunction(ngs.VectorH1(mesh, order=1))
    u.Set(ngs.CF((a * ngs.x + b * ngs.y, c * ngs.x + d * ngs.y)))
    F = kinematics.deformation_gradient(u)
    assert tuple(F.dims) == (3, 3)
    point = mesh(0.3, 0.2)
    np.testing.assert_allclose(np.asarray(F(point)).reshape(3, 3),
                               [[1 + a, b, 0], [c, 1 + d, 0], [0, 0, 1]], atol=1e-13)
    assert kinematics.jacobian(F)(point) == pytest.approx((1 + a) * (1 + d) - b * c, rel=1e-13)
