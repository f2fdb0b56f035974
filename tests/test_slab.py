"""The bilayer as a slab one prism thick (:func:`geometries.bilayer.extrude`) and its
displacement linear through the depth (:func:`ngincompat.fem.problem.linear_through_depth`):
the mesh is the section's, oriented, with the section's names; the reduced space gives the
plane-strain solution of the full one with fewer unknowns."""

import ngsolve as ngs
import numpy as np
import pytest

from geometries import bilayer, cube
from ngincompat.errors import ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import displacement_space
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_coupled
from ngincompat.fem.terms import GrowthEnergy, RigidPins
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw
from ngincompat.mechanics.materials import NeoHookean, Regional
from ngincompat.sampling import element_points

SLAB = dict(length=1.0, height=0.5, depth=0.05, cortex=0.1, maxh=0.2, cortex_maxh=0.05)


@pytest.fixture(scope="module")
def slab():
    return bilayer(**SLAB)


def test_the_slab_is_one_layer_of_positively_oriented_prisms(slab):
    assert {el.type for el in slab.Elements(ngs.VOL)} == {ngs.ET.PRISM}
    heights = {round(v.point[1], 12) for v in slab.vertices}
    assert heights == {0.0, 0.05}
    jacobian = ngs.Det(ngs.specialcf.JacobianMatrix(3))
    assert np.min(np.asarray(jacobian(element_points(slab, 2)))) > 0


@pytest.mark.parametrize("boundary, normal, area", [
    ("top", (0, 0, 1), 0.05), ("bottom", (0, 0, -1), 0.05), ("left", (-1, 0, 0), 0.025),
    ("right", (1, 0, 0), 0.025), ("interface", (0, 0, 1), 0.05)])
def test_every_boundary_has_its_area_and_its_outward_normal(slab, boundary, normal, area):
    """The section's edges extruded: each boundary's area and its normal, outward (the
    interface's from the subcortex into the cortex)."""
    n = ngs.specialcf.normal(3)
    region = slab.Boundaries(boundary)
    assert ngs.Integrate(1.0, slab, ngs.BND, definedon=region) == pytest.approx(area, rel=1e-12)
    flux = [ngs.Integrate(n[i], slab, ngs.BND, definedon=region) for i in range(3)]
    np.testing.assert_allclose(flux, np.multiply(normal, area), atol=1e-14)


def test_the_two_faces_are_the_sides_with_outward_normals(slab):
    n = ngs.specialcf.normal(3)
    sides = slab.Boundaries("sides")
    for below, sign in ((1, -1), (-1, 1)):      # the face Y = 0 faces -e2, Y = depth +e2
        flux = ngs.Integrate(ngs.IfPos(below * (0.025 - ngs.y), n[1], 0.0), slab, ngs.BND,
                             definedon=sides)
        assert flux == pytest.approx(sign * 0.5, rel=1e-12)


def grown(mesh, slab):
    """The bilayer's cortex grown by 10 % along e1, its left end on rollers, in plane strain
    (the rest of the rigid motions pinned): it bends as a bimetal. The displacement and the
    number of unknowns."""
    material = Regional(mesh, {"cortex": NeoHookean(3.0, 300.0),
                               "subcortex": NeoHookean(1.0, 100.0)})
    f0 = fields.by_region(mesh, {"cortex": fields.constant("e1"),
                                 "subcortex": fields.constant("e3")}, "f0")
    law = RegionalLaw(mesh, {"cortex": ConstantRateLaw(0.1), "subcortex": ConstantRateLaw(0)})
    growth = GrowthEnergy("fiber", f0, law, material)
    problem = CoupledProblem(mesh, [growth, RigidPins()], order=2, slab=slab,
                             symmetry={"left": "x", "sides": "y"})
    assert solve_coupled(problem, t_end=1.0, dt=0.5,
                         options=NewtonOptions(rtol=1e-10, line_search=False)).converged
    return problem.u, int(sum(problem.freedofs))


def test_the_linear_space_gives_the_full_spaces_plane_strain_solution(slab):
    """The growth bends the slab (u1 and u3 vary over the section), u2 = 0 on both faces:
    the same displacement to round-off from 0.57 of the unknowns (11 against 19 per
    section node at order 2)."""
    full, n_full = grown(slab, slab=False)
    linear, n_linear = grown(slab, slab=True)
    points = element_points(slab, 3)
    a, b = (np.asarray(u(points)) for u in (full, linear))
    assert np.abs(a[:, 2]).max() > 1e-3                   # it bends
    assert np.abs(a - b).max() < 1e-9 * np.abs(a).max()
    assert np.abs(a[:, 1]).max() < 1e-12                 # plane strain
    assert n_linear < 0.6 * n_full


def test_a_mesh_that_is_not_a_slab_of_prisms_is_refused():
    with pytest.raises(ParameterError, match="slab"):
        displacement_space(cube(maxh=0.5, elements="tet"), 2, slab=True)
