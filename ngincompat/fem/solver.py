"""Robust Newton minimisation for :class:`~ngincompat.fem.problem.GrowthMechanics` and
:class:`~ngincompat.fem.coupled.CoupledProblem` (the load and time steps around it:
:mod:`ngincompat.fem.stepping`).

A full growth step from u = 0 at high order makes plain Newton overshoot into Je <= 0, where
log Je is not defined and the energy is NaN. This solver

* takes Newton directions from the tangent (the linearisation of the residual of the same
  energy, so energy, residual and tangent are consistent by construction),
* backtracks along the direction while the energy is not finite or decreases neither the
  energy (Armijo condition) nor, near convergence where the energy is round-off, the residual;
  so a step "too far" is simply shortened,
* and reports a step it cannot converge as failed (after ``max_iter`` iterations, or once
  its residual stalls), for :mod:`~ngincompat.fem.stepping` to cut.

Every attempted step is recorded (:class:`StepRecord`): time, step size, Newton iterations,
residual norms, line-search lengths and the energy.
"""

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any, Protocol

import ngsolve as ngs
import numpy as np
from ngsolve.krylovspace import CGSolver, GMResSolver

from ngincompat import parallel
from ngincompat.errors import require
from ngincompat.fem.amg import SmoothedAggregation
from ngincompat.fem.rigid import rigid_body_modes
from ngincompat.fem.sparse_lu import SuperLUInverse
from ngincompat.fem.symmetric import SymmetricPart
from ngincompat.fem.work import part

log = logging.getLogger(__name__)


class NewtonProblem(Protocol):
    """What :class:`NewtonSolver` uses of a problem, as
    :class:`~ngincompat.fem.problem.GrowthMechanics` and
    :class:`~ngincompat.fem.coupled.CoupledProblem`
    provide it (:func:`~ngincompat.fem.stepping.solve_growth` and
    :func:`~ngincompat.fem.stepping.solve_coupled` use more of each).

    Attributes
    ----------
    form : ngsolve.BilinearForm
        The nonlinear form whose ``Apply`` is the residual and whose linearisation the tangent;
        with ``has_energy``, ``Energy`` is the energy it derives from.
    state : ngsolve.GridFunction
        All unknowns; Newton updates its vector in place.
    fes : ngsolve.FESpace
        The space of ``state``.
    freedofs : ngsolve.BitArray
        The dofs the tangent is inverted on (with static condensation: the coupling ones).
    pinned : tuple of int
        Dofs held fixed in addition to the Dirichlet ones (rigid-body pins).
    condense : bool
        Whether ``form`` condenses element-interior dofs.
    inverse : str
        The sparse direct solver to use unless the options name one.
    has_energy : bool
        Whether ``form`` derives from an energy (the line search then tests it).
    """

    form: ngs.BilinearForm
    state: ngs.GridFunction
    fes: ngs.FESpace
    freedofs: ngs.BitArray
    pinned: tuple[int, ...]
    condense: bool
    inverse: str
    has_energy: bool


#: What the line search asks of a trial state (see :class:`NewtonOptions`).
BACKTRACKS = ("descent", "finite")
#: Linear solvers of the Newton directions (see :class:`NewtonOptions`).
LINEAR_SOLVERS = ("auto", "direct", "cg", "gmres", "symmetric-gmres", "amg")
#: Sparse direct solvers of the "direct" linear solver: NGSolve's, and SuperLU from SciPy
#: (:mod:`ngincompat.fem.sparse_lu`, the coupled problems' non-symmetric tangents).
INVERSES = ("sparsecholesky", "umfpack", "pardiso", "superlu")


#: From this many unknowns on, "auto" solves a tangent that an iterative solver suits (the
#: symmetric positive definite Hessian of an energy minimisation: CG with the smoothed-
#: aggregation multigrid, "amg") iteratively instead of factorising it: the factorisation's
#: time and memory grow far faster than the unknowns, and above this size it is the slower
#: and the larger (``docs/performance.md``, "Where auto switches to CG").
ITERATIVE_NDOF = 40_000


def resolve_linear_solver(name: str, mesh: ngs.Mesh, ndof: int = 0,
                          iterative: str | None = None) -> str:
    """The linear solver that ``name`` (one of :data:`LINEAR_SOLVERS`) means on ``mesh`` for
    a problem of ``ndof`` unknowns whose tangent ``iterative`` suits (None: no iterative
    solver does, e.g. a non-symmetric tangent): "auto" is "cg" on a distributed mesh, else
    ``iterative`` from :data:`ITERATIVE_NDOF` unknowns on and "direct" below."""
    if name != "auto":
        return name
    if parallel.distributed(mesh):
        return "cg"
    return iterative if iterative is not None and ndof >= ITERATIVE_NDOF else "direct"


@dataclass(frozen=True)
class NewtonOptions:
    """Settings of the nonlinear solver.

    Attributes
    ----------
    rtol : float
        Converged when the residual norm falls below ``rtol`` times that of the step's start.
        Near the solution Newton squares the error, so 1e-9 leaves an energy error of order
        1e-18 relative: far below any discretisation error, and one iteration fewer than 1e-10
        where the last step would only square a negligible error.
    atol : float
        ... or below ``atol`` (absolute, in the problem's force unit).
    max_iter : int
        Newton iterations per load step before the step is cut.
    steps : int
        Number of equal load steps to start with (1: the full growth at once).
    min_step : float
        Smallest load step before giving up.
    max_backtracks : int
        Halvings of the line search before the Newton step counts as failed.
    inverse : str or None
        Sparse direct solver: "sparsecholesky", "umfpack" or "pardiso" (if installed);
        None takes the problem's choice (Cholesky for energy minimisation, umfpack for the
        non-symmetric coupled-growth system).
    predictor : bool
        Start each load step from the best compatible approximation of the growth increment
        (:meth:`GrowthMechanics.compatible_displacement`) rather than from the last state.
    extrapolate : bool
        :func:`~ngincompat.fem.stepping.solve_coupled` starts each step from the linear
        extrapolation in time of the last two converged states, u_n + dt / dt_prev (u_n -
        u_n-1), rather than from u_n (from the second converged step on, and again after a
        cut step).
    max_step : float
        Largest step the adaptive stepping may grow to (time accuracy of coupled growth).
    step_up : int
        A converged step that took at most this many Newton iterations doubles the next one
        (up to ``max_step``).
    step_hold : int
        After a failed step (cut in half), the next ``step_hold`` converged steps do not
        double the step, however easy: where the march meets a short event (a fold that
        snaps), doubling after the first easy step fails again and again
        (docs/measurements/folding.md, "The march's failed steps").
    stall : int
        Give a step up as failed once the residual norm has stayed above its smallest value
        before for this many iterations in a row (from the fifth iteration on; 0: never),
        rather than after ``max_iter``: a step that does not converge cycles between
        residuals that never fall below what its first iterations reached, and is retried
        shorter as it would be at ``max_iter`` (docs/measurements/folding.md, "The march's
        failed steps").
    line_search : bool
        Backtrack on the energy; without it every Newton step is taken in full (plain Newton,
        kept for comparison: it fails where a full step leaves the domain Je > 0).
    backtrack : {"descent", "finite"}
        What the line search asks of a trial state: "descent", the Armijo condition on the
        energy or a sufficient decrease of the residual norm; "finite", only a finite energy
        and residual (Je > 0 everywhere): Newton's full step unless it inverts an element. For
        a march whose residual is not the derivative of the energy (coupled growth by a
        stretch-driven law), where the energy is no merit function and a full step that first
        raises the residual is what converges (docs/measurements/folding.md, "The march's
        line search").
    reuse_tangent : bool
        Keep the factorised tangent for the following iterations as long as each of them
        reduces the residual norm at least ``1 / reuse_contraction``-fold and needs no
        backtracking (a modified Newton method); otherwise, and at the start of every load
        step, the tangent is assembled and factorised afresh. Pays where assembling and
        factorising cost far more than a residual (high order, few elements).
    reuse_contraction : float
        The contraction in (0, 1) a reused tangent must achieve per iteration.
    linear_solver : {"auto", "direct", "cg", "gmres", "symmetric-gmres", "amg"}
        How the tangent system is solved: "direct" factorises it (``inverse``); "cg" and
        "gmres" iterate, preconditioned by BDDC (NGSolve's balancing domain decomposition by
        constraints, on the condensed system where the problem condenses), to a residual
        ``krylov_rtol`` relative to the right-hand side (far below Newton's ``rtol``: the
        iterates are Newton's, and the answer the direct solver's). "symmetric-gmres" iterates with
        GMRES preconditioned by the sparse Cholesky factorisation (LDL^T) of the tangent's
        symmetric part (K + K^T) / 2: for a tangent that is symmetric but for a weak
        coupling, as coupled growth's (the condensed growth block), where it needs a few
        iterations and costs far less than an LU factorisation of K (serial only). "amg"
        iterates with CG preconditioned by one V-cycle of a smoothed-aggregation algebraic
        multigrid built from the rigid motions (:mod:`ngincompat.fem.amg`, PyAMG; serial
        only), for an energy's Hessian on a displacement space. CG
        needs a positive definite tangent, as near equilibrium; GMRES also copes with the
        indefinite tangent that the start of a load step can have (and with the indefinite
        BDDC built from it). "auto": in a serial run "direct", or from
        :data:`ITERATIVE_NDOF` unknowns on the iterative solver the problem declares
        (``iterative``: "amg" for an energy minimisation), "cg" on a distributed mesh (the
        pip wheels have no distributed direct solver; a direct inverse there is gathered
        onto rank 0).
    krylov_rtol : float
        Relative residual at which the iterative linear solver stops.
    krylov_maxiter : int
        Iterations of the iterative linear solver per Newton direction.
    """

    rtol: float = 1e-9
    atol: float = 1e-14
    max_iter: int = 30
    steps: int = 1
    min_step: float = 1e-4
    max_backtracks: int = 30
    inverse: str | None = None
    predictor: bool = True
    line_search: bool = True
    backtrack: str = "descent"
    extrapolate: bool = False
    max_step: float = float("inf")
    step_up: int = 4
    step_hold: int = 0
    stall: int = 0
    reuse_tangent: bool = False
    reuse_contraction: float = 0.1
    linear_solver: str = "auto"
    krylov_rtol: float = 1e-10
    krylov_maxiter: int = 2000

    def __post_init__(self) -> None:
        require(0 < self.rtol < 1, "rtol", self.rtol, "in (0, 1)")
        require(self.atol >= 0, "atol", self.atol, ">= 0")
        require(self.max_iter >= 1, "max_iter", self.max_iter, ">= 1")
        require(self.steps >= 1, "steps", self.steps, ">= 1")
        require(self.backtrack in BACKTRACKS, "backtrack", self.backtrack,
                ", ".join(BACKTRACKS))
        require(self.step_up >= 0, "step_up", self.step_up, ">= 0")
        require(self.step_hold >= 0, "step_hold", self.step_hold, ">= 0")
        require(self.stall >= 0, "stall", self.stall, ">= 0")
        require(0 < self.min_step <= 1, "min_step", self.min_step, "in (0, 1]")
        require(self.inverse in (None, *INVERSES), "inverse", self.inverse,
                ", ".join(INVERSES))
        require(0 < self.reuse_contraction < 1, "reuse_contraction", self.reuse_contraction,
                "in (0, 1)")
        require(self.linear_solver in LINEAR_SOLVERS, "linear_solver", self.linear_solver,
                ", ".join(LINEAR_SOLVERS))
        require(0 < self.krylov_rtol < 1, "krylov_rtol", self.krylov_rtol, "in (0, 1)")
        require(self.krylov_maxiter >= 1, "krylov_maxiter", self.krylov_maxiter, ">= 1")


@dataclass
class StepRecord:
    """What one attempted load step did (``linear_iterations``: those of the iterative
    linear solver per Newton direction, empty with a direct one)."""

    t: float
    dt: float
    converged: bool
    iterations: int = 0
    tangents: int = 0
    residuals: list = field(default_factory=list)
    line_search: list = field(default_factory=list)
    energy: float = float("nan")
    seconds: float = 0.0
    reason: str = ""
    linear_iterations: list = field(default_factory=list)


@dataclass
class SolverHistory:
    """The record of a whole solve: every attempted step, in order."""

    steps: list = field(default_factory=list)
    converged: bool = False
    t_reached: float = 0.0
    #: Seconds per kind of work (:data:`ngincompat.fem.work.KINDS`) while the history was
    #: made, where the stage's runner measured them.
    work: dict = field(default_factory=dict)

    @property
    def newton_iterations(self) -> int:
        return sum(s.iterations for s in self.steps if s.converged)

    @property
    def tangent_assemblies(self) -> int:
        """Tangents assembled and factorised over all attempted steps."""
        return sum(s.tangents for s in self.steps)

    def as_dict(self) -> dict[str, Any]:
        return {"converged": self.converged, "t_reached": self.t_reached,
                "newton_iterations": self.newton_iterations,
                "tangent_assemblies": self.tangent_assemblies,
                "work": dict(self.work),
                "steps": [asdict(s) for s in self.steps]}


class NewtonSolver:
    """Newton's method with a line search, for a :class:`NewtonProblem`.

    ``energy``, if given, is a function returning the energy of the problem's current state
    whose derivative the residual is (e.g. the strain energy of coupled growth at frozen
    growth and no load): the line search then tests it as it tests ``form.Energy`` of a
    problem ``has_energy``."""

    def __init__(self, problem: NewtonProblem, options: NewtonOptions = NewtonOptions(),
                 energy: Callable[[], float] | None = None) -> None:
        self.problem = problem
        self.options = options
        self._energy = energy
        self.has_energy = problem.has_energy or energy is not None
        vec = problem.state.vec
        self._res = vec.CreateVector()
        self._du = vec.CreateVector()
        self._u0 = vec.CreateVector()
        self._inverse: ngs.BaseMatrix | None = None
        free = problem.fes.FreeDofs()
        self._fixed = np.array([not free[i] for i in range(len(free))], dtype=bool)
        self._fixed[list(problem.pinned)] = True
        mesh = problem.fes.mesh
        self._mesh = mesh
        self.linear_solver = resolve_linear_solver(options.linear_solver, mesh,
                                                   problem.fes.ndof,
                                                   getattr(problem, "iterative", None))
        self._preconditioner: ngs.Preconditioner | None = None
        self._linear: CGSolver | GMResSolver | None = None
        self._symmetric: SymmetricPart | None = None
        if self.linear_solver in ("cg", "gmres"):
            # registered with the form: rebuilt by every AssembleLinearization
            self._preconditioner = ngs.Preconditioner(problem.form, "bddc")
        self._modes: np.ndarray | None = None
        if self.linear_solver == "amg":
            require(not parallel.distributed(mesh), "linear_solver", "amg",
                    "a serial run's solver (distributed: cg)")
            self._modes = rigid_body_modes(problem.fes)

    def energy(self, vec: ngs.BaseVector) -> float:
        """The problem's energy at ``vec``, summed over the ranks of a distributed mesh; with
        ``energy`` given, its value at the current state (which ``vec`` is)."""
        with part("energy"):
            if self._energy is not None:
                return self._energy()
            return parallel.total(self._mesh, self.problem.form.Energy(vec))

    def residual(self, vec: ngs.BaseVector | None = None) -> ngs.BaseVector:
        """The residual (energy gradient) on free dofs at ``vec`` (default: the current u)."""
        a = self.problem.form
        with part("residual"):
            a.Apply(self.problem.state.vec if vec is None else vec, self._res)
            self._res.FV().NumPy()[self._fixed] = 0.0
        return self._res

    def factorise(self) -> None:
        """Assemble the tangent at the current state and factorise it (kept for
        :meth:`direction` until the next call)."""
        p = self.problem
        with part("assembly"):
            p.form.AssembleLinearization(p.state.vec)
        if self.linear_solver == "direct":
            inverse = self.options.inverse or p.inverse
            with part("factorisation"):
                self._inverse = (SuperLUInverse(p.form.mat, p.freedofs)
                                 if inverse == "superlu"
                                 else p.form.mat.Inverse(p.freedofs, inverse=inverse))
            return
        if self.linear_solver == "symmetric-gmres":
            if self._symmetric is None:
                self._symmetric = SymmetricPart(p.form.mat)
            with part("factorisation"):
                preconditioner = self._symmetric.of(p.form.mat).Inverse(
                    p.freedofs, inverse="sparsecholesky")
            krylov = GMResSolver
        elif self.linear_solver == "amg":
            with part("factorisation"):
                preconditioner = SmoothedAggregation(p.form.mat, p.freedofs,
                                                     self._modes)  # type: ignore[arg-type]
            krylov = CGSolver
        else:
            free = ngs.Projector(p.freedofs, True)
            # made with the solver for cg and gmres
            preconditioner = free @ self._preconditioner.mat @ free  # type: ignore[union-attr]
            krylov = CGSolver if self.linear_solver == "cg" else GMResSolver
        self._linear = krylov(p.form.mat, preconditioner, tol=self.options.krylov_rtol,
                              maxiter=self.options.krylov_maxiter)
        self._inverse = self._linear

    def direction(self) -> ngs.BaseVector:
        """Solve K du = r with the last factorised tangent K (of the current state unless
        tangents are reused); returns du."""
        p = self.problem
        a, r, du, inv = p.form, self._res, self._du, self._inverse
        with part("linear solve"):
            if p.condense:
                rhs = r.CreateVector()
                rhs.data = r
                rhs.data += a.harmonic_extension_trans * r
                du.data = inv * rhs
                du.data += a.harmonic_extension * du
                du.data += a.inner_solve * rhs
            else:
                du.data = inv * r
        return du

    def _acceptable(self, E: float, E_new: float, alpha: float, slope: float,
                    r_norm: float, r_new: float | None) -> tuple[bool, float | None]:
        """Is the trial state (already in u) acceptable? ``r_new`` is its residual norm where
        already computed (in the solver's residual vector), else None. Returns the answer
        and the trial's residual norm where it is known (then in the residual vector).

        A non-finite energy (Je <= 0 somewhere) never is. Otherwise, with ``backtrack``
        "finite" any state with a finite residual is; with "descent" a step is accepted if it
        satisfies the Armijo condition on the energy or decreases the residual norm
        sufficiently. The second test is what lets Newton finish where energy differences drown
        in round-off and what drives problems without an energy; it also accepts steps that
        raise the energy (seen with nearly incompressible materials, where the tangent at the
        start of a step is indefinite).
        """
        if not math.isfinite(E_new):
            return False, r_new
        if self.options.backtrack != "finite" and self.has_energy and (
                E_new <= E + 1e-4 * alpha * min(slope, 0.0)):
            return True, r_new
        if r_new is None:
            r_new = self.residual().Norm()
        if self.options.backtrack == "finite":
            return math.isfinite(r_new), r_new
        return math.isfinite(r_new) and r_new <= (1 - 1e-4 * alpha) * r_norm, r_new

    def _step(self, E: float, r: ngs.BaseVector) -> tuple[float, float, bool]:
        """One line-searched step along the Newton direction from the current state.

        Returns (alpha, energy, known) of the accepted step, known where the solver's
        residual vector holds the residual there already (the line search computed it), or
        (0, E, True) with the state unchanged when no step length was acceptable."""
        opts = self.options
        u = self.problem.state.vec
        du = self.direction()
        slope = -ngs.InnerProduct(du, r)
        r_norm = r.Norm()
        self._u0.data = u
        if not opts.line_search:
            # the full step; without an energy the caller's residual there is the merit
            u.data = self._u0 - du
            return 1.0, self.energy(u) if self.has_energy else E, False
        trial: dict[str, float] = {}
        known: list[bool] = []

        def acceptable(alpha: float) -> bool:
            r_new = None if self.has_energy else self.residual().Norm()
            E_new = self.energy(u) if self.has_energy else _merit(r_new)  # type: ignore[arg-type]
            ok, r_new = self._acceptable(E, E_new, alpha, slope, r_norm, r_new)
            trial["E"] = E_new
            known[:] = [r_new is not None]
            return ok

        alpha = self._backtrack(du, acceptable, opts.max_backtracks)
        if alpha == 0.0:
            self.residual()
            return 0.0, E, True
        return alpha, trial["E"], known[0]

    def _backtrack(self, du: ngs.BaseVector, acceptable: Callable[[float], bool],
                   tries: int) -> float:
        """Move the state from ``_u0`` along -``du`` by the first of ``tries`` lengths 1,
        1/2, 1/4, ... at which ``acceptable(alpha)`` holds (the trial state in place);
        returns that length, or 0 with the state back at ``_u0``."""
        u = self.problem.state.vec
        alpha = 1.0
        for _ in range(tries):
            u.data = self._u0 - alpha * du
            if acceptable(alpha):
                return alpha
            alpha /= 2
        u.data = self._u0
        return 0.0

    def step(self, record: StepRecord, acceptable: Callable[[], bool]) -> float:
        """One Newton step from the current state: the tangent assembled and factorised there
        once, the state moved along its direction by the longest of 1, 1/2, 1/4, ... (at
        most ``max_backtracks`` halvings) at which ``acceptable()`` holds (called with the
        trial state in place, e.g. an energy that must fall). Fills ``record`` (one
        iteration, one tangent, the residual at the start, the step length); returns the
        step length, or 0 with the state restored where none was acceptable or the residual
        at the start is not finite."""
        u = self.problem.state.vec
        r = self.residual()
        record.residuals.append(r.Norm())
        record.iterations = 1
        if not math.isfinite(record.residuals[-1]):
            record.reason = "residual is not finite at the start of the step"
            return 0.0
        self.factorise()
        record.tangents += 1
        self._u0.data = u
        du = self.direction()
        if self._linear is not None:
            record.linear_iterations.append(self._linear.iterations)
        alpha = self._backtrack(du, lambda _: acceptable(), self.options.max_backtracks + 1)
        if alpha == 0.0:
            record.reason = "no step along the direction was acceptable"
        else:
            record.line_search.append(alpha)
        return alpha

    def minimise(self, record: StepRecord) -> bool:
        """Newton iterations at the current load; fills ``record``; returns True if converged."""
        opts = self.options
        u = self.problem.state.vec
        r = self.residual()
        r0 = r.Norm()
        record.residuals.append(r0)
        E = self.energy(u) if self.has_energy else _merit(r0)
        if not (math.isfinite(E) and math.isfinite(r0)):   # inf <= rtol * inf would pass
            record.reason = "energy or residual is not finite at the start of the step"
            return False
        fresh, short = True, 0      # short: iterative solves stopped at their limit
        for it in range(1, opts.max_iter + 1):
            if r.Norm() <= max(opts.rtol * r0, opts.atol):
                record.iterations, record.energy = it - 1, E
                return True
            if fresh or not opts.reuse_tangent:
                self.factorise()
                record.tangents += 1
            r_old = r.Norm()
            alpha, E_new, known = self._step(E, r)
            record.line_search.append(alpha)
            if self._linear is not None:
                record.linear_iterations.append(self._linear.iterations)
                last = self._linear.residuals or [0.0]
                short += (self._linear.iterations >= opts.krylov_maxiter
                          and last[-1] > opts.krylov_rtol * last[0])
            if alpha == 0.0:
                if not fresh and opts.reuse_tangent:
                    fresh = True    # an old tangent failed: retry with a new one
                    continue
                record.iterations = it
                record.reason = "line search found no acceptable step" + self._note(short)
                return False
            E = E_new
            # the line search's last trial is the new state: its residual, if it took one
            r = self._res if known else self.residual()
            record.residuals.append(r.Norm())
            if not math.isfinite(record.residuals[-1]):
                record.reason = "residual is not finite"
                return False
            fresh = alpha < 1.0 or r.Norm() > opts.reuse_contraction * r_old
            if _at_roundoff(record.residuals):
                record.iterations, record.energy = it, E
                return True
            if _stalled(record.residuals, opts.stall):
                record.iterations = it
                record.reason = (f"the residual stayed above its smallest value for "
                                 f"{opts.stall} iterations" + self._note(short))
                return False
        record.iterations = opts.max_iter
        if r.Norm() <= max(opts.rtol * r0, opts.atol):
            record.energy = E
            return True
        record.reason = f"no convergence in {opts.max_iter} iterations" + self._note(short)
        return False

    def _note(self, short: int) -> str:
        """A failed step's reason's addition where ``short`` of its iterative solves stopped
        at ``krylov_maxiter`` above their tolerance: directions not the tangent's."""
        return "" if not short else (f" ({short} of its linear solves stopped at "
                                     f"krylov_maxiter = {self.options.krylov_maxiter} "
                                     "iterations above their tolerance: a preconditioner "
                                     "too weak for this tangent)")


#: A step whose residual has fallen below this fraction of the largest of its iterations
#: and then stops falling (the next residual at least half the one before) has reached the
#: round-off of its assembly: it is converged, even where ``rtol`` times the start's
#: residual lies below that round-off. Seen on the folding bilayer at 80,794 unknowns: a
#: growth step's residual fell from 1.6e-4 to 2.9e-14 and stayed there, where 1e-9 of its
#: start asked for 1.6e-14 (``docs/measurements/folding.md``, "The march's failed
#: steps").
ROUNDOFF = 1e-8


def _at_roundoff(residuals: Sequence[float]) -> bool:
    """Has the residual stopped falling (the last at least half the one before) after it
    fell below :data:`ROUNDOFF` of the largest of the step (``residuals[0]`` its start)?"""
    if len(residuals) < 3:
        return False
    return (residuals[-2] <= ROUNDOFF * max(residuals[:-1])
            and residuals[-1] >= 0.5 * residuals[-2])


#: The first Newton iteration after which a step may count as stalled (``stall``).
STALL_FROM = 5


def _stalled(residuals: Sequence[float], stall: int) -> bool:
    """Have the last ``stall`` residuals (``residuals[0]`` the step's start, one per
    iteration after it) all stayed above the smallest before them, from iteration
    :data:`STALL_FROM` on? Never with ``stall`` = 0."""
    k = len(residuals) - 1
    if stall == 0 or k < max(STALL_FROM, stall):
        return False
    return min(residuals[-stall:]) > min(residuals[:-stall])


def _merit(residual_norm: float) -> float:
    """Stand-in for the energy of a problem without one: 0 where the residual is finite."""
    return 0.0 if math.isfinite(residual_norm) else float("nan")
