"""The skin scene's case (section 3.6): the coupled problem of the patch and the stages it
walks (inflation, hold, deflation, release), and what is measured of the result."""

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from geometries.skin_patch import SIDE
from ngincompat import config, sampling
from ngincompat.errors import require
from ngincompat.fem import contact, postprocess
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stages import (
    ContactControlStage,
    CoupledStage,
    FallbackStage,
    PrescribedGrowthStage,
    Stage,
    restore_checkpoint,
)
from ngincompat.fem.terms import DeadTraction, GrowthEnergy, VolumeConstraint
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.growth import AreaGrowth
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.progress import Progress
from ngincompat.scenes import curvature as curvature_report
from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.skin import figures, measures
from ngincompat.workflow.frames import Frames
from ngincompat.workflow.pipeline import Solution, solve_stages, timed
from ngincompat.workflow.results import Results

#: The hold's checkpoint in the output folder (``--set resume=true`` continues from it).
CHECKPOINT = "checkpoint.npz"
#: Step of the quasi-static deflation, as a fraction of the inflated volume (steps of twice
#: that fail and are cut).
DEFLATION_STEP = 0.1
#: The deflation ends where the load that holds the skin up (pressure, contact force) has
#: fallen to this fraction of its value at the end of the hold: Newton without the expander
#: goes on from there to the same clamped state as from where the load vanishes, and the
#: steps close to zero load are the ones that fail and are cut (the skin goes slack)
#: (``docs/measurements/skin.md``, "The deflation's path").
DEFLATED = 0.25
#: Newton iterations allowed per step of a deflation that lowers the volume: lowering the
#: contact model's dome takes more than the pressure model's steps (the skin leaves the
#: dome), and with fewer allowed its steps were cut and stayed cut
#: (``docs/measurements/skin.md``, "The deflation's path").
DEFLATION_MAX_ITER = 25
#: Newton iterations up to which a converged inflation step doubles the next one (up to the
#: initial step).
INFLATION_STEP_UP = 10
#: Boundary conditions while the patch is held: the periphery clamped, the base sliding.
CLAMP: dict[str, Any] = {"dirichlet": "periphery", "symmetry": {"bottom": "z"}}



@dataclass(eq=False)
class SkinCase(SceneCase):
    """The skin scene's case: the coupled problem and the stages it walks. ``scene`` is the
    :class:`~ngincompat.scenes.skin.scene.SkinExpansionScene` that built it.

    Stages: ``inflation`` (volume 0 -> V, growth frozen), with an expander in contact
    ``contact`` (the expander resized until the volume under the skin is V), ``hold`` (V, or
    the expander, held, Hill-law area growth for ``hold_days``, checkpointed),
    ``deflation`` (growth frozen; the volume, or the dead traction that the contact force
    was handed over to, lowered in steps of :data:`DEFLATION_STEP` of it until the load that
    holds the skin, the pressure or the traction, has fallen to :data:`DEFLATED` of its
    value at the end of the hold),
    ``deflation_clamped`` (the expander taken out: the equilibrium of the grown, clamped
    patch without a load) and ``deflation_released`` (the expander and the clamp taken out:
    the free patch's equilibrium), each found by Newton from the deflated state. This
    follows the physical path, and it costs tens of Newton iterations where applying the
    grown field to the flat patch in load steps from u = 0 cost hundreds: a grown, clamped
    patch has more area than its frame and must buckle out of the flat state, and that path
    let it buckle either way, also down through its base. Where Newton fails from the
    deflated state, a stage falls back to those load steps. The grown skin has more than one
    equilibrium, clamped and free; the deflated path keeps the bulge on the side it was
    inflated to. (From the clamped equilibrium, Newton finds the free rectangle no step that
    lowers its energy: its tangent is indefinite there.) The state at the end of the hold is
    kept for what is measured of it.
    """

    scene: Any
    mesh: ngs.Mesh
    noted: dict = field(default_factory=dict)
    end_of_hold: tuple | None = None
    load_end_of_hold: float = float("nan")

    def __post_init__(self) -> None:
        scene, mesh = self.scene, self.mesh
        self.material = NeoHookean.from_nu(scene.mu, scene.nu)
        self.N0 = fields.constant("e3")
        self.growth = GrowthEnergy("area", self.N0, scene.law(), self.material,
                                   growth_order=scene.growth_order)
        # the contact model's expander: the dome under the footprint, whose load a dead
        # traction on the footprint takes over as it is emptied; the pressure model's, the
        # volume under the footprint held by a pressure
        self.in_contact = scene.expander == "contact"
        if self.in_contact:
            self.holder: contact.ExpanderContact | VolumeConstraint = contact.ExpanderContact(
                scene.expander_body(), "footprint")
            self.traction: DeadTraction | None = DeadTraction("footprint")
            terms = [self.growth, self.traction, self.holder]
        else:
            self.holder, self.traction = VolumeConstraint("footprint"), None
            terms = [self.growth, self.holder]
        self.problem = CoupledProblem(mesh, terms, order=scene.order, **CLAMP)
        self.ramp = ngs.Parameter(0.0)
        self.relaxed: dict[str, GrowthMechanics] = {}
        self.frames: Frames = Frames.of(scene, mesh, lambda: self._frame_fields(self.problem.u))

    def stages(self, workdir: Path | None, t_hold: float | None) -> list[Stage]:
        """The load history from the hold time ``t_hold`` on (None: from the start)."""
        scene, problem, holder = self.scene, self.problem, self.holder
        checkpoint = None if workdir is None else Path(workdir) / CHECKPOINT
        stages: list[Stage] = []
        if t_hold is None:
            # A cut step grows back after up to INFLATION_STEP_UP iterations: the contact
            # steps take more than Newton's default allows for it, and a step cut once stayed
            # cut to the end of the inflation (docs/measurements/skin.md, "The stages' step
            # controls").
            step = 1.0 / scene.inflation_steps
            stages.append(CoupledStage("inflation", problem, t_end=1.0, dt=step, grow=False,
                                       volume=(0.0, scene.volume), holder=holder,
                                       options=NewtonOptions(max_iter=20, max_step=step,
                                                             step_up=INFLATION_STEP_UP),
                                       observe=lambda s: self.frames.take(s - 1)))
            if self.in_contact:
                stages.append(ContactControlStage("contact", problem,
                                                  holder,  # type: ignore[arg-type]  # in contact
                                                  scene.volume))
        # the contact model's expander keeps the size that gave the volume
        held = None if self.in_contact else (scene.volume, scene.volume)
        # A hold step changes the tangent little: the hold reuses it while Newton contracts,
        # the inflation, which got slower with it, keeps fresh ones (docs/measurements/
        # skin.md, "The stages' step controls").
        stages.append(CoupledStage("hold", problem, t_end=scene.hold_days, dt=scene.dt,
                                   t_start=t_hold or 0.0, volume=held, holder=holder,
                                   options=NewtonOptions(max_iter=20, max_step=scene.dt,
                                                         reuse_tangent=True),
                                   checkpoint=checkpoint, observe=self.frames.take,
                                   unit=scene.units["time"]))
        # The contact model deflates by its dome's force, handed over to a dead traction,
        # whose steps are cheaper than lowering the dome as the skin leaves it; both paths end
        # in the same released state. Where the dead traction's path has a limit point, the
        # deflation starts again from the end of the hold and lowers the dome
        # (docs/measurements/skin.md, "The deflation's path").
        deflation: dict[str, Any] = dict(t_end=1.0, dt=DEFLATION_STEP, grow=False,
                                         observe=self._deflated)
        lowered = CoupledStage("deflation", problem, volume=(None, 0.0), holder=holder,
                               **deflation,
                               options=NewtonOptions(max_iter=DEFLATION_MAX_ITER,
                                                     max_step=DEFLATION_STEP,
                                                     reuse_tangent=True))
        if not self.in_contact:
            stages.append(lowered)
        else:
            stages.append(FallbackStage(
                CoupledStage("deflation", problem, traction=(1.0, 0.0), dead_load=self.traction,
                             start=self.expander_to_traction, **deflation,
                             options=NewtonOptions(max_iter=12, max_step=DEFLATION_STEP,
                                                   reuse_tangent=True)),
                lowered, reset=self._back_to_end_of_hold))
        ramped = AreaGrowth(1 + (self.growth.theta - 1) * self.ramp, self.N0)
        for stage, bcs in (("clamped", CLAMP), ("released", {})):
            relaxed = GrowthMechanics(self.mesh, ramped, self.material, order=scene.order,
                                      **bcs)
            self.relaxed[stage] = relaxed
            stages.append(PrescribedGrowthStage(f"deflation_{stage}", relaxed, self.ramp,
                                                NewtonOptions(max_iter=30), start=problem.u))
        return stages

    def solve(self, solution: Solution, progress: Progress,
              workdir: Path | None = None) -> None:
        t_hold = None
        if self.scene.resume and workdir is not None:
            t_hold = restore_checkpoint(self.problem, Path(workdir) / CHECKPOINT)
            if t_hold is not None:
                progress.line(f"resuming the hold at t = {t_hold:.4g} "
                              f"{self.scene.units['time']}")
                self._note_inflated()
        solution.state = self.problem
        stages = self.stages(workdir, t_hold)
        progress.plan(stage.name for stage in stages)
        with config.task_manager():
            solve_stages(stages, progress, solution, after=self._note)
        if not solution.converged and workdir is not None \
                and (Path(workdir) / CHECKPOINT).is_file():
            solution.error += (  # type: ignore[operator]  # an error: not converged
                f" (the last converged state of the hold is in {CHECKPOINT}; "
                "run again with --set resume=true)")

    def expander_to_traction(self) -> float:
        """Hand the expander's load over to the dead traction (the expander being emptied):
        the force the expander exerts on the footprint in the current state becomes the
        traction (scale 1, :meth:`~ngincompat.fem.terms.DeadTraction.hold`) and the
        expander is lowered to height 0, under the footprint (which stays in X3 >= 0), so
        the state remains an equilibrium. Returns the norm of that force."""
        require(self.in_contact, "expander", self.scene.expander,
                "contact (a dome whose load a dead traction takes over)")
        self.holder.target.Set(0.0)
        return self.traction.hold()  # type: ignore[union-attr]  # in contact: a traction

    def _note(self, stage: Stage) -> None:
        if stage.name == "contact":
            self.frames.take(0.0)       # the inflation's end, corrected
        elif stage.name.startswith("deflation_"):
            which = stage.name.removeprefix("deflation_")
            self.frames.take(self.scene.hold_days + (2 if which == "clamped" else 3),
                             self._frame_fields(self.relaxed[which].u))
        if stage.name == ("contact" if self.in_contact else "inflation"):
            self._note_inflated()
        elif stage.name == "hold":
            self.noted.update(self._loads("end_of_hold"))
            self.end_of_hold = (self.problem.state.vec.CreateVector(),
                                self.holder.target.Get())
            self.end_of_hold[0].data = self.problem.state.vec
            self.load_end_of_hold = self._holding_load()

    def _back_to_end_of_hold(self) -> None:
        """The state, the expander and no dead traction of the end of the hold."""
        # end_of_hold: kept when the hold ended (this follows it)
        self.problem.state.vec.data = self.end_of_hold[0]  # type: ignore[index]
        self.holder.target.Set(self.end_of_hold[1])  # type: ignore[index]
        if self.traction is not None:
            self.traction.scale.Set(0.0)

    def _deflated(self, t: float) -> bool:
        """Whether the deflation has gone far enough: the load that holds the skin up has
        fallen to :data:`DEFLATED` of its value at the end of the hold. (Its step ``t``, the
        fraction of the load taken away, is a frame.)"""
        self.frames.take(self.scene.hold_days + t)
        return self._holding_load() <= DEFLATED * self.load_end_of_hold

    def _holding_load(self) -> float:
        """What holds the skin up in the current state: the pressure, or the contact force
        (the integral of the contact pressure over the footprint)."""
        if not self.in_contact:
            return self.holder.pressure()  # type: ignore[union-attr]  # a VolumeConstraint
        scale = self.traction.scale.Get()  # type: ignore[union-attr]  # in contact: a traction
        if scale > 0:                       # the expander handed over to a dead traction
            return scale * self.load_end_of_hold
        return ngs.Integrate(self.holder.contact_pressure(),  # type: ignore[union-attr]
                             self.mesh, ngs.BND,
                             definedon=self.mesh.Boundaries("footprint"))

    def _note_inflated(self) -> None:
        volume = self.holder.volume()
        self.noted.update(volume_inflated=volume,
                          volume_error_rel=abs(volume - self.scene.volume) / self.scene.volume,
                          **self._loads("inflated"))

    def _loads(self, when: str) -> dict[str, float]:
        """What holds the volume at ``when``: the pressure, or the expander and its contact
        (the measures of the problem's terms)."""
        return {f"{k}_{when}": v for k, v in self.problem.measures().items()}

    def keep(self, results: Results) -> None:
        """The hold's checkpoint."""
        results.files = [CHECKPOINT]

    def _frame_fields(self, u: ngs.GridFunction) -> dict[str, Any]:
        """The fields of a frame at the displacement ``u``: u, theta, J and Je = J / theta
        (area growth: Jg = theta)."""
        J = ngs.Det(kinematics.deformation_gradient(u))
        theta = self.growth.theta
        return {"u": u, "theta": theta, "J": J, "Je": J / theta}

    def measure(self, solution: Solution, progress: Progress) -> Results:
        """Growth, incompatibility and residual stress of the grown patch."""
        results = self.interrupted(solution)
        if "hold" not in solution.histories or not solution.histories["hold"].converged:
            return results          # the hold did not end: its checkpoint is the result
        if self.end_of_hold is not None:    # the deflation moved on from the held state
            self._back_to_end_of_hold()
        scene, mesh, theta = self.scene, self.mesh, self.growth.theta
        metrics, timings = results.metrics, results.timings
        footprint = mesh.Boundaries("footprint")
        area = ngs.Integrate(1, mesh, ngs.BND, definedon=footprint)
        metrics["theta_max"] = sampling.maximum(theta, mesh)
        # an L2 field has no boundary trace: its continuous interpolant gives the footprint mean
        theta_h1 = ngs.GridFunction(ngs.H1(mesh, order=scene.growth_order))
        theta_h1.Set(theta)
        metrics["theta_mean_footprint"] = ngs.Integrate(theta_h1, mesh, ngs.BND,
                                                        definedon=footprint) / area
        growth = AreaGrowth(theta, self.N0)
        with progress.phase("incompatibility"), timed(timings, "incompatibility"):
            measured = Incompatibility.projected(growth.Fg, mesh, scene.g_order,
                                                 {"e3": self.N0.cf})
            flds = {"theta": theta, **measured.fields()}
            metrics["burgers_max"], where = sampling.argmax(flds["|b|"], mesh)
            metrics["burgers_max_radius"] = float(
                np.hypot(*where[:2]))  # type: ignore[call-overload]  # (X1, X2)
        # the problem's state is back at the end of the hold (the inflated, grown skin)
        flds["u_end_of_hold"] = self.problem.u
        if self.in_contact:
            flds.update(gap=self.holder.gap(),  # type: ignore[union-attr]  # an ExpanderContact
                        contact_pressure=self.holder.contact_pressure())  # type: ignore[union-attr]
        for stage, relaxed in self.relaxed.items():
            if f"deflation_{stage}" not in solution.histories:
                continue
            sigma = postprocess.stresses(relaxed.energy_density, relaxed.u)["sigma"]
            flds[f"sigma_max_{stage}"] = postprocess.largest_principal_value(sigma)
            flds[f"sigma_min_{stage}"] = -postprocess.largest_principal_value(-sigma)
            flds[f"u_{stage}"] = relaxed.u
            metrics[f"max_principal_stress_{stage}"] = sampling.maximum(
                flds[f"sigma_max_{stage}"], mesh)
            metrics[f"strain_energy_{stage}"] = relaxed.strain_energy()
        metrics.update(measures.apex(mesh, theta, flds["|b|"]))
        if self.in_contact and "sigma_min_released" in flds:
            metrics.update(measures.compression(mesh, self.holder,  # type: ignore[arg-type]
                                                flds["sigma_min_released"]))
        if "curvature" in scene.output_set():
            # growth computed on the mesh: the Regge path, on the continuous interpolant of Fg
            # that G is computed from (theta itself may jump between elements)
            with progress.phase("curvature"), timed(timings, "curvature"):
                extra, curved = cv.measure_growth(measured.Fg_h, mesh, measured.G,
                                                  exact=False)
            flds.update(extra)
            metrics.update(curved)
        edge = SIDE / 2 - figures.LINE_INSET
        line = ((-edge, 0.0, 0.0), (edge, 0.0, 0.0))
        sampled = [k for k in ("theta", "|b|", "sigma_max_clamped", "sigma_max_released",
                               "einstein_norm_g", "scalar_curvature") if k in flds]
        s, values = postprocess.sample_line(mesh, {k: flds[k] for k in sampled}, *line)
        results.profiles = {"line": {"X1": line[0][0] + s, **values},
                            "map": figures.mid_plane(mesh, flds)}
        results.fields = flds
        results.figures = figures.figures(scene, results.profiles["map"])
        if "curvature" in scene.output_set():
            curvature_report.report(scene, results, "X1", {"|b| on e3": "|b|"})
        return results
