"""A body in plane strain solved on its section (a two-dimensional mesh, the displacement
(u1, u2), :func:`ngincompat.mechanics.kinematics.displacement_gradient` embedding its
gradient with F33 = 1) against the same body as a three-dimensional slab of tetrahedra held
by u3 = 0 on both faces: an independent discretisation of the same solution."""

import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import Glue, OCCGeometry, WorkPlane, X, Y, Z

from geometries import bilayer
from ngincompat.errors import ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import displacement_space, rigid_pins
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_coupled
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw
from ngincompat.mechanics.materials import NeoHookean, Regional

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


@pytest.mark.parametrize("symmetry, pins", [({}, 3), ({"left": "x"}, 1),
                                            ({"left": "x", "bottom": "y"}, 0)])
def test_a_section_is_pinned_against_the_rigid_motions_its_supports_leave(symmetry, pins):
    """Of the three rigid motions of a section (two translations, the rotation about X3)
    a roller end leaves the vertical translation, a roller bottom besides it none."""
    mesh = bilayer(length=LENGTH, height=HEIGHT, cortex=CORTEX, maxh=0.25)
    space = displacement_space(mesh, 2, symmetry=symmetry)
    assert len(rigid_pins(mesh, space)) == pins


def test_a_section_has_no_third_axis_to_hold():
    mesh = bilayer(length=LENGTH, height=HEIGHT, cortex=CORTEX, maxh=0.25)
    with pytest.raises(ParameterError, match="symmetry axis = 'z'.*x or y"):
        displacement_space(mesh, 2, symmetry={"left": "z"})
