"""Mechanically coupled growth (section 2.6-2.7): one problem, the sum of energy terms.

The unknowns are the displacement u (VectorH1 of ``order``) and those the terms add (the
growth theta of :class:`~ngincompat.fem.terms.GrowthEnergy`, the pressure of a
:class:`~ngincompat.fem.terms.VolumeConstraint`); the residual is the sum of the terms'
residuals, e.g. for the skin held by a pressure

    int P : Grad v dV + int R^g eta dV + int p dV/du . v dA + (V(u) - V*) q,

P = dW/dF with W = Jg Psi(F Fg(theta)^-1) and R^g the implicit Euler growth residual of
eq. (48). Its linearisation, assembled symbolically, is the consistent tangent including c^g
(eq. 49), so the global Newton iteration converges quadratically. A step is ``dt.Set(...)``
(0: growth frozen), ``growing`` (1) the growth's share of it (0 holds theta at theta_n while
the step goes on, a pseudo-time step).

For example, fiber growth by a strain-driven law on a free body with a viscous
regularisation::

    growth = GrowthEnergy("fiber", fields.constant("e1"), law, material)
    viscous = ViscousRegularisation()
    problem = CoupledProblem(mesh, [growth, viscous], order=2)     # pinned: no Dirichlet
    viscous.viscosity.Set(1.0)
    solve_coupled(problem, t_end=1.0, dt=0.25)      # growth.theta: the grown field
"""

from collections.abc import Mapping, Sequence
from typing import Any, Literal

import ngsolve as ngs
import numpy as np

from ngincompat.errors import require
from ngincompat.fem.problem import REALCOMPILE_NDOF, displacement_space, ensure_heap, rigid_pins
from ngincompat.fem.terms import Term, Unknown


class CoupledProblem:
    """Equilibrium and coupled growth of a body, the sum of ``terms``.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    terms : sequence of Term
        The terms (:class:`~ngincompat.fem.terms.Term`), in the order their integrals enter
        the residual; each is attached to this problem and to no other.
    order : int
        Polynomial order of the displacement, >= 1.
    dirichlet, symmetry : as for :class:`~ngincompat.fem.problem.GrowthMechanics`
        Without Dirichlet boundaries the body is pinned against the rigid-body motions its
        supports leave free (:func:`~ngincompat.fem.problem.rigid_pins`), now and after
        every change of the supports, as a
        :class:`~ngincompat.fem.problem.GrowthMechanics` is. The symmetry planes are
        supports that :meth:`support` can change (e.g. remove) later: their dofs are held
        (:attr:`pinned`), not Dirichlet dofs of the space, so the problem's form and its
        compiled residual serve every set of supports.
    condense : bool
        Static condensation of element-interior dofs (theta's among them).
    realcompile : bool or None
        Compile the residual of the growth term to C++
        (:func:`~ngincompat.fem.compiler.compiled`); None: from
        :data:`~ngincompat.fem.problem.REALCOMPILE_NDOF` dofs on.

    Attributes
    ----------
    u : ngsolve.GridFunction
        The displacement, first component of ``state``; ``displacement`` its
        :class:`~ngincompat.fem.terms.Unknown`, ``space`` its space.
    dt : ngsolve.Parameter
        The step (0: growth frozen).
    growing : ngsolve.Parameter
        The growth's share of the step (1).
    symmetry : dict
        The symmetry planes that hold the body now (:meth:`support`).
    pinned : tuple of int
        Dofs held fixed besides the Dirichlet ones: the normal components on the symmetry
        planes, then the rigid pins, if any (no Dirichlet boundaries).
    """

    has_energy = False
    #: Its tangent is not symmetric (the growth rows): SuperLU, several times faster than
    #: UMFPACK on it (:mod:`ngincompat.fem.sparse_lu`).
    inverse = "superlu"

    def __init__(self, mesh: ngs.Mesh, terms: Sequence[Term], order: int = 2,
                 dirichlet: str = "", symmetry: Mapping[str, str] | None = None,
                 condense: bool = True, realcompile: bool | None = None) -> None:
        require(isinstance(order, int) and order >= 1, "order", order, "an integer >= 1")
        ensure_heap(order)
        self.mesh, self.order, self.condense = mesh, order, condense
        self.terms = tuple(terms)
        self.dt = ngs.Parameter(0.0)
        self.growing = ngs.Parameter(1.0)
        self.dirichlet = dirichlet
        self.space = displacement_space(mesh, order, dirichlet)
        added = [tuple(term.spaces(self)) for term in self.terms]
        self.fes = ngs.FESpace([self.space] + [s for spaces in added for s in spaces])
        self.state = ngs.GridFunction(self.fes)
        self.u = self.state.components[0]
        self.symmetry: dict[str, str] = {}
        self.pinned: tuple[int, ...] = ()
        self._rigid = not dirichlet
        self._frozen: FrozenGrowth | Literal[False] | None = None
        self.support(symmetry or {})
        self.realcompile = (self.fes.ndof >= REALCOMPILE_NDOF if realcompile is None
                            else realcompile)
        trials, tests = self.fes.TnT()
        unknowns = [Unknown(*field) for field in zip(trials, tests, self.state.components,
                                                     strict=True)]
        self.displacement = unknowns[0]
        self.form = ngs.BilinearForm(self.fes, condense=condense)
        first = 1
        for term, spaces in zip(self.terms, added, strict=True):
            residual = term.attach(self, unknowns[first:first + len(spaces)])
            first += len(spaces)
            if residual is not None:
                self.form += residual

    @property
    def ndof(self) -> int:
        return self.fes.ndof

    def support(self, symmetry: Mapping[str, str]) -> None:
        """Hold the body by the symmetry planes ``symmetry`` (boundary name -> axis of the
        normal component held at its current value, as for
        :func:`~ngincompat.fem.problem.displacement_space`) instead of those before, and
        re-pin the rigid motions they leave free if the problem pins them
        (without Dirichlet boundaries); ``{}`` removes every support."""
        symmetry = dict(symmetry)
        held = np.array(displacement_space(self.mesh, self.order, self.dirichlet,
                                           symmetry).FreeDofs(), dtype=bool)
        free = np.array(self.space.FreeDofs(), dtype=bool)
        before, self.symmetry = self.pinned, symmetry
        self.pinned = tuple(int(i) for i in np.flatnonzero(free & ~held))
        if self._rigid:
            self.pinned += rigid_pins(self.mesh, self.fes, held=self.pinned)
        # the held dofs are cleared in the spaces' own arrays of free dofs (those held before
        # set again), which NGSolve's BDDC preconditioner and FrozenGrowth read
        for bits in (self.fes.FreeDofs(coupling=self.condense),
                     self.space.FreeDofs(coupling=FrozenGrowth.condense)):
            for dof in before:
                bits.Set(dof)
            for dof in self.pinned:
                bits.Clear(dof)
        self.freedofs = self.fes.FreeDofs(coupling=self.condense)
        self._frozen = None         # made anew with these supports

    def energy(self) -> float:
        """The energy of the current step at the current state, the sum of the terms'
        energies in their order, e.g. with a viscous regularisation and a dead traction

            Phi(u) = int Jg Psi dV + eta / (2 dt) int |u - u_n|^2 dV - s int t . u dA.

        At frozen growth (``growing`` = 0, or dt = 0) the residual is its derivative in u
        (the growth rows hold theta at theta_n)."""
        return sum(term.energy() for term in self.terms)

    def frozen_energy(self) -> float:
        """The energy at frozen growth (a step dt = 0, which switches the viscous term off)
        at the current state: the energy whose derivative the residual of :meth:`frozen_tangent`
        is."""
        dt = self.dt.Get()
        self.dt.Set(0.0)
        try:
            return self.energy()
        finally:
            self.dt.Set(dt)

    def frozen_tangent(self) -> ngs.BaseMatrix:
        """The tangent at frozen growth (a step dt = 0: theta held at theta_n, no viscosity)
        at the current state, assembled into and returned as ``form.mat``. Its growth rows
        are then the identity and do not depend on u, so condensed onto u it is the Hessian
        of the energy int Jg Psi(F Fg^-1) dV by the rule of the residual the problem solves
        (NGSolve integrates the compound form more finely than an energy on u alone)."""
        dt = self.dt.Get()
        self.dt.Set(0.0)
        try:
            self.form.AssembleLinearization(self.state.vec)
        finally:
            self.dt.Set(dt)
        return self.form.mat

    def frozen(self) -> "FrozenGrowth | None":
        """The problem at frozen growth on its displacement alone (:class:`FrozenGrowth`,
        made once), or None if one of its terms cannot be held so (a multiplier)."""
        if self._frozen is None:
            u = self.space.TrialFunction()
            energies = [term.held_energy(u) for term in self.terms]
            self._frozen = (False if any(e is NotImplemented for e in energies)
                            else FrozenGrowth(self, energies))
        return self._frozen or None

    def measures(self) -> dict[str, float]:
        """What the terms report of the current state, merged in their order."""
        measured = {}
        for term in self.terms:
            measured.update(term.measures())
        return measured

    def accept_step(self) -> None:
        """Make the converged state the start of the next step, in every term (theta_n <-
        theta_n+1, u_n <- u_n+1)."""
        for term in self.terms:
            term.accept_step()

    def saved(self) -> dict:
        """What a checkpoint keeps of the terms besides the state."""
        kept = {}
        for term in self.terms:
            kept.update(term.saved())
        return kept

    def restore(self, data: Mapping[str, Any]) -> None:
        """Take back into the terms what :meth:`saved` kept (``data`` from a checkpoint)."""
        for term in self.terms:
            term.restore(data)


class FrozenGrowth:
    """A :class:`CoupledProblem` at frozen growth, solved on its displacement alone.

    At frozen growth (a step dt = 0, or ``growing`` = 0) the growth rows of the coupled
    residual hold theta at theta_n, and its displacement rows are the derivative of

        Pi(u) = sum over the terms of their energies, theta and the loads held

    (:meth:`~ngincompat.fem.terms.Term.held_energy`, each by the rule of the coupled
    residual). This is that energy as a problem of the displacement alone
    (a :class:`~ngincompat.fem.solver.NewtonProblem`): the same equilibria, a symmetric
    tangent (the Hessian of Pi, factorised by sparse Cholesky) assembled without theta's
    dofs: on the skin, where theta's dofs are most of the problem's, a tangent and its
    factorisation cost a fraction of the coupled ones.

    Its state is the coupled problem's displacement (the same memory), its Dirichlet and
    pinned dofs the coupled problem's, its step ``dt`` the coupled problem's Parameter;
    :meth:`accept_step` is the coupled problem's.
    """

    #: The line search tests the residual, as on the coupled problem, not the energy:
    #: accepting steps that lower the energy but not the residual, the skin's inflation took
    #: half as many Newton iterations more.
    has_energy = False
    inverse = "sparsecholesky"
    condense = True

    def __init__(self, problem: CoupledProblem,
                 energies: Sequence[ngs.comp.SumOfIntegrals]) -> None:
        self.coupled, self.fes, self.state, self.dt = problem, problem.space, problem.u, problem.dt
        self.form = ngs.BilinearForm(self.fes, symmetric=True, condense=self.condense)
        for energy in energies:
            self.form += ngs.Variation(energy)
        self.pinned = problem.pinned
        # the space's own array, whose held dofs the problem's support clears
        self.freedofs = self.fes.FreeDofs(coupling=self.condense)

    def accept_step(self) -> None:
        self.coupled.accept_step()
