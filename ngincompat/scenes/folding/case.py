"""The folding scene's case: the coupled bilayer, its stages (approach, perfect branch,
buckling, equilibrium, release), the records of its growth and the measures of the result."""

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat.fem import buckling, postprocess
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import pin_reactions
from ngincompat.fem.relaxation import RelaxationStage, SnappingMarch
from ngincompat.fem.self_contact import SelfContact
from ngincompat.fem.shape import circle_curvature
from ngincompat.fem.solver import NewtonSolver
from ngincompat.fem.stages import CoupledStage, Stage
from ngincompat.fem.terms import GrowthEnergy, ViscousRegularisation
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw
from ngincompat.mechanics.materials import NeoHookean, Regional
from ngincompat.progress import Progress
from ngincompat.sampling import element_points
from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.folding import measures
from ngincompat.scenes.folding.numerics import (
    CONTACT_REACH,
    EIGENPAIRS,
    MARCH_RTOL,
    RELAXATION_STEPS,
    RELAXATION_SWITCH,
    SNAP_STEP,
    STALL,
    newton,
    placing_onset,
)
from ngincompat.workflow.frames import Frames
from ngincompat.workflow.pipeline import Solution, solve_stages
from ngincompat.workflow.results import Results

#: Elastic compressive stretch at which the surface of a neo-Hookean half-space creases in
#: plane strain (critical strain 0.35: Hong, Zhao and Suo, Appl. Phys. Lett. 95 (2009)
#: 111901), well before the wrinkling stretch 0.54 of Biot's analysis.
CREASE_STRETCH = 0.65

#: Boundary conditions while growing: ends on rollers, bottom on rollers.
GROWING = {"left": "x", "right": "x", "bottom": "y"}

#: After the release: no support (the rigid motions are pinned).
RELEASED: dict[str, str] = {}


@dataclass(eq=False)
class FoldingCase(SceneCase):
    """The folding scene's case: the coupled bilayer and the observations of its growth.

    ``series`` holds, per converged step of the perfect branch and per record (every
    ``observe_dt`` of growth) of the buckling stage,
    the time, the cortex growth, the smallest tangent eigenvalue, the fold amplitude (half
    the peak-to-peak u2 along the top surface) and the top surface's smallest elastic
    stretch (:meth:`top_stretch`).

    ``scene`` is the :class:`~ngincompat.scenes.folding.scene.FoldingScene` that built it.
    """

    scene: Any
    mesh: ngs.Mesh
    noted: dict = field(default_factory=dict)
    series: dict = field(default_factory=lambda: {
        branch: {"t": [], "theta_c": [], "eigenvalue": [], "amplitude": [], "stretch": [],
                 "Je_min": [], "contact_length": [], "penetration": []}
        for branch in ("perfect", "buckling")})

    def __post_init__(self) -> None:
        scene, mesh = self.scene, self.mesh
        lam = scene.lam_ratio
        self.material = Regional(mesh, {
            "cortex": NeoHookean(scene.mu_gray, lam * scene.mu_gray),
            "subcortex": NeoHookean(scene.mu_white, lam * scene.mu_white)})
        axons = (fields.constant("e2") if scene.axons == "none" else
                 fields.axons(scene.axons, interface=scene.height - scene.cortex_thickness,
                              length=scene.length, vertical="e2"))
        self.f0 = fields.by_region(mesh, {"cortex": fields.constant("e1"),
                                          "subcortex": axons}, "f0")
        self.law = RegionalLaw(mesh, {"cortex": ConstantRateLaw(scene.cortex_rate),
                                      "subcortex": scene.axon_law()})
        self.problem, self.growth, self.viscous, self.contact = self.coupled()
        self.grown: ngs.GridFunction | None = None       # kept by the release
        self.grown_contact: dict[str, float] | None = None
        self.reactions = float("nan")
        self.mode: ngs.GridFunction | None = None
        self.pairs: tuple[np.ndarray, list[ngs.GridFunction]] | None = None
        self.frames: Frames = Frames.of(scene, mesh, lambda: {"u": self.problem.u,
                                                              "theta": self.growth.theta})

    def coupled(self) -> tuple[CoupledProblem, GrowthEnergy, ViscousRegularisation, SelfContact]:
        """The viscous coupled bilayer on its supports while growing (:data:`GROWING`),
        which :meth:`release` changes to :data:`RELEASED`; the top surface in self-contact
        (:class:`~ngincompat.fem.self_contact.SelfContact`, pairs within
        :data:`CONTACT_REACH` cortex thicknesses, and with its images in the roller ends:
        a sulcus there has its other wall in the image); its rigid motions pinned (none
        while growing). One problem for every stage: its residual is compiled once.
        Returns the problem and its growth, viscous and contact terms."""
        scene = self.scene
        growth = GrowthEnergy("fiber", self.f0, self.law, self.material,
                              growth_order=scene.growth_order)
        viscous = ViscousRegularisation()
        ends = {"left": ((0, 0, 0), (1, 0, 0)), "right": ((scene.length, 0, 0), (-1, 0, 0))}
        contact = SelfContact("top", scene.contact_penalty, scene.contact_width,
                              reach=CONTACT_REACH * scene.cortex_thickness,
                              mirrors=[ends[end] for end in ends if GROWING.get(end) == "x"])
        problem = CoupledProblem(self.mesh, [growth, viscous, contact],
                                 order=scene.order, symmetry=GROWING,
                                 realcompile=True if self.marches() else None)
        return problem, growth, viscous, contact

    def _along_top(self, cf: ngs.CoefficientFunction, n: int) -> tuple[np.ndarray, np.ndarray]:
        """X1 and the values of ``cf`` at ``n`` points along the top surface."""
        s = self.scene
        x, values = postprocess.sample_line(self.mesh, {"v": cf}, (0.0, s.height),
                                            (s.length, s.height), n=n)
        return x, values["v"]

    def top_profile(self, u: ngs.GridFunction, n: int = 301,
                    component: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """X1 and the displacement ``component`` along the top surface (default u2, the
        vertical)."""
        return self._along_top(u[component], n)

    def top_curvature(self, u: ngs.GridFunction, n: int = 301) -> float:
        """The curvature of the circle fitted to the deformed top line (X1 + u1, X2 + u2)
        over the central third of the length (1/length; > 0: bulging upward)."""
        x, u1 = self.top_profile(u, n, component=0)
        _, u2 = self.top_profile(u, n)
        third = (x >= self.scene.length / 3) & (x <= 2 * self.scene.length / 3)
        return circle_curvature(x[third] + u1[third], self.scene.height + u2[third])

    def top_stretch(self, u: ngs.GridFunction, theta_c: float, n: int = 301) -> float:
        """The smallest elastic stretch of the top surface along it, lambda_e = |F e1| /
        theta_c (F = I + Grad u; the cortex grows along e1 by theta_c), over ``n`` points
        along the top."""
        F_e1 = kinematics.deformation_gradient(u) * ngs.CF((1, 0, 0))
        _, values = self._along_top(ngs.Norm(F_e1), n)
        return float(np.nanmin(values)) / theta_c

    def _observe(self, branch: str, t: float,
                 negative: bool = False) -> tuple[np.ndarray, list[ngs.GridFunction]]:
        """Append the time, cortex growth, smallest eigenvalue, fold amplitude, smallest
        top stretch, smallest Je and the self-contact (:meth:`SelfContact.measures`: on the
        section its area is the length of the top line in contact) of the
        current state to ``series[branch]``; return the eigenpairs (:data:`EIGENPAIRS`
        smallest; with ``negative`` at least every negative one)."""
        values, modes = buckling.smallest_eigenpairs(self.problem, count=EIGENPAIRS,
                                                     negative=negative)
        _, u2 = self.top_profile(self.problem.u)
        theta_c = 1 + self.scene.cortex_rate * t
        contact = self.contact.measures()
        for key, value in (("t", t), ("theta_c", theta_c),
                           ("eigenvalue", values[0]), ("amplitude", np.ptp(u2) / 2),
                           ("stretch", self.top_stretch(self.problem.u, theta_c)),
                           ("Je_min", self.elastic_jacobian_min(self.growth, self.problem.u)),
                           ("contact_length", contact["self_contact_area"]),
                           ("penetration", contact["self_contact_penetration_max"])):
            self.series[branch][key].append(float(value))
        self.frames.take(t)             # a frame of fields.pvd per record
        return values, modes

    def _reached(self, t: float) -> None:
        """Note ``t`` and its cortex growth as the furthest the growth has gone."""
        self.noted.update(t_reached=float(t),
                          theta_c_reached=float(1 + self.scene.cortex_rate * t))

    def elastic_jacobian_min(self, growth: GrowthEnergy, u: ngs.GridFunction) -> float:
        """The smallest Je = det F / Jg (Jg = theta for fiber growth) over the integration
        points and vertices of the mesh: > 0 where no element has inverted."""
        Je = ngs.Det(kinematics.deformation_gradient(u)) / growth.theta
        return float(np.min(np.asarray(Je(element_points(self.mesh, 4))).ravel()))

    def _observe_perfect(self, t: float) -> bool:
        """Record the step; at the first negative eigenvalue measure the onset and stop.

        The onset is the earliest zero crossing among the modes negative there (all of them
        are computed at that step) and the modes of the step before:
        :func:`~ngincompat.fem.buckling.earliest_crossing`, each mode's Rayleigh quotient
        interpolated linearly in theta_c between the two steps, at the other step from its
        overlaps with that step's pairs. Past the onset the wrinkling modes fall steeply and
        cross in an order unlike the one they have at the first negative sample: the most
        negative there need not be the first to have crossed. ``onset_growth``,
        ``onset_time`` and ``onset_wavelength`` are that mode's, and it is the mode the
        state is perturbed by (:meth:`perturb`), as a combination of the modes of this
        step. At the first step (no step before) the onset is not bracketed: only the
        most negative mode and its wavelength are kept."""
        self._reached(t)
        values, modes = self._observe("perfect", t, negative=True)
        previous, self.pairs = self.pairs, (values, modes)
        if values[0] >= 0:
            return False
        self.mode = modes[0]
        if previous is not None:
            theta = self.series["perfect"]["theta_c"][-2:]
            onset, x, _ = buckling.earliest_crossing(  # type: ignore[misc]  # bracketed: found
                theta, previous[0], values, buckling.overlaps(previous[1], modes))
            self.mode = buckling.combine(modes, x)
            self.noted.update(onset_growth=onset,
                              onset_time=(onset - 1) / self.scene.cortex_rate)
        x, w = self.top_profile(self.mode)
        self.noted["onset_wavelength"] = buckling.wavelength(x, w)
        return True

    def _observe_buckling(self, t: float) -> bool:
        """Record the march's state (:meth:`_observe`: its eigenpairs cost as much as a
        Newton iteration and more) at its first step, then once at least ``observe_dt`` of
        growth has passed since the last record, and at ``t_end``."""
        series, scene = self.series["buckling"], self.scene
        self._reached(t)
        if (not series["t"] or t >= series["t"][-1] + scene.observe_dt - 1e-9
                or t >= scene.t_end - 1e-9 * max(1.0, scene.t_end)):
            self._observe("buckling", t)
        return False

    def perturb(self) -> None:
        """Add the onset's buckling mode to the displacement, scaled to ``imperfection`` x
        ``cortex_thickness`` on the top surface, and start the viscous regularisation
        (:attr:`eta`) from there."""
        _, w = self.top_profile(self.mode)
        scale = self.scene.imperfection * self.scene.cortex_thickness / np.max(np.abs(w))
        self.problem.u.vec.data += scale * self.mode.vec  # type: ignore[union-attr]  # the onset's
        self.viscous.restart(self.eta)

    def analysis_onset_time(self) -> float | None:
        """The time of the onset of the bifurcation analysis
        (:func:`~ngincompat.references.bifurcation.onset`, roller ends, scanned in theta_c
        steps of 0.02: it places steps, it is not the measured onset), or None if it finds
        none."""
        scene = self.scene
        growth = placing_onset(scene.bifurcation_bilayer(), scene.length)
        return None if growth is None else (growth - 1) / scene.cortex_rate

    def marches(self) -> bool:
        """Whether the run is expected to follow folds past the onset (``buckle``, and the
        analysis' onset before ``t_end``): hundreds of Newton iterations, for which the
        residual is compiled to C++ whatever the number of unknowns
        (:data:`~ngincompat.fem.problem.REALCOMPILE_NDOF`): the compilation, seconds, is
        repaid within the march (``docs/measurements/folding.md``, "The section")."""
        onset_time = self.analysis_onset_time()
        return self.scene.buckle and onset_time is not None and onset_time < self.scene.t_end

    def approach_end(self) -> float:
        """Where the perfect branch's short steps begin: 2 ``onset_dt`` before the
        analysis' onset (:meth:`analysis_onset_time`), or 0 (no approach) if that is not
        after two of the approach's longest steps, beyond ``t_end`` or not found."""
        scene, onset_time = self.scene, self.analysis_onset_time()
        if onset_time is None:
            return 0.0
        t = onset_time - 2 * scene.onset_dt
        return t if 2 * max(scene.approach_dt, scene.onset_dt) <= t < scene.t_end else 0.0

    def stages(self) -> list[CoupledStage]:
        """The perfect branch: ``approach`` in steps up to ``approach_dt`` to
        :meth:`approach_end` (if after 0), ``perfect`` from there in steps up to
        ``onset_dt``; both stop at the first negative eigenvalue."""
        scene = self.scene
        # Plain Newton steps: the residual norm mixes the growth residual (small: dt r times
        # element volumes) with forces, and the first full step, quadratically convergent
        # after it, raises it; a line search on it backtracks to 1/16 steps and takes several
        # times the iterations. A failed step is cut instead. Steps start from the
        # extrapolation of the last two states (the flat branch is smooth in t), which saves
        # Newton iterations to the onset (docs/measurements/folding.md, "Where the time goes").
        options = newton(max_step=scene.onset_dt, line_search=False, extrapolate=True)
        near = self.approach_end()
        perfect = CoupledStage("perfect", self.problem, t_end=scene.t_end,
                               dt=min(scene.dt, scene.onset_dt) if near else scene.dt,
                               t_start=near, options=options, observe=self._observe_perfect,
                               unit=scene.units["time"])
        if not near:
            return [perfect]
        return [CoupledStage("approach", self.problem, t_end=near, dt=scene.dt,
                             options=replace(options, max_step=max(scene.approach_dt,
                                                                   scene.onset_dt)),
                             observe=self._observe_perfect, unit=scene.units["time"]),
                perfect]

    @property
    def eta(self) -> float:
        """The viscosity of the regularisation (stress x time / length^2)."""
        return self.scene.viscosity * self.scene.mu_white

    def viscous_step(self) -> float:
        """The largest step of the viscous march, eta / (2 |omega_onset|), or ``dt``."""
        eigenvalue = self.series["perfect"]["eigenvalue"][-1]
        return min(self.scene.dt, self.eta / (2 * abs(eigenvalue)))

    def buckling_stage(self) -> SnappingMarch:
        """The viscous march from the onset step to ``t_end``, in steps up to
        :meth:`viscous_step` and ``onset_dt``: on the default bilayer every longer step
        (2.5 days) failed, a full Newton step from the growing folds inverting an element
        after about six iterations. A Newton step is shortened only where it would invert
        an element (non-finite: ``backtrack`` "finite"), not to lower the energy or the
        residual: with growing axons the residual is not the energy's derivative, and the
        full steps that converge first raise it (``docs/measurements/folding.md``, "The
        march's line search"); full steps without any shortening cut the march's steps far
        sooner on the coarse bilayer with the graded top. Each step is solved to
        :data:`MARCH_RTOL` from the extrapolation of the last two states; a step cut below
        :data:`SNAP_STEP` of the longest hands the snap to :meth:`relaxation` at held
        growth (:class:`~ngincompat.fem.relaxation.SnappingMarch`)."""
        step = min(self.viscous_step(), self.scene.onset_dt)
        options = newton(max_step=step, line_search=True, backtrack="finite",
                         min_step=step * SNAP_STEP, stall=STALL, rtol=MARCH_RTOL,
                         extrapolate=True)
        march = CoupledStage("buckling", self.problem, t_end=self.scene.t_end, dt=step,
                             t_start=self.series["perfect"]["t"][-1], options=options,
                             observe=self._observe_buckling, unit=self.scene.units["time"])
        return SnappingMarch(march, lambda: self.relaxation("buckling", self.problem,
                                                            self.viscous))

    def relaxation(self, name: str, problem: CoupledProblem,
                   viscous: ViscousRegularisation) -> RelaxationStage:
        """The gradient flow to the equilibrium at frozen growth of ``problem`` (its viscous
        term ``viscous``), in pseudo-time steps from the viscous march's largest; a saddle
        is left along its unstable mode, moved as the onset's imperfection is (``kick``:
        ``imperfection`` x ``cortex_thickness``)."""
        # at most 12 halvings of a step's direction (1/4096 of it), then a shorter step
        options = newton(line_search=False, min_step=1e-6, max_backtracks=12)
        return RelaxationStage(name, problem, viscous, self.eta, self.viscous_step(),
                               options=options,
                               unit=self.scene.units["time"], eigenpairs=EIGENPAIRS,
                               switch=RELAXATION_SWITCH,
                               max_steps=RELAXATION_STEPS,
                               kick=self.scene.imperfection * self.scene.cortex_thickness)

    @property
    def released(self) -> bool:
        """Whether :meth:`release` has begun (the supports removed)."""
        return self.grown is not None

    @property
    def grown_u(self) -> ngs.GridFunction:
        """The displacement of the grown state: kept by the release, else the current one."""
        return self.problem.u if self.grown is None else self.grown

    def release(self) -> list[RelaxationStage]:
        """The stage of the release from the current state, growth frozen: the grown state
        is kept (``grown``, its contact measures ``grown_contact``), the supports become
        :data:`RELEASED` and the images of the top in the roller ends go with them (the
        pressure of the images of its walls was a reaction of the symmetry planes); the
        forces they carried (``reactions``, the residual's norm there now) are the
        imbalance from which the relaxation finds the released equilibrium. Its first
        pseudo-time steps are short gradient steps, which the jump survives: ramping
        those forces off first (an unloading at the viscosity) cost 78-294 Newton
        iterations and reached the same equilibrium (``docs/measurements/folding.md``,
        "The release in contact")."""
        problem = self.problem
        self.grown = ngs.GridFunction(problem.space, name="u")
        self.grown.vec.data = problem.u.vec
        self.grown_contact = self.contact.measures()
        problem.support(RELEASED)
        self.contact.remove_mirrors()
        self.reactions = NewtonSolver(problem, newton()).residual().Norm()
        return [self.relaxation("release", problem, self.viscous)]

    def plan(self, branch: Iterable[Stage], onset: bool = True) -> list[str]:
        """The names of the stages a run goes through after the stages ``branch`` of the
        perfect branch (``onset``: if that reaches the onset, where the buckling starts)."""
        names = [stage.name for stage in branch]
        if onset and self.scene.buckle:
            names += ["buckling", "equilibrium"]
        return names + (["release"] if self.scene.release else [])

    def solve(self, solution: Solution, progress: Progress,
              workdir: Path | None = None) -> None:
        solution.state = self.problem
        branch = self.stages()
        progress.plan(self.plan(branch))
        for stage in branch:            # the perfect branch, ended at the onset
            if self.mode is None:
                solve_stages([stage], progress, solution)
            if not solution.converged:
                return
        if not solution.converged or (self.mode is not None and not self.scene.buckle):
            return
        if self.mode is not None:
            self.perturb()
            solve_stages([self.buckling_stage(),
                          self.relaxation("equilibrium", self.problem, self.viscous)],
                         progress, solution, after=self._note)
            if not solution.converged:
                self._explain_crease(solution)
                return
        if self.scene.release:
            if self.mode is None:       # no onset: nothing buckled
                progress.plan(self.plan(branch, onset=False))
            solve_stages(self.release(), progress, solution, after=self._note)

    def _explain_crease(self, solution: Solution) -> None:
        """Add to the error of a failed march where the top surface went below
        :data:`CREASE_STRETCH`, if it did."""
        series = self.series["buckling"]
        below = [i for i, v in enumerate(series["stretch"]) if v < CREASE_STRETCH]
        if below and solution.error:
            i = below[0]
            remedy = ("the unrefined top does not resolve the creases: refine it "
                      "(top_refinement, e.g. 4) or end the growth before (t_end)"
                      if self.scene.top_refinement == 1 else
                      "a finer top (top_refinement, cortex_maxh) or an end of the growth "
                      "before (t_end) may get through")
            solution.error += (
                f"; the top surface's elastic stretch fell below {CREASE_STRETCH} (the "
                f"creasing threshold of a neo-Hookean surface) at t = {series['t'][i]:.4g} "
                f"(theta_c = {series['theta_c'][i]:.4g}), {series['stretch'][-1]:.3g} at "
                f"the last step: the folds crease at the sulci; {remedy} "
                "(docs/measurements/folding.md)")

    def _note(self, stage: Any) -> None:
        """After the equilibrium its residual (relative to the start's) and smallest
        eigenvalue; after the release the reactions of the pins."""
        if stage.name == "equilibrium":
            self.noted.update(
                equilibrium_residual=stage.final_residual / stage.initial_residual,
                equilibrium_eigenvalue=stage.eigenvalue)
        elif stage.name == "release":
            reactions = np.linalg.norm(pin_reactions(self.problem))
            self.noted["release_reaction_rel"] = float(reactions / self.reactions)

    def measure(self, solution: Solution, progress: Progress) -> Results:
        """The measures of the grown and released states
        (:func:`ngincompat.scenes.folding.measures.measure`)."""
        return measures.measure(self, solution, progress)
