"""Self-contact (:mod:`ngincompat.fem.self_contact`) against the closed form of two blocks of one
body pressed into each other (and of one block pressed into its mirror image), and its energy,
residual and tangent by finite differences."""

import math

import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import (
    Box,
    Compound,
    IdentificationType,
    OCCGeometry,
    Pnt,
    Vec,
    WorkPlane,
    X,
    Y,
    Z,
    gp_Trsf,
)
from scipy.optimize import brentq

from ngincompat.errors import ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.self_contact import SelfContact
from ngincompat.fem.solver import NewtonOptions, NewtonSolver, StepRecord
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import ConstantRateLaw
from ngincompat.mechanics.materials import NeoHookean

#: Two unit blocks, one above the other with a gap G0 between them: one body (one material)
#: whose boundary "gap" is both facing faces; pushed together by D at the top. The facing
#: faces are meshed alike (identified, or the same edge of two equal squares): on unlike
#: meshes the pairs' integration across the other face's element edges is inexact and the
#: uniform state is not reproduced exactly (rms deviation of the strain 0.8 % at maxh 0.5,
#: penalty 100).
H, G0, D = 1.0, 0.05, 0.15
MU, LAM = 1.0, 10.0


@pytest.fixture(scope="module", params=["tetrahedra", "section"])
def blocks(request):
    """The two blocks meshed with tetrahedra, or in plane strain as their section, two
    squares (a two-dimensional mesh: the facing faces are segments, as the folding bilayer's
    top)."""
    if request.param == "section":
        lower = WorkPlane().Rectangle(1, H).Face()
        upper = WorkPlane().MoveTo(0, H + G0).Rectangle(1, H).Face()
        for block in (lower, upper):
            block.edges.Min(X).name = block.edges.Max(X).name = "xs"
            block.name = "body"
        lower.edges.Min(Y).name, lower.edges.Max(Y).name = "bottom", "gap"
        upper.edges.Min(Y).name, upper.edges.Max(Y).name = "gap", "top"
        return ngs.Mesh(OCCGeometry(Compound([lower, upper]), dim=2).GenerateMesh(maxh=0.5))
    lower = Box(Pnt(0, 0, 0), Pnt(1, 1, H))
    upper = Box(Pnt(0, 0, H + G0), Pnt(1, 1, 2 * H + G0))
    for block in (lower, upper):
        block.faces.Min(X).name = block.faces.Max(X).name = "xs"
        block.faces.Min(Y).name = block.faces.Max(Y).name = "ys"
        block.mat("body")
    lower.faces.Min(Z).name, lower.faces.Max(Z).name = "bottom", "gap"
    upper.faces.Min(Z).name, upper.faces.Max(Z).name = "gap", "top"
    lower.faces.Max(Z).Identify(upper.faces.Min(Z), "across", IdentificationType.PERIODIC,
                                gp_Trsf.Translation(Vec(0, 0, G0)))
    return ngs.Mesh(OCCGeometry(Compound([lower, upper])).GenerateMesh(maxh=0.5))


def height(mesh):
    """The vertical coordinate: X3 of a body, X2 of a section (plane strain)."""
    return (ngs.x, ngs.y, ngs.z)[mesh.dim - 1]


def vertical(mesh, value):
    """The vector field ``value`` times the vertical unit vector (of the mesh's dimension)."""
    return ngs.CF((0,) * (mesh.dim - 1) + (value,))


def rollers(mesh, *names):
    """Symmetry planes: the side faces on rollers, and ``names`` held vertically."""
    axes = ("x", "y", "z")[:mesh.dim]
    planes = {"xs": "x", "ys": "y"} if mesh.dim == 3 else {"xs": "x"}
    return {**planes, **{name: axes[-1] for name in names}}


def mirror(mesh, level):
    """The horizontal plane at ``level``, its normal upward, as a mirror of
    :class:`SelfContact` (a point and a unit normal of three components)."""
    return ((0, 0, level), (0, 0, 1)) if mesh.dim == 3 else ((0, level, 0), (0, 1, 0))


def pressed(mesh, penalty, width=0.0):
    """The blocks on rollers (sides, bottom, top), the top moved down by D: a uniaxial strain
    once the gap has closed. Solved by Newton at fixed pairs, the pairs updated after each
    solve until the residual with the new pairs is 1e-10 of the first."""
    contact = SelfContact("gap", penalty, width, reach=0.3)
    growth = GrowthEnergy("fiber", fields.constant("e1"), ConstantRateLaw(0.0),
                          NeoHookean(MU, LAM))
    problem = CoupledProblem(mesh, [growth, contact], order=2,
                             symmetry=rollers(mesh, "bottom", "top"))
    problem.u.Set(vertical(mesh, -D * ngs.IfPos(height(mesh) - H - G0 / 2, 1, 0)))
    contact.update()
    first = None
    for _ in range(30):
        record = StepRecord(0.0, 0.0, False)
        solver = NewtonSolver(problem, NewtonOptions(max_iter=30, line_search=False,
                                                     linear_solver="direct", rtol=1e-10,
                                                     atol=1e-12))
        assert solver.minimise(record), record.reason
        problem.accept_step()
        first = first or record.residuals[0]
        if record.residuals[0] <= 1e-10 * first:
            return problem, contact
    raise AssertionError("the pairs kept changing")


def closed_form(penalty, width):
    """The uniaxial strain of the closed gap: stretch lam = (2H - D + G0 + delta) / 2H with the
    penetration delta where the penalty's pressure kappa r(delta) balances the compressive
    nominal stress -P33 = -(mu (lam - 1 / lam) + lambda ln(lam) / lam) of the neo-Hookean
    material (eq. 36 with F = diag(1, 1, lam); of a section in plane strain diag(1, lam, 1))."""
    def stretch(delta):
        return (2 * H - D + G0 + delta) / (2 * H)

    def pressure(delta):
        r = delta if width == 0 else (delta**2 / (2 * width) if delta < width
                                      else delta - width / 2)
        return penalty * r

    def nominal(lam):
        return MU * (lam - 1 / lam) + LAM * math.log(lam) / lam

    delta = brentq(lambda d: -nominal(stretch(d)) - pressure(d), 0.0, D)
    return delta, stretch(delta), nominal(stretch(delta))


@pytest.mark.parametrize("penalty", [1e2, 1e3, 1e4])
def test_blocks_pressed_together_are_the_closed_form_uniaxial_strain(blocks, penalty):
    width = 1e-4
    problem, contact = pressed(blocks, penalty, width)
    delta, lam, _ = closed_form(penalty, width)
    strain = ngs.Grad(problem.u)[blocks.dim - 1, blocks.dim - 1]
    volume = ngs.Integrate(1.0, blocks)
    # the stretch is uniform and the closed form's, in both blocks
    assert ngs.Integrate(strain, blocks) / volume == pytest.approx(lam - 1, rel=1e-6)
    assert math.sqrt(ngs.Integrate((1 + strain - lam) ** 2, blocks) / volume) < 1e-8
    measured = contact.measures()
    assert measured["self_contact_penetration_max"] == pytest.approx(delta, rel=1e-5)
    assert measured["self_contact_area"] == pytest.approx(2.0, rel=1e-9)   # both faces


def test_penetration_falls_as_the_penalty_grows(blocks):
    penetration = [pressed(blocks, penalty)[1].measures()["self_contact_penetration_max"]
                   for penalty in (1e2, 1e3, 1e4)]
    assert penetration[0] > 8 * penetration[1] > 64 * penetration[2] > 0
    delta = [closed_form(penalty, 0.0)[0] for penalty in (1e2, 1e3, 1e4)]
    np.testing.assert_allclose(penetration, delta, rtol=1e-5)


@pytest.fixture(scope="module")
def upper_block():
    """The upper block alone, its face "gap" G0 / 2 above the plane Z = H + G0 / 2, whose
    mirror image of the block is the lower block of :func:`blocks`."""
    block = Box(Pnt(0, 0, H + G0), Pnt(1, 1, 2 * H + G0))
    block.faces.Min(X).name = block.faces.Max(X).name = "xs"
    block.faces.Min(Y).name = block.faces.Max(Y).name = "ys"
    block.faces.Min(Z).name, block.faces.Max(Z).name = "gap", "top"
    block.mat("body")
    return ngs.Mesh(OCCGeometry(block).GenerateMesh(maxh=0.5))


@pytest.mark.parametrize("penalty", [1e2, 1e4])
def test_a_block_pressed_into_its_mirror_image_is_the_two_blocks_pressed_together(
        upper_block, penalty):
    """Rollers on the sides and the top, the top moved down by D / 2, the face "gap" against
    its image in the plane midway between the blocks: the image moves up by D / 2, so the
    pair is the two blocks pushed together by D, with the same penetration and stretch."""
    width = 1e-4
    plane = ((0, 0, H + G0 / 2), (0, 0, 1))
    contact = SelfContact("gap", penalty, width, reach=0.3, mirrors=[plane])
    growth = GrowthEnergy("fiber", fields.constant("e1"), ConstantRateLaw(0.0),
                          NeoHookean(MU, LAM))
    problem = CoupledProblem(upper_block, [growth, contact], order=2,
                             symmetry={"xs": "x", "ys": "y", "top": "z"})
    problem.u.Set(ngs.CF((0, 0, -D / 2 * (ngs.z - H - G0) / H)))
    contact.update()
    record = StepRecord(0.0, 0.0, False)
    solver = NewtonSolver(problem, NewtonOptions(max_iter=30, line_search=False,
                                                 linear_solver="direct", rtol=1e-10,
                                                 atol=1e-12))
    assert solver.minimise(record), record.reason
    delta, lam, _ = closed_form(penalty, width)
    strain = ngs.Grad(problem.u)[2, 2]
    assert ngs.Integrate(strain, upper_block) == pytest.approx(lam - 1, rel=1e-6)
    assert math.sqrt(ngs.Integrate((1 + strain - lam) ** 2, upper_block)) < 1e-8
    measured = contact.measures()
    assert measured["self_contact_penetration_max"] == pytest.approx(delta, rel=1e-5)
    assert measured["self_contact_area"] == pytest.approx(1.0, rel=1e-9)


def test_a_mirror_far_away_carries_nothing(upper_block):
    contact = SelfContact("gap", 1e3, 0.0, reach=0.3, mirrors=[((0, 0, 0), (0, 0, 1))])
    problem = CoupledProblem(upper_block, [contact], order=2, symmetry={"top": "z"})
    contact.update()
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    assert residual.Norm() == 0.0 and contact.energy() == 0.0


def test_removed_mirrors_carry_nothing(upper_block):
    """The block sunk into its image in the plane below it is pushed back; with the mirror
    removed (its symmetry plane gone, :meth:`SelfContact.remove_mirrors`) the same state has
    no contact: residual, energy and measures zero."""
    contact = SelfContact("gap", 1e3, 0.0, reach=0.3, mirrors=[((0, 0, H + G0 / 2), (0, 0, 1))])
    problem = CoupledProblem(upper_block, [contact], order=2, symmetry={"top": "z"})
    problem.u.Set(ngs.CF((0, 0, -G0)))
    contact.update()
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    assert residual.Norm() > 0 and contact.energy() > 0
    assert contact.measures()["self_contact_penetration_max"] == pytest.approx(G0, rel=1e-9)
    contact.remove_mirrors()
    problem.form.Apply(problem.state.vec, residual)
    assert residual.Norm() == 0.0 and contact.energy() == 0.0
    assert contact.measures() == {"self_contact_area": 0.0,
                                  "self_contact_penetration_max": 0.0}


def test_open_gap_carries_nothing(blocks):
    """Pushed by less than the gap, the blocks do not touch: no contact, no stress."""
    contact = SelfContact("gap", 1e3, 0.0, reach=0.3)
    problem = CoupledProblem(blocks, [contact], order=2, symmetry=rollers(blocks, "bottom"))
    problem.u.Set(vertical(blocks, -0.5 * G0 * ngs.IfPos(height(blocks) - H - G0 / 2, 1, 0)))
    contact.update()
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    assert residual.Norm() == 0.0 and contact.energy() == 0.0
    assert contact.measures() == {"self_contact_area": 0.0,
                                  "self_contact_penetration_max": 0.0}


def test_a_bent_wall_is_not_in_contact_with_itself():
    """A slab's top bent into crowns and troughs (curvature up to 3.2 / cm), pairs sought
    within 0.3: neither the energy's pairs nor the measures' find contact (the neighbours of
    a point on one smooth wall are not its pairs)."""
    slab = Box(Pnt(0, 0, 0), Pnt(1, 1, 0.2))
    slab.faces.name = "sides"
    slab.faces.Max(Z).name = "wall"
    mesh = ngs.Mesh(OCCGeometry(slab).GenerateMesh(maxh=0.1))
    contact = SelfContact("wall", 1e3, 0.0, reach=0.3)
    problem = CoupledProblem(mesh, [contact], order=2)
    problem.u.Set(ngs.CF((0, 0, 0.02 * ngs.cos(2 * math.pi * ngs.x / 0.5) * ngs.z / 0.2)))
    contact.update()
    assert contact.energy() == 0.0
    assert contact.measures() == {"self_contact_area": 0.0,
                                  "self_contact_penetration_max": 0.0}


@pytest.mark.parametrize("width", [0.0, 0.01])
@pytest.mark.parametrize("mirrored", [False, True])
def test_energy_residual_and_tangent_agree_by_finite_differences(blocks, width, mirrored):
    """At a state with the upper block sunk into the lower one (and into its image in the
    plane between them) and sheared, the residual is the derivative of the term's energy and
    the tangent the residual's."""
    mirrors = [mirror(blocks, H + G0 / 2)] if mirrored else []
    contact = SelfContact("gap", 1e3, width, reach=0.3, mirrors=mirrors)
    problem = CoupledProblem(blocks, [contact], order=2, condense=False)
    z = height(blocks)
    sunk = -(G0 + 0.03 + 0.01 * ngs.x) * ngs.IfPos(z - H - G0 / 2, 1, 0)
    problem.u.Set(ngs.CF((0.02 * z, 0.01 * ngs.x * z, sunk) if blocks.dim == 3 else
                         (0.02 * z, sunk)))
    contact.update()
    state = problem.state.vec
    start = state.CreateVector()
    start.data = state
    direction = state.CreateVector()
    direction.FV().NumPy()[:] = np.random.default_rng(3).standard_normal(len(direction))
    r0, rp, rm = (state.CreateVector() for _ in range(3))
    problem.form.Apply(state, r0)
    h = 1e-6
    energies = []
    for sign, r in ((1, rp), (-1, rm)):
        state.data = start + sign * h * direction
        energies.append(contact.energy())
        problem.form.Apply(state, r)
    state.data = start
    assert contact.energy() > 0
    slope = ngs.InnerProduct(r0, direction)
    assert (energies[0] - energies[1]) / (2 * h) == pytest.approx(slope, rel=1e-6)
    problem.form.AssembleLinearization(state)
    Kw, fd = state.CreateVector(), state.CreateVector()
    Kw.data = problem.form.mat * direction
    fd.data = (0.5 / h) * (rp - rm)
    diff = fd.CreateVector()
    diff.data = fd - Kw
    assert diff.Norm() < 1e-6 * Kw.Norm()


def test_bad_penalty_is_refused():
    with pytest.raises(ParameterError, match="contact_penalty"):
        SelfContact("top", 0.0, 0.0, 1.0)
    with pytest.raises(ParameterError, match="contact_reach"):
        SelfContact("top", 1.0, 0.0, -1.0)
    with pytest.raises(ParameterError, match="mirror normal"):
        SelfContact("top", 1.0, 0.0, 1.0, mirrors=[((0, 0, 0), (0, 0, 2))])
