"""The energy terms of a coupled problem: each term's residual is the derivative of its energy,
the problem's energy is the sum of its terms', and a term defined outside the package is one
class that adds its energy and residual and nothing else."""

import ngsolve as ngs
import numpy as np
import pytest

from geometries import cube, skin_patch
from ngincompat.fem.contact import Expander, ExpanderContact
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.terms import (
    DeadTraction,
    GrowthEnergy,
    Term,
    ViscousRegularisation,
    VolumeConstraint,
)
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean

LAW = StrainDrivenLaw(tau=1.0, theta_max=1.5, gamma=2.0, theta_crit=1.0)


@pytest.mark.parametrize("loaded", [False, True], ids=["frozen", "viscous-traction"])
def test_the_energy_is_the_potential_of_the_frozen_residual(loaded):
    """At frozen growth the coupled residual is the derivative of the step's energy in u:
    the strain energy int Jg Psi dV (dt = 0), and with a viscous pseudo-time step and a dead
    traction Phi = int Jg Psi dV + eta / (2 dt) int |u - u_n|^2 dV - s int t . u dA
    (:meth:`~ngincompat.fem.coupled.CoupledProblem.energy`). Its central difference along a
    displacement w equals R(u) . w. This is what lets the frozen Newton solves of
    :mod:`ngincompat.fem.stages` test their line search on the energy."""
    if loaded:
        growth = GrowthEnergy("fiber", fields.constant("e1"), LAW, NeoHookean.from_nu(1.0, 0.3))
        viscous, traction = ViscousRegularisation(), DeadTraction("right|top")
        problem = CoupledProblem(cube(maxh=0.5), [growth, viscous, traction],
                                 order=2, symmetry={"left": "x"})
        traction.field.Set(ngs.CF((0.3 + ngs.y, 0.2 * ngs.z, -0.1)))
        traction.scale.Set(0.7)
        viscous.u_old.Set(ngs.CF((0.02 * ngs.y, 0.01, -0.03 * ngs.x)))
        viscous.viscosity.Set(5.0)
        problem.growing.Set(0.0)
        problem.dt.Set(0.25)
    else:
        growth = GrowthEnergy("fiber", fields.constant("e1"), LAW, NeoHookean.from_nu(1.0, 0.3))
        problem = CoupledProblem(cube(maxh=0.5), [growth], order=2,
                                 symmetry={"left": "x", "right": "x"})
        problem.dt.Set(0.0)
    growth.theta.Set(1.0 + 0.1 * ngs.x)
    growth.theta_old.vec.data = growth.theta.vec
    problem.u.Set(ngs.CF((0.1 * ngs.x + 0.05 * ngs.y * ngs.z, 0.03 * ngs.x * ngs.y, 0)))
    w = _direction(problem, ngs.CF((ngs.y * ngs.z, 0.5 * ngs.x * ngs.x, ngs.y)))
    slope, difference = _slope_and_difference(problem, w, problem.energy)
    assert abs(slope) > 1e-3
    assert difference == pytest.approx(slope, rel=1e-6)
    if loaded:      # each term counts: without the viscous and the load terms it fails
        _, strain_only = _slope_and_difference(problem, w, growth.energy)
        assert strain_only != pytest.approx(slope, rel=1e-3)


def _direction(problem, displacement=None, rest=None):
    """A direction in the problem's state: ``displacement`` (a CF) in u, ``rest`` (a
    vector) in the other unknowns, zero on the fixed dofs."""
    direction = ngs.GridFunction(problem.fes)
    if displacement is not None:
        direction.components[0].Set(displacement)
    w = problem.state.vec.CreateVector()
    w.data = direction.vec
    if rest is not None:
        w.FV().NumPy()[problem.space.ndof:] = rest
    w.FV().NumPy()[_fixed(problem)] = 0.0
    return w


def _fixed(problem):
    """The dofs that Dirichlet conditions or pins fix (not those static condensation
    removes from the global system)."""
    fixed = ~np.array(problem.fes.FreeDofs(), dtype=bool)
    fixed[list(problem.pinned)] = True
    return fixed


def _slope_and_difference(problem, w, energy, eps=1e-5):
    """R(x) . w, R the problem's residual at its state x, and the central difference of
    ``energy()`` along w; the state is restored."""
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    x = problem.state.vec.CreateVector()
    x.data = problem.state.vec
    problem.state.vec.data = x + eps * w
    plus = energy()
    problem.state.vec.data = x - eps * w
    minus = energy()
    problem.state.vec.data = x
    return ngs.InnerProduct(residual, w), (plus - minus) / (2 * eps)


def _skin_problem(term, order=2):
    """A coarse skin patch, clamped at its periphery, with ``term`` alone."""
    mesh = skin_patch(footprint="circle", maxh=2.5, curve_order=1)
    return CoupledProblem(mesh, [term], order=order, dirichlet="periphery")


def _alone(name):
    """A problem of one term, in a state where each of its parts counts: the term."""
    bend = ngs.CF((0.05 * ngs.y * ngs.z, 0.02 * ngs.x, 0.1 * ngs.x * ngs.y))
    if name == "growth":
        term = GrowthEnergy("fiber", fields.constant("e1"), LAW, NeoHookean.from_nu(1.0, 0.3))
        problem = CoupledProblem(cube(maxh=0.5), [term], order=2,
                                 symmetry={"left": "x"})
        term.theta.Set(1.0 + 0.1 * ngs.x)
        term.theta_old.vec.data = term.theta.vec
    elif name == "viscous":
        term = ViscousRegularisation()
        problem = CoupledProblem(cube(maxh=0.5), [term], order=2, dirichlet="left")
        term.u_old.Set(ngs.CF((0.02 * ngs.y, 0.01, -0.03 * ngs.x)))
        term.viscosity.Set(5.0)
        problem.dt.Set(0.25)
    elif name == "traction":
        term = DeadTraction("right|top")
        problem = CoupledProblem(cube(maxh=0.5), [term], order=2, dirichlet="left")
        term.field.Set(ngs.CF((0.3 + ngs.y, 0.2 * ngs.z, -0.1)))
        term.scale.Set(0.7)
    elif name == "volume":
        term = VolumeConstraint("footprint")
        problem = _skin_problem(term)
        term.target.Set(2.0)
        problem.state.components[1].vec[0] = -0.3
        bend = ngs.CF((0.02 * ngs.y, -0.01 * ngs.x, 0.1 * (25 - ngs.x ** 2 - ngs.y ** 2)))
    else:
        term = ExpanderContact(Expander("circle", 5.0, 100.0, 0.05), "footprint")
        problem = _skin_problem(term)
        term.set_target(5.0)            # the dome rises into the flat skin
        bend = ngs.CF((0.02 * ngs.y, -0.01 * ngs.x, 0.01 * ngs.x))
    problem.u.Set(bend)
    return problem, term


TERMS = ["growth", "viscous", "traction", "volume", "contact"]


@pytest.mark.parametrize("name", TERMS)
def test_each_terms_residual_is_the_derivative_of_its_energy(name):
    """A problem of one term: along a direction in every unknown, its residual is the
    central difference of the term's energy (the growth's at frozen growth, where its
    growth rows do not count against a direction in u alone; the volume constraint's
    p (V - V*), a saddle point, also along the pressure, see also
    :func:`test_the_volume_constraint_is_the_derivative_of_its_energy_in_plane_too`; the
    contact's integrated by the residual's rule, the displacement's order 2 twice plus 2)."""
    problem, term = _alone(name)
    energy = (lambda: term.energy(order=6)) if name == "contact" else term.energy
    if name == "volume":
        w = _direction(problem, ngs.CF((0.1 * ngs.x, 0, 0.2 + ngs.y * ngs.x)), [0.7])
    else:
        w = _direction(problem, ngs.CF((ngs.y * ngs.z, 0.5 * ngs.x * ngs.x, 0.2 + ngs.y)))
    slope, difference = _slope_and_difference(problem, w, energy)
    assert abs(slope) > 1e-4
    assert difference == pytest.approx(slope, rel=1e-6)


@pytest.mark.parametrize("direction", [(ngs.x, 0, 0), (0, ngs.y, 0), (0, 0, ngs.x * ngs.y)],
                         ids=["in-plane x", "in-plane y", "vertical"])
def test_the_volume_constraint_is_the_derivative_of_its_energy_in_plane_too(direction):
    """The pressure model's residual p dV/du . v includes the in-plane part p x3 d(det)/du . v
    (NGSolve's ``Diff`` would leave it out: Grad(u).Trace() gets no derivative in u there):
    along in-plane and vertical directions it is the slope of p (V - V*)."""
    problem, term = _alone("volume")
    slope, difference = _slope_and_difference(problem, _direction(problem, ngs.CF(direction)),
                                              term.energy)
    assert abs(difference) > 1e-3
    assert difference == pytest.approx(slope, rel=1e-6)


def test_the_contact_measures_what_the_expander_presses():
    """The contact term reports the expander's height, where and how hard it presses: a
    dome risen into the flat skin has a contact area, a penetration and a pressure."""
    problem, term = _alone("contact")
    problem.u.Set(ngs.CF((0, 0, 0)))
    measured = problem.measures()
    assert measured["expander_height"] == term.expander_height() > 0
    assert measured["penetration_max"] == pytest.approx(term.expander_height(), rel=1e-3)
    assert measured["contact_area"] > 0 and measured["contact_pressure_max"] > 0


def test_a_term_that_forgets_its_energy_cannot_be_built():
    """With Term a Protocol used as a base, its ``energy`` body ``...`` returned None, and a
    line search compared None."""

    class Forgetful(Term):
        def attach(self, problem, unknowns):
            return None

    with pytest.raises(TypeError, match="energy"):
        Forgetful()


class Foundation(Term):
    """A test's own term: an elastic foundation of stiffness k under the boundary
    ``bottom``, the energy k / 2 int |u|^2 dA."""

    def __init__(self, stiffness):
        self.stiffness = stiffness

    def attach(self, problem, unknowns):
        self.problem = problem
        u, v = problem.displacement.trial, problem.displacement.test
        return self.stiffness * ngs.InnerProduct(u, v) * ngs.ds("bottom")

    def energy(self):
        u, mesh = self.problem.u, self.problem.mesh
        return self.stiffness / 2 * ngs.Integrate(ngs.InnerProduct(u, u), mesh,
                                                  definedon=mesh.Boundaries("bottom"))


def test_a_new_term_adds_its_energy_and_residual_and_nothing_else():
    """A term defined outside the package (one class) changes the problem's energy by its
    integral and its residual by the assembled form of that integral alone; the energy is
    the sum of the terms' energies, in their order."""
    def built(*extra):
        growth = GrowthEnergy("fiber", fields.constant("e1"), LAW,
                              NeoHookean.from_nu(1.0, 0.3))
        viscous = ViscousRegularisation()
        problem = CoupledProblem(cube(maxh=0.5), [growth, viscous, *extra],
                                 order=2, symmetry={"left": "x"})
        viscous.u_old.Set(ngs.CF((0.02 * ngs.y, 0.01, 0)))
        viscous.viscosity.Set(5.0)
        problem.dt.Set(0.25)
        problem.u.Set(ngs.CF((0.1 * ngs.x, 0.03 * ngs.x * ngs.y, 0.02 * ngs.z)))
        return problem

    foundation = Foundation(3.0)
    plain, founded = built(), built(foundation)
    assert founded.fes.ndof == plain.fes.ndof and founded.pinned == plain.pinned
    growth, viscous = founded.terms[:2]
    assert founded.energy() == growth.energy() + viscous.energy() + foundation.energy()
    u = founded.u
    integral = 1.5 * ngs.Integrate(ngs.InnerProduct(u, u), founded.mesh,
                                   definedon=founded.mesh.Boundaries("bottom"))
    assert foundation.energy() == integral > 0
    assert founded.energy() - plain.energy() == pytest.approx(integral, rel=1e-12)
    r_plain, r_founded = (p.state.vec.CreateVector() for p in (plain, founded))
    plain.form.Apply(plain.state.vec, r_plain)
    founded.form.Apply(founded.state.vec, r_founded)
    alone = ngs.LinearForm(founded.space)
    alone += 3.0 * ngs.InnerProduct(u, founded.space.TestFunction()) * ngs.ds("bottom")
    alone.Assemble()
    added = r_founded.FV().NumPy() - r_plain.FV().NumPy()
    n = founded.space.ndof
    assert np.linalg.norm(added[n:]) == 0.0
    np.testing.assert_allclose(added[:n], alone.vec.FV().NumPy(),
                               atol=1e-12 * np.linalg.norm(alone.vec.FV().NumPy()))
    w = _direction(founded, ngs.CF((ngs.y, ngs.x * ngs.z, 1.0)))
    slope, difference = _slope_and_difference(founded, w, founded.energy)
    assert difference == pytest.approx(slope, rel=1e-6)


def test_accepting_a_step_and_a_checkpoint_reach_every_term():
    """``accept_step`` moves theta_n and u_n on; ``saved``/``restore`` carry the growth
    term's theta_n and the volume target through a checkpoint."""
    growth = GrowthEnergy("area", fields.constant("e3"), LAW, NeoHookean.from_nu(0.18, 0.4))
    viscous, volume = ViscousRegularisation(), VolumeConstraint("footprint")
    mesh = skin_patch(footprint="circle", maxh=2.5, curve_order=1)
    problem = CoupledProblem(mesh, [growth, viscous, volume], order=1, dirichlet="periphery")
    growth.theta.Set(1.0 + 0.01 * ngs.x)
    problem.u.Set(ngs.CF((0, 0, 0.1)))
    volume.target.Set(4.0)
    problem.accept_step()
    np.testing.assert_array_equal(growth.theta_old.vec.FV().NumPy(),
                                  growth.theta.vec.FV().NumPy())
    np.testing.assert_array_equal(viscous.u_old.vec.FV().NumPy(), problem.u.vec.FV().NumPy())
    kept = {k: np.copy(v) for k, v in problem.saved().items()}
    assert set(kept) == {"theta_old", "volume_target"} and kept["volume_target"] == 4.0
    growth.theta_old.Set(1.0)
    volume.target.Set(0.0)
    problem.restore(kept)
    np.testing.assert_array_equal(growth.theta_old.vec.FV().NumPy(),
                                  growth.theta.vec.FV().NumPy())
    assert volume.target.Get() == 4.0
