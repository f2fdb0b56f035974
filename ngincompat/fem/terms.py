"""The energy terms a :class:`~ngincompat.fem.coupled.CoupledProblem` is the sum of.

A coupled step's residual is the derivative of

    Phi(u, ...) = sum over the terms of their energies,

each term adding its integrals to the residual (the tangent is their linearisation), its
unknowns to the problem's state, and what it measures of the state. The growth law is the one
part that is not a derivative: its implicit Euler residual (eq. 48) is the growth term's second
row, so only at frozen growth (dt = 0 or ``growing`` = 0) is the residual the derivative of
Phi in u.

==============================  =============================================================
:class:`GrowthEnergy`           int Jg Psi(F Fg(theta)^-1) dV, theta by a growth law (eq. 48)
:class:`ViscousRegularisation`  eta / (2 dt) int |u - u_n|^2 dV
:class:`DeadTraction`           -s int t . u dA on some boundaries
:class:`VolumeConstraint`       p (V(u) - V*): the volume under a boundary held by a pressure
==============================  =============================================================

and :class:`~ngincompat.fem.contact.ExpanderContact`, the penalty contact with an expander
(like :class:`VolumeConstraint` a :class:`VolumeHolder`, whose target stages drive), and
:class:`~ngincompat.fem.self_contact.SelfContact`, the penalty self-contact of a boundary. A term
is one class with the methods of :class:`Term`; nothing else needs to know it.
"""

import abc
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import NotImplementedType
from typing import TYPE_CHECKING, Any

import ngsolve as ngs
import numpy as np

from ngincompat.fem.compiler import compiled
from ngincompat.mechanics import kinematics
from ngincompat.mechanics.fields import DirectionField
from ngincompat.mechanics.growth import GrowthKind, growth_kind
from ngincompat.mechanics.laws import GrowthLaw, euler_residual
from ngincompat.mechanics.materials import Material, grown_energy_density


@dataclass(frozen=True)
class Unknown:
    """One field of a coupled problem: its trial and test functions in the problem's
    compound space and its values, a component of the problem's state."""

    trial: ngs.comp.ProxyFunction
    test: ngs.comp.ProxyFunction
    field: ngs.GridFunction


class Term(abc.ABC):
    """What a term of a :class:`~ngincompat.fem.coupled.CoupledProblem` provides.

    The problem calls :meth:`spaces` of every term, builds its state on the displacement
    space followed by those spaces, then :meth:`attach` of every term in the order given
    (the order in which their integrals enter the residual). A term is bound to the one
    problem it is attached to. A term implements :meth:`attach` and :meth:`energy` (a
    class that forgets one cannot be instantiated); the other methods' defaults are those
    of a term without unknowns, measures, history or checkpointed data.
    """

    def spaces(self, problem: Any) -> Sequence[ngs.FESpace]:
        """The spaces of the unknowns the term adds (the problem's ``mesh``, ``order`` and
        displacement ``space`` are set when this is called)."""
        return ()

    @abc.abstractmethod
    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals | None:
        """Bind the term to ``problem`` (its displacement is ``problem.displacement``),
        ``unknowns`` those of :meth:`spaces`; returns the term's residual, integrals linear
        in the test functions (e.g. ``r * ngs.dx``), or None."""

    @abc.abstractmethod
    def energy(self) -> float:
        """The term's energy at the problem's current state and step."""

    def held_energy(self,
                    u: ngs.CoefficientFunction) -> ngs.comp.SumOfIntegrals | NotImplementedType:
        """The term's energy as integrals in the displacement alone, ``u`` a trial function
        of the problem's displacement space, with everything else it depends on held at its
        current value (theta at frozen growth), each by the rule of the term's residual (the
        same equilibria): the energy of
        :class:`~ngincompat.fem.coupled.FrozenGrowth`. NotImplemented (the default) for a
        term that does not provide it (one whose energy needs unknowns of its own, as a
        multiplier, cannot): a problem with such a term has no FrozenGrowth."""
        return NotImplemented

    def measures(self) -> dict[str, float]:
        """What the term reports of the current state, by name."""
        return {}

    def accept_step(self) -> None:  # noqa: B027 - a hook: nothing for a term without history
        """The converged state becomes the start of the next step."""

    def saved(self) -> dict:
        """What a checkpoint keeps of the term besides the state (name -> array or float)."""
        return {}

    def restore(self, data: Mapping[str, Any]) -> None:  # noqa: B027 - a hook: nothing for a term saving none
        """Take back what :meth:`saved` kept, from a checkpoint's ``data`` (a mapping that
        may lack the keys of older checkpoints)."""


class GrowthEnergy(Term):
    """The strain energy of a growing body with its growth law: int Jg Psi(Fe) dV,
    Fe = F Fg(theta)^-1 (eq. 30 without body force), and the implicit Euler update of the
    growth theta (eq. 48).

    Unknown: theta in L2 of ``growth_order`` (default: the displacement's order - 1), whose
    dofs are element-local, so that static condensation removes them from the global system.
    The residual is

        int P : Grad v dV + int R^g eta dV,      P = dW/dF, W = Jg Psi(F Fg(theta)^-1),

    R^g the growth residual of eq. (48) with the step ``growing`` dt (the problem's
    Parameters); its linearisation, assembled symbolically, is the consistent tangent with
    c^g (eq. 49), so Newton converges quadratically.

    Parameters
    ----------
    kind : str or GrowthKind subclass
        Growth kind, a registered name (:data:`ngincompat.mechanics.growth.KINDS`:
        "isotropic", "area", "fiber", ...) or the class itself; theta drives it through
        ``from_theta`` and growth laws through its ``stretch(F)``.
    direction : DirectionField or None
        N0 (area) or f0 (fiber growth); None for a kind without a direction.
    law : GrowthLaw
        See :mod:`ngincompat.mechanics.laws`.
    material : Material
        See :mod:`ngincompat.mechanics.materials`.
    fibers : sequence of DirectionField
        Reference fiber directions a0 for anisotropic materials.
    growth_order : int, optional
        Order of theta.
    """

    def __init__(self, kind: str | type[GrowthKind], direction: DirectionField | None,
                 law: GrowthLaw, material: Material, fibers: Sequence[DirectionField] = (),
                 growth_order: int | None = None) -> None:
        self.growth_class = kind if isinstance(kind, type) else growth_kind(kind)
        self.kind = self.growth_class.kind
        self.direction, self.law, self.material = direction, law, material
        self.fibers = tuple(fibers)
        self.growth_order = growth_order

    def spaces(self, problem: Any) -> tuple[ngs.FESpace, ...]:
        order = max(problem.order - 1, 0) if self.growth_order is None else self.growth_order
        return (ngs.L2(problem.mesh, order=order),)

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals:
        (growth,) = unknowns
        self.mesh, self.u = problem.mesh, problem.u
        self.theta = growth.field
        self.theta.Set(1.0)
        self.theta_old = ngs.GridFunction(growth.field.space)
        self.theta_old.Set(1.0)
        u, v = problem.displacement.trial, problem.displacement.test
        th, eta = growth.trial, growth.test
        F = kinematics.deformation_gradient(u)
        W = self.energy_density(F, th)
        stretch = self.model(th).stretch(F)
        rate = euler_residual(self.law, th, self.theta_old, problem.growing * problem.dt,
                              stretch)
        # dW/du . v as P : Grad v with P = dW/dF: the same residual and tangent, the tangent's
        # element matrices in about 0.4 of the time of the symbolic Diff of W by u
        # (docs/measurements/solver-costs.md, "The coupled residual")
        stress = W.Diff(F)
        self.realcompile = problem.realcompile
        # the energy of the state, evaluated after every step of a line search on energy:
        # compiled once into NGSolve's step list, several times faster than the tree
        self._energy = self.energy_density(kinematics.deformation_gradient(self.u)).Compile()
        return compiled(ngs.InnerProduct(stress, kinematics.displacement_gradient(v)) + rate * eta,
                        problem.realcompile) * ngs.dx

    def model(self, theta: ngs.CoefficientFunction) -> GrowthKind:
        """The growth model of the term's kind and direction for the growth theta."""
        return self.growth_class.from_theta(theta, self.direction)

    def energy_density(self, F: ngs.CoefficientFunction,
                       theta: ngs.CoefficientFunction | None = None) -> ngs.CoefficientFunction:
        """Strain energy per reference volume, Jg Psi(F Fg^-1), at the growth ``theta``
        (default: the current one), the fibers pushed to the intermediate configuration,
        Fg a0 / |Fg a0| (eq. 39)."""
        growth = self.model(self.theta if theta is None else theta)
        return grown_energy_density(F, growth, self.material, self.fibers)

    def energy(self) -> float:
        """The strain energy int Jg Psi dV of the current state."""
        return ngs.Integrate(self._energy, self.mesh)

    def held_energy(self, u: ngs.CoefficientFunction) -> ngs.comp.SumOfIntegrals:
        """int Jg Psi(F(u) Fg(theta)^-1) dV at the current theta, by the rule of the residual:
        NGSolve's default rule has degree 2 p - 2 for an energy in the gradient of u of
        order p, and 2 max(p, q) for the residual on the compound space of u and theta (of
        order q), so the energy's rule is raised by the difference: a coarser rule (3
        points a triangle for quadratic u and linear theta, where the residual takes 6) is
        another discrete problem, 6e-5 apart in the residual on the folding bilayer."""
        p, q = self.u.space.globalorder, self.theta.space.globalorder
        bonus = 2 * max(p, q) - (2 * p - 2)
        density = self.energy_density(kinematics.deformation_gradient(u))
        return compiled(density, self.realcompile, maxderiv=2) * ngs.dx(bonus_intorder=bonus)

    def accept_step(self) -> None:
        """theta_n <- theta_n+1."""
        self.theta_old.vec.data = self.theta.vec

    def saved(self) -> dict:
        return {"theta_old": self.theta_old.vec.FV().NumPy()}

    def restore(self, data: Mapping[str, Any]) -> None:
        self.theta_old.vec.FV().NumPy()[:] = data["theta_old"]


class ViscousRegularisation(Term):
    """eta / (2 dt) int |u - u_n|^2 dV: the residual eta / dt int (u - u_n) . v dV, with u_n
    the last converged displacement and eta the Parameter ``viscosity`` (stress x time /
    length^2; 0 switches it off, as does a frozen step, dt = 0).

    It adds eta / dt M to the tangent, which keeps Newton's system positive definite past a
    buckling point (smallest eigenvalue of K w = omega M w above -eta / dt) and lets an
    unstable mode grow at the finite rate -omega / eta instead of jumping. With the problem's
    ``growing`` = 0 a step dt > 0 holds the growth and keeps this term: the pseudo-time step
    of a relaxation at frozen growth (:class:`~ngincompat.fem.relaxation.RelaxationStage`).
    """

    def __init__(self) -> None:
        self.viscosity = ngs.Parameter(0.0)

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals:
        self.problem, self.u = problem, problem.u
        self.u_old = ngs.GridFunction(problem.space)
        dt = problem.dt
        rate = self.viscosity / ngs.IfPos(dt, dt, 1.0) * ngs.IfPos(dt, 1, 0)
        return rate * ngs.InnerProduct(problem.displacement.trial - self.u_old,
                                       problem.displacement.test) * ngs.dx

    def restart(self, viscosity: float) -> None:
        """Set eta and measure u - u_n from the current displacement."""
        self.viscosity.Set(viscosity)
        self.u_old.vec.data = self.u.vec

    def energy(self) -> float:
        dt = self.problem.dt.Get()
        if dt <= 0:
            return 0.0
        change = self.u - self.u_old
        return self.viscosity.Get() / (2 * dt) * ngs.Integrate(ngs.InnerProduct(change, change),
                                                               self.problem.mesh)

    def accept_step(self) -> None:
        """u_n <- u_n+1."""
        self.u_old.vec.data = self.u.vec


class DeadTraction(Term):
    """A dead traction s t on the ``boundaries`` (a region expression such as "left|right"):
    the energy -s int t . u dA, the residual -s int t . v dA, with t the GridFunction
    ``field`` and s the Parameter ``scale`` (0 at first). :meth:`hold` sets t to the forces
    that supports exerted there, e.g. to remove them gradually once they are gone
    (:meth:`~ngincompat.fem.coupled.CoupledProblem.support`)."""

    def __init__(self, boundaries: str) -> None:
        self.boundaries = boundaries
        self.scale = ngs.Parameter(0.0)

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals:
        self.problem = problem
        self.field = ngs.GridFunction(problem.space, name="traction")
        return self._work(problem.displacement.test)

    def _work(self, w: ngs.CoefficientFunction) -> ngs.comp.SumOfIntegrals:
        """-s int t . w dA: the energy at w = u, the residual at the test function (the
        energy is linear in u)."""
        return -self.scale * ngs.InnerProduct(self.field, w) * ngs.ds(self.boundaries)

    def held_energy(self, u: ngs.CoefficientFunction) -> ngs.comp.SumOfIntegrals:
        return self._work(u)

    def energy(self) -> float:
        return ngs.Integrate(self._work(self.problem.u), self.problem.mesh)

    def hold(self) -> float:
        """Hold the current state in equilibrium by this traction: t with
        int t . v dA = R(u) . v on the boundaries, R the problem's residual without it (the
        reactions there of supports just removed; elsewhere R is
        its residual, about 0), i.e. t = M_b^-1 R with M_b the boundary mass matrix on the
        free dofs of the boundaries, and ``scale`` = 1. Returns the norm of R there."""
        problem = self.problem
        V = problem.space
        on = V.GetDofs(problem.mesh.Boundaries(self.boundaries)) & V.FreeDofs()
        for dof in problem.pinned:
            on.Clear(dof)
        self.scale.Set(0.0)
        residual = problem.state.vec.CreateVector()
        problem.form.Apply(problem.state.vec, residual)
        reactions = problem.u.vec.CreateVector()
        reactions.FV().NumPy()[:] = residual.FV().NumPy()[:V.ndof]
        u, v = V.TnT()
        mass = ngs.BilinearForm(V)
        mass += ngs.InnerProduct(u, v) * ngs.ds(self.boundaries)
        mass.Assemble()
        self.field.vec.data = mass.mat.Inverse(on, inverse="sparsecholesky") * reactions
        self.scale.Set(1.0)
        return float(np.linalg.norm(reactions.FV().NumPy()[np.array(on, dtype=bool)]))


def enclosed_volume_density(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """x3 det(dx_a / dX_b) (a, b = 1, 2), x = X + u: per reference area of a boundary
    initially in the plane X3 = 0, whose integral is the volume V enclosed under the
    boundary's current place (the boundary's edge held in that plane)."""
    Fs = ngs.Id(3) + ngs.Grad(u).Trace()
    x3 = ngs.z + u[2]
    return x3 * (Fs[0, 0] * Fs[1, 1] - Fs[0, 1] * Fs[1, 0])


def enclosed_volume_variation(u: ngs.CoefficientFunction,
                              v: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """d/du of :func:`enclosed_volume_density` along v, written out:
    v3 det(Fs) + x3 (dFs_11 Fs_22 + Fs_11 dFs_22 - dFs_12 Fs_21 - Fs_12 dFs_21) with
    Fs = I + Grad(u) and dFs = Grad(v) on the boundary (their tangential parts)."""
    Fs = ngs.Id(3) + ngs.Grad(u).Trace()
    dFs = ngs.Grad(v).Trace()
    x3 = ngs.z + u[2]
    det = Fs[0, 0] * Fs[1, 1] - Fs[0, 1] * Fs[1, 0]
    ddet = (dFs[0, 0] * Fs[1, 1] + Fs[0, 0] * dFs[1, 1]
            - dFs[0, 1] * Fs[1, 0] - Fs[0, 1] * dFs[1, 0])
    return v[2] * det + x3 * ddet


class VolumeHolder(Term):
    """What the terms that hold the volume under a ``boundary`` (initially in the plane
    X3 = 0) share: the Parameter ``target`` that stages drive (``set_target``), the volume
    they measure and the target a checkpoint keeps. A subclass sets ``mesh`` and ``u`` as
    it is attached."""

    if TYPE_CHECKING:   # set by the subclass as it is attached
        mesh: ngs.Mesh
        u: ngs.GridFunction

    def __init__(self, boundary: str) -> None:
        self.boundary = boundary
        self.target = ngs.Parameter(0.0)

    def volume(self) -> float:
        """The volume enclosed under the boundary in the current state."""
        return ngs.Integrate(enclosed_volume_density(self.u), self.mesh, ngs.BND,
                             definedon=self.mesh.Boundaries(self.boundary))

    @abc.abstractmethod
    def set_target(self, volume: float, lift: bool = False) -> None:
        """Hold the volume ``volume`` from now on (``lift``: move the state with the holder
        where it has a shape that moves)."""

    def saved(self) -> dict:
        return {"volume_target": self.target.Get()}

    def restore(self, data: Mapping[str, Any]) -> None:
        if "volume_target" in data:             # older checkpoints: the hold sets it
            self.target.Set(float(data["volume_target"]))


class VolumeConstraint(VolumeHolder):
    """The volume V under the ``boundary`` (initially in the plane X3 = 0, e.g. an
    expander's footprint; :func:`enclosed_volume_density`) held at the Parameter ``target``
    V* by a pressure p, one more unknown: the energy p (V(u) - V*), a saddle point in (u, p),
    whose residual is

        int p dV/du . v dA + (V(u) - V*) q,

    with dV/du . v written out (:func:`enclosed_volume_variation`): NGSolve's ``Diff(u, v)``
    does not differentiate through the surface gradient ``Grad(u).Trace()`` (6.2.2608), and
    would leave out the in-plane part x3 d(det)/du . v."""

    def spaces(self, problem: Any) -> tuple[ngs.FESpace, ...]:
        return (ngs.NumberSpace(problem.mesh),)

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals:
        (multiplier,) = unknowns
        self.mesh, self.u, self.multiplier = problem.mesh, problem.u, multiplier.field
        p, q = multiplier.trial, multiplier.test
        u, v = problem.displacement.trial, problem.displacement.test
        dV = enclosed_volume_density(u)
        area = ngs.Integrate(1, self.mesh, ngs.BND, definedon=self.mesh.Boundaries(self.boundary))
        return (p * enclosed_volume_variation(u, v) * ngs.ds(self.boundary)
                + (dV - self.target / area) * q * ngs.ds(self.boundary))

    def set_target(self, volume: float, lift: bool = False) -> None:
        """Set the volume target (``lift`` as for an expander's, here without effect)."""
        self.target.Set(volume)

    def pressure(self) -> float:
        """The pressure that holds the volume (the multiplier, with the sign of a pressure
        pushing on the boundary)."""
        return -self.multiplier.vec[0]

    def energy(self) -> float:
        return self.multiplier.vec[0] * (self.volume() - self.target.Get())

    def measures(self) -> dict[str, float]:
        return {"pressure": self.pressure()}
