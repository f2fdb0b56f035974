"""The atrophy scene's case: the transport, the atrophy and the equilibria at the snapshots,
walked one stage per snapshot, and the measures of the result."""

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from geometries import fsaverage_brain as fsaverage
from ngincompat import config, parallel, sampling
from ngincompat.fem import depth, postprocess, resolution
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import NewtonOptions, SolverHistory
from ngincompat.fem.stepping import solve_growth
from ngincompat.fem.transport import FisherKPP, diffusion_tensor
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics.atrophy import exposure_increment
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.kinematics import deformation_gradient
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.progress import Progress
from ngincompat.scenes import curvature as curvature_report
from ngincompat.scenes.atrophy.figures import figures
from ngincompat.scenes.atrophy.tissues import PLANES, TISSUES, bounding_box
from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.hemisphere import spherical_basis
from ngincompat.workflow.frames import Frames
from ngincompat.workflow.pipeline import Solution, solve_stages, timed
from ngincompat.workflow.results import Results

#: The fields of a frame of the time series (the end's fields.vtu has more).
FRAME_FIELDS = ("c", "theta", "u", "J", "Je", *(f"|b_{p}|" for p in PLANES),
                "sigma_max_principal")
#: Bands of the depth profile per cortical thickness (Fig. 5e).
DEPTH_BANDS = 8
#: |Je - 1| above which the elastic volume change is not what nu = 0.49 allows (runs at the
#: defaults: 1.2e-2 on the ellipsoid; the coarse --maxh 2 --set t_end=10 --set dt=1 --set
#: snapshots=2: 0.54 over 1e-6 of the volume, its gray shell one element thick).
JE_DEVIATION = 0.1


@dataclass(eq=False)
class AtrophyCase(SceneCase):
    """The atrophy scene's case: transport, exposure, atrophy and the mechanics, walked in
    one stage per snapshot (:class:`AtrophyStage`); ``scene`` the
    :class:`~ngincompat.scenes.atrophy.scene.AtrophyScene` that built it."""

    scene: Any
    mesh: ngs.Mesh
    series: dict = field(default_factory=dict)
    snapshots: dict = field(default_factory=dict)
    #: The fields of :data:`FRAME_FIELDS` at the snapshot times
    #: (:class:`~ngincompat.workflow.frames.Frames`).
    frames: Frames = field(init=False)
    #: The incompatibility of the current growth (:meth:`_incompatibility_fields`).
    incompatibility: Incompatibility | None = field(default=None, init=False)

    def __post_init__(self) -> None:
        scene, mesh = self.scene, self.mesh
        X = ngs.CF((ngs.x, ngs.y, ngs.z))
        white = mesh.MaterialCF({"white": 1.0}, default=0.0)
        axon = X / (ngs.Norm(X) + 1e-12)
        D = diffusion_tensor(scene.d_ext, scene.d_axn * white, axon if scene.d_axn else None)
        centre = scene.seed_centre()
        if centre is None:
            c0 = ngs.CF(scene.c0)
        else:
            d = X - ngs.CF(centre)
            c0 = scene.c0 * ngs.exp(-ngs.InnerProduct(d, d) / (2 * scene.seed_radius ** 2))
        self.transport = FisherKPP(mesh, D, scene.alpha, c0)
        self.exposure = ngs.GridFunction(self.transport.fes, name="exposure")
        self.exposure_solved = ngs.GridFunction(self.transport.fes)
        self.ramp = ngs.Parameter(0.0)
        ramped = self.exposure_solved + self.ramp * (self.exposure - self.exposure_solved)
        laws = scene.laws()
        self.theta = mesh.MaterialCF({k: laws[k].theta(self.exposure, ngs.exp)
                                      for k in TISSUES})
        self.growth = IsotropicGrowth(mesh.MaterialCF({k: laws[k].theta(ramped, ngs.exp)
                                                       for k in TISSUES}))
        self.material = NeoHookean.by_region(mesh, scene.material_moduli())
        self.problem: GrowthMechanics | None = None
        self.volume0 = {k: ngs.Integrate(1.0, mesh, definedon=mesh.Materials(k))
                        for k in TISSUES}
        self.volume0["total"] = sum(self.volume0.values())
        self.vertices = np.array([v.point for v in mesh.vertices]).reshape(-1, 3)
        #: Centre and half-sizes of the body's bounding box: the sections pass through the
        #: centre, the profile starts there.
        low, high = bounding_box(mesh)
        self.centre, self.extent = (low + high) / 2, (high - low) / 2
        self.c_extremes = [self.transport.minimum(), self.transport.maximum()]
        self._record(0.0)
        self.frames = Frames.of(scene, mesh, self._frame_fields, FRAME_FIELDS)

    def stages(self) -> list["AtrophyStage"]:
        """One stage per snapshot time."""
        scene = self.scene
        ends = scene.snapshot_steps()
        starts = [0] + ends[:-1]
        dt = scene.t_end / scene.n_steps()
        return [AtrophyStage(f"t={e * dt:g}", self, s, e, dt)
                for s, e in zip(starts, ends, strict=True)]

    def advance(self, steps: int, dt: float) -> None:
        """``steps`` steps of transport and atrophy; the time series at every step."""
        for _ in range(steps):
            self.transport.step(dt)
            c = self.transport.c.vec.FV().NumPy()
            self.exposure.vec.FV().NumPy()[:] += exposure_increment(c, dt)
            self.c_extremes = [min(self.c_extremes[0], self.transport.minimum()),
                               max(self.c_extremes[1], self.transport.maximum())]
            self._record(self.transport.t)

    def _record(self, t: float) -> None:
        volumes = self.volumes(self.theta)
        row = {"t": t, "c_integral": self.transport.integral(),
               "c_min": self.transport.minimum(),
               **{f"{k}_volume_loss_theta": 1 - volumes[k] / self.volume0[k]
                  for k in volumes}}
        centre = self.scene.seed_centre()
        if centre is not None:
            reached = self.transport.c.vec.FV().NumPy() >= 0.5
            row["front_radius"] = parallel.maximum(self.mesh, np.max(np.linalg.norm(
                self.vertices[reached] - centre, axis=1), initial=0.0))
        for key, value in row.items():
            self.series.setdefault(key, []).append(value)

    def volumes(self, density: ngs.CoefficientFunction) -> dict[str, float]:
        """int density dV over each tissue and the whole body."""
        out = {k: ngs.Integrate(density, self.mesh, definedon=self.mesh.Materials(k),
                                order=2 * self.scene.order + 2) for k in TISSUES}
        out["total"] = sum(out.values())
        return out

    def equilibrium(self, progress: Progress, stage: str) -> SolverHistory:
        """Solve the mechanics with theta ramped from the last equilibrium to now."""
        if self.problem is None:
            self.problem = GrowthMechanics(self.mesh, self.growth, self.material,
                                           order=self.scene.order,
                                           formulation=self.scene.formulation,
                                           linear_solver=self.scene.linear_solver,
                                           coarse=self.scene.coarse)
        self.ramp.Set(0.0)
        options = NewtonOptions(steps=self.scene.steps, reuse_tangent=True,
                                linear_solver=self.scene.linear_solver)
        history = solve_growth(self.problem, self.ramp, options, 1.0, progress=progress,
                               stage=stage)
        self.exposure_solved.vec.data = self.exposure.vec
        J = ngs.Det(deformation_gradient(self.problem.u))
        volumes = self.volumes(J)
        row = {"t": self.transport.t,
               **{f"{k}_volume_loss": 1 - volumes[k] / self.volume0[k] for k in volumes}}
        for key, value in row.items():
            self.snapshots.setdefault(key, []).append(value)
        return history

    def solve(self, solution: Solution, progress: Progress,
              workdir: Path | None = None) -> None:
        solution.state = self
        stages = self.stages()
        progress.plan(stage.name for stage in stages)
        with config.task_manager():
            solve_stages(stages, progress, solution)

    def ndof(self, solution: Solution) -> int | None:
        """The mechanics' unknowns (None without mechanics)."""
        return None if self.problem is None else self.problem.ndof

    def keep(self, results: Results) -> None:
        """The series of the front and the snapshots' profiles."""
        results.profiles = {"series": {k: np.array(v) for k, v in self.series.items()}}
        if self.snapshots:
            results.profiles["snapshots"] = {k: np.array(v) for k, v in self.snapshots.items()}

    def measure(self, solution: Solution, progress: Progress) -> Results:
        """Volumes, incompatibility, residual stress, profile, sections and figures."""
        results = self.interrupted(solution)
        scene, metrics = self.scene, results.metrics
        with config.task_manager():
            with progress.phase("incompatibility"), timed(results.timings, "incompatibility"):
                fields, inc_metrics = self._incompatibility()
            metrics.update(inc_metrics)
            if "curvature" in scene.output_set():
                with progress.phase("curvature"), timed(results.timings, "curvature"):
                    metrics.update(self._curvature(fields))
            with progress.phase("stresses and profiles"), \
                    timed(results.timings, "postprocess"):
                metrics.update(self._transport_metrics())
                metrics.update(self._anatomy())
                if self.problem is not None and self.snapshots:
                    metrics.update(self._mechanics(fields))
                results.profiles["depth"] = self._depth(fields, metrics)
                if "u" in fields:
                    results.profiles["surface"] = self._surface(fields)
                results.profiles["line"] = self._line(fields, metrics)
                results.profiles["sections"] = self._sections(fields)
        results.fields = fields
        if results.converged:
            self.frames.take(scene.t_end, fields)      # the end's frame: the fields just made
            results.frames = list(self.frames)
        results.figures = figures(scene, self.problem is not None and bool(self.snapshots))
        if "curvature" in scene.output_set():
            curvature_report.report(scene, results, "R", {"|b| (largest plane)": "burgers"})
        return results

    def _frame_fields(self) -> dict[str, Any]:
        """The fields of the current state that a frame keeps: the incompatibility's and,
        once solved, the mechanics'."""
        fields = self._incompatibility_fields()
        if self.problem is not None:
            fields.update(self._mechanics_fields())
        return fields

    def _incompatibility_fields(self) -> dict[str, Any]:
        """The incompatibility's fields on the coordinate planes (projected path:
        :class:`~ngincompat.incompatibility.measure.Incompatibility`), beside the
        transport's."""
        self.incompatibility = Incompatibility.projected(
            IsotropicGrowth(self.theta).Fg, self.mesh, self.scene.g_order, PLANES)
        return {"c": self.transport.c, "theta": self.theta, "exposure": self.exposure,
                **self.incompatibility.fields()}

    def _incompatibility(self) -> tuple[dict[str, Any], dict[str, float]]:
        """The fields of :meth:`_incompatibility_fields`, the largest |b| and ||G||_L2."""
        fields = self._incompatibility_fields()
        return fields, {"burgers_max": sampling.maximum(fields["|b|"], self.mesh),
                        "G_norm_L2": self.incompatibility.norm_L2(  # type: ignore[union-attr]
                            self.mesh, 2 * self.scene.g_order)}

    def _curvature(self, fields: dict[str, Any]) -> dict[str, float]:
        """The curvature of Cg (:mod:`ngincompat.incompatibility.curvature`): theta is computed on
        the mesh, so
        the Regge path on the continuous interpolant of Fg that G comes from; adds the fields,
        returns the metrics."""
        # self.incompatibility: set by _incompatibility_fields, which measure calls first
        extra, metrics = cv.measure_growth(
            self.incompatibility.Fg_h, self.mesh,  # type: ignore[union-attr]
            self.incompatibility.G, exact=False)  # type: ignore[union-attr]
        fields.update(extra)
        return metrics

    def _anatomy(self) -> dict[str, float]:
        """The tissues' volumes; on the fsaverage brain also their deviation from the volumes
        the surfaces enclose (divergence theorem) and the elements across the cortex."""
        out = {"gray_volume": self.volume0["gray"], "white_volume": self.volume0["white"]}
        scene = self.scene
        if scene.geometry != "fsaverage":
            return out
        pial, white, triangles = fsaverage.surfaces(scene.hemisphere, scene.ico)
        across = resolution.elements_across(  # type: ignore[misc]  # four arrays, then material
            self.mesh, *fsaverage.cortex_columns(scene.hemisphere, scene.ico), material="gray")
        white, _ = fsaverage.cortex(pial, white, triangles, fsaverage.MIN_THICKNESS)
        inner = fsaverage.enclosed_volume(white, triangles)
        gray = fsaverage.enclosed_volume(pial, triangles) - inner
        out["volume_surface_deviation"] = max(abs(out["gray_volume"] / gray - 1),
                                              abs(out["white_volume"] / inner - 1))
        out["cortex_elements_across_min"] = float(np.nanmin(across))
        out["cortex_elements_across_median"] = float(np.nanmedian(across))
        return out

    def _transport_metrics(self) -> dict[str, float]:
        last = {k: v[-1] for k, v in self.series.items()}
        metrics = {"c_min": self.c_extremes[0], "c_max": self.c_extremes[1],
                   "c_integral": last["c_integral"],
                   "volume_loss_theta": last["total_volume_loss_theta"],
                   "theta_min_reached": -sampling.maximum(-self.theta, self.mesh)}
        if "front_radius" in last:
            metrics["front_radius"] = last["front_radius"]
        return metrics

    def _mechanics_fields(self) -> dict[str, Any]:
        """u, J, Je and the max principal Cauchy stress of the last equilibrium."""
        problem: GrowthMechanics = self.problem  # type: ignore[assignment]  # set once solved
        sigma = postprocess.stresses(problem.energy_density, problem.u)["sigma"]
        J = ngs.Det(deformation_gradient(problem.u))
        return {"u": problem.u, "J": J, "Je": J / self.theta,
                "sigma_max_principal": postprocess.largest_principal_value(sigma)}

    def _mechanics(self, fields: dict[str, Any]) -> dict[str, float]:
        """Stresses and volumes of the last equilibrium; adds the fields, returns metrics."""
        mesh, problem = self.mesh, self.problem
        stress = postprocess.stresses(problem.energy_density,  # type: ignore[union-attr]
                                      problem.u)  # type: ignore[union-attr]
        F = deformation_gradient(problem.u)  # type: ignore[union-attr]
        J = ngs.Det(F)
        sigma = stress["sigma"]
        fields.update(self._mechanics_fields())
        order = 2 * self.scene.order + 2
        total = ngs.Integrate(stress["P"] * F.trans, mesh, order=order)
        size = ngs.Integrate(ngs.Norm(sigma) * J, mesh, order=order)
        volumes_J = self.volumes(J)
        volumes_theta = self.volumes(self.theta)
        return {
            "volume_loss": self.snapshots["total_volume_loss"][-1],
            "gray_volume_loss": self.snapshots["gray_volume_loss"][-1],
            "white_volume_loss": self.snapshots["white_volume_loss"][-1],
            "volume_bookkeeping_error":
                abs(volumes_J["total"] - volumes_theta["total"]) / self.volume0["total"],
            "Je_deviation_max": max(sampling.maximum(J / self.theta - 1, mesh),
                                    sampling.maximum(1 - J / self.theta, mesh)),
            "Je_deviation_volume_fraction": ngs.Integrate(
                ngs.IfPos(ngs.Norm(J / self.theta - 1) - JE_DEVIATION, 1.0, 0.0), mesh,
                order=order) / self.volume0["total"],
            "max_principal_stress": sampling.maximum(fields["sigma_max_principal"], mesh),
            "strain_energy": problem.strain_energy(),  # type: ignore[union-attr]
            "equilibrium_residual_rel": relative(float(np.linalg.norm(np.array(total))),
                                                  size),
        }

    def _depth(self, fields: dict[str, Any], metrics: dict[str, float]) -> dict[str, np.ndarray]:
        """The paper's finding (Fig. 5e): theta, |b| and the max principal stress averaged
        over bands of depth xi below the surface (:mod:`ngincompat.fem.depth`; 0 at the
        surface, 1 at the gray/white interface, 2 one mean cortical thickness T into the
        white matter); the share of int |b| dV within T of the interface, and of the
        volume; the mean stress in the gray band at the interface (7/8 <= xi < 1) over that
        in the band at the surface (0 <= xi < 1/8)."""
        mesh, order = self.mesh, 2 * self.scene.order
        xi, d_i, thickness = depth.depth_coordinate(mesh)
        edges = np.linspace(0.0, 2.0, 2 * DEPTH_BANDS + 1)
        cfs: dict[str, Any] = {k: fields[k] for k in ("theta", "|b|", "sigma_max_principal")
                               if k in fields}
        means, _ = depth.band_means(cfs, xi, edges, mesh, order)
        near = ngs.IfPos(thickness - d_i, 1.0, 0.0)
        metrics["cortex_thickness"] = thickness
        metrics["burgers_interface_fraction"] = (
            ngs.Integrate(near * fields["|b|"], mesh, order=order)
            / ngs.Integrate(fields["|b|"], mesh, order=order))
        metrics["interface_band_volume_fraction"] = (
            ngs.Integrate(near, mesh, order=order) / self.volume0["total"])
        stress = means.get("sigma_max_principal", np.full(DEPTH_BANDS, np.nan))
        interface, surface = stress[DEPTH_BANDS - 1], stress[0]
        if np.isfinite(interface) and np.isfinite(surface) and surface != 0:
            # (a mesh coarser than the cortex, 2 cm voxels, leaves bands empty)
            metrics["stress_interface_over_surface"] = float(interface / surface)
        return {"xi": (edges[:-1] + edges[1:]) / 2, **means}

    def _surface(self, fields: dict[str, Any]) -> dict[str, np.ndarray]:
        """c, theta, the max principal stress and u at the vertices of the outer surface,
        and its triangles (Fig. 5 a-c)."""
        mesh = self.mesh
        triangles: list | np.ndarray = []
        for el in mesh.Elements(ngs.BND):
            if el.mat == "surface":
                corners: list | np.ndarray = [v.nr for v in el.vertices]
                triangles += [corners[:3]] + ([[corners[0], corners[2], corners[3]]]
                                              if len(corners) == 4 else [])
        triangles = np.array(triangles, dtype=int).reshape(-1, 3)
        used, local = np.unique(triangles, return_inverse=True)
        points = self.vertices[used]
        keys = ("c", "theta", "sigma_max_principal", "u")
        values = [np.asarray(fields[k](mesh(*points.T))).reshape(len(points), -1)
                  if len(points) else np.empty((0, fields[k].dim)) for k in keys]
        # on a distributed mesh: every rank's triangles, a vertex shared by ranks once
        rows = parallel.gather_rows(mesh, np.column_stack([points, *values]))
        corners = parallel.gather_rows(mesh, points[local.reshape(-1, 3)].reshape(-1, 9))
        rows = rows[np.sort(np.unique(rows[:, :3], axis=0, return_index=True)[1])]
        index = {tuple(p): k for k, p in enumerate(rows[:, :3])}
        out = {"points": rows[:, :3],
               "triangles": np.array([index[tuple(p)] for p in corners.reshape(-1, 3)],
                                     dtype=int).reshape(-1, 3)}
        column = 3
        for key, v in zip(keys, values, strict=True):
            width = v.shape[1]
            part = rows[:, column:column + width]
            out[key] = part[:, 0] if width == 1 else part
            column += width
        return out

    def _line(self, fields: dict[str, Any], metrics: dict[str, float]) -> dict[str, np.ndarray]:
        """The profile from the centre along +X1 to the surface, with the depth of the
        largest |b| and stress below the surface (the last point of the line in the body)."""
        a = float(self.extent[0])
        basis = spherical_basis()
        sampled: dict[str, Any] = {
            "c": fields["c"], "theta": fields["theta"], "burgers": fields["|b|"],
            **{f"|b_{p}|": fields[f"|b_{p}|"] for p in PLANES},
            **{k: fields[k] for k in ("einstein_norm_g", "scalar_curvature") if k in fields}}
        if "u" in fields:
            sigma = postprocess.stresses(self.problem.energy_density,  # type: ignore[union-attr]
                                         self.problem.u)["sigma"]  # type: ignore[union-attr]
            sampled.update({
                "sigma_rr": postprocess.component(sigma, basis["r"]),
                "sigma_thetatheta": postprocess.component(sigma, basis["theta"]),
                "sigma_max_principal": fields["sigma_max_principal"]})
        centre = tuple(self.centre)
        s, values = postprocess.sample_line(self.mesh, sampled, centre,
                                            (centre[0] + a, *centre[1:]), n=401)
        line = {"R": s, **values}
        surface = s[np.flatnonzero(np.isfinite(values["c"]))[-1]]     # last point inside
        metrics["burgers_peak_depth"] = float(surface - s[np.nanargmax(values["burgers"])])
        if "sigma_max_principal" in values:
            metrics["stress_peak_depth"] = float(
                surface - s[np.nanargmax(values["sigma_max_principal"])])
        return line

    def _sections(self, fields: dict[str, Any], n: int = 121) -> dict[str, np.ndarray]:
        """theta, the max principal stress and, as the paper computes them "for each of the
        planes of interest" (Fig. 5d), |b| of the plane's own normal, b = G^T e_k (eq. 11),
        with b's components along the plane's two axes ("b_inplane", for its arrows) and
        along its normal ("b_normal"), on the planes X_k = const through the centre, k = 1,
        2, 3, sampled on n x n grids (NaN outside the mesh)."""
        axes = self.extent
        common: dict[str, Any] = {k: fields[k] for k in ("theta", "sigma_max_principal")
                                  if k in fields}
        basis = np.eye(3)
        out = {}
        for k, plane in enumerate(PLANES):
            i, j = [m for m in range(3) if m != k]
            u = np.linspace(-axes[i], axes[i], n)
            v = np.linspace(-axes[j], axes[j], n)
            out[f"{plane}_u"], out[f"{plane}_v"] = u, v
            b = fields[f"b_{plane}"]
            cfs = {**common, "|b|": fields[f"|b_{plane}|"],
                   "b_inplane": ngs.CF((b[i], b[j])), "b_normal": b[k]}
            sampled = postprocess.sample_plane(self.mesh, cfs, tuple(self.centre), basis[i],
                                               basis[j], u, v)
            out.update({f"{plane}_{key}": values for key, values in sampled.items()})
        return out


@dataclass(eq=False)
class AtrophyStage:
    """Transport and atrophy from step ``first`` to ``last``, then the equilibrium there."""

    name: str
    case: AtrophyCase
    first: int
    last: int
    dt: float

    def run(self, progress: Progress) -> SolverHistory:
        case = self.case
        case.advance(self.last - self.first, self.dt)
        history = (case.equilibrium(progress, self.name) if case.scene.mechanics
                   else SolverHistory(converged=True, t_reached=1.0))
        if history.converged and self.last < case.scene.n_steps():  # the end's: measure
            case.frames.take(self.last * self.dt)
        return history



def relative(value: float, scale: float) -> float:
    """``value / scale``; 0 for a body without stress (a seed too small for the mesh to see
    atrophies nothing: the residual and the stresses are both 0)."""
    if scale > 0:
        return value / scale
    return 0.0 if value == 0 else math.inf
