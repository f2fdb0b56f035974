"""The atrophy scene's parameters (section 3.5): the brain, the transport, the atrophy and
the mechanics, with their presets, metrics and checks of trust."""

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import ngsolve as ngs
import numpy as np

from geometries import brain, brain_geometry, estimate
from geometries import fsaverage_brain as fsaverage
from geometries.voxel_brain import ELEMENTS, from_nifti, mni152, mni152_elements
from ngincompat import parallel
from ngincompat.errors import ParameterError, require
from ngincompat.fem.problem import check_formulation
from ngincompat.mechanics.atrophy import AtrophyLaw
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.scenes.atrophy.case import JE_DEVIATION, AtrophyCase
from ngincompat.scenes.atrophy.tissues import TISSUES, bounding_box
from ngincompat.scenes.base import (
    COARSE,
    G_ORDER,
    LENGTH_FLOOR,
    LINEAR_SOLVER,
    MAX_STEPS,
    MAXH,
    ORDER,
    TIME_FLOOR,
    Scene,
    check_time_steps,
    param,
)
from ngincompat.scenes.material import MU, NU
from ngincompat.scenes.metrics import (
    CURVATURE,
    INCOMPATIBILITY,
    MECHANICS,
    Metric,
    registry,
    select,
)
from ngincompat.scenes.trust import Indicator
from ngincompat.workflow.results import Results

GEOMETRIES = ("idealized", "mni152", "fsaverage")
#: The brains in MNI coordinates, where a named seed lies where its name says.
ANATOMICAL = ("mni152", "fsaverage")
#: Named seeds: MNI coordinates [mm] of the left hemisphere (x mirrored for the right).
#: entorhinal: the anterior parahippocampal gyrus of the medial temporal lobe, where tau
#: tangles appear first (Braak & Braak, Acta Neuropathol 82 (1991) 239, stage I-II) and
#: where Weickenmeier et al. (J Mech Phys Solids 124 (2019) 264) seed tau; the coordinates
#: are an estimate read off the anatomy, not a published centroid.
NAMED_SEEDS = {"entorhinal": (-25.0, -10.0, -30.0)}
#: The default seed of the idealized brain (its basal pole) [cm].
IDEALIZED_SEED = (0.0, 0.0, -5.0)
#: The cortex is resolved with at least this many elements across its thickness (median).
CORTEX_ELEMENTS_ACROSS = 2
#: Endings of a user's own brain: a NIfTI label image (1 gray, 2 white) or a Netgen mesh
#: with materials gray and white.
USER_FILES = (".nii", ".nii.gz", ".vol", ".vol.gz")



@dataclass(frozen=True)
class AtrophyScene(Scene):
    """Brain atrophy driven by the spreading of misfolded protein (section 3.5)."""

    name = "atrophy"
    distributed = True
    summary = ("section 3.5: misfolded protein spreads (Fisher-KPP) and shrinks gray matter "
               "faster than white")
    units = {"length": "cm", "stress": "kPa", "energy": "mJ", "time": "yr"}
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(snapshots=1), "paper": dict(maxh=0.7, dt=0.1)}
    metrics = registry(
        dict(
            volume_loss=Metric("the brain's volume loss at the last equilibrium, 1 - int J dV "
                               "/ V0 over the body (V0 its reference volume)"),
            gray_volume_loss=Metric("the same over the gray matter, 1 - int J dV / V0 over "
                                    "gray (section 3.5: it shrinks faster than white)"),
            white_volume_loss=Metric("the same over the white matter, 1 - int J dV / V0 over "
                                     "white"),
            volume_loss_theta=Metric("the volume loss the growth prescribes at t_end, "
                                     "1 - int theta dV / V0 over the body, without the "
                                     "mechanics"),
            volume_bookkeeping_error=Metric("the difference between int J dV and int theta dV "
                                            "over the body at the last equilibrium, relative "
                                            "to the reference volume"),
            Je_deviation_max=Metric("the largest |Je - 1|, Je = J / theta, over the integration "
                                    "points and vertices at the last equilibrium: the elastic "
                                    "volume change, small in a nearly incompressible tissue"),
            Je_deviation_volume_fraction=Metric(
                "the share of the reference volume where |Je - 1| exceeds JE_DEVIATION "
                "(ngincompat.scenes.atrophy.case) at the last equilibrium")),
        select(["burgers_max"], INCOMPATIBILITY),
        dict(
            burgers_peak_depth=Metric("the depth below the outer surface of the largest |b| "
                                      "(of the planes normal to e1, e2, e3) along the line "
                                      "from the centre of the bounding box along +X1 (Fig. 5d)",
                                      "length")),
        select(["max_principal_stress"], MECHANICS),
        dict(
            stress_peak_depth=Metric("the depth below the outer surface of the largest maximum "
                                     "principal Cauchy stress along that line (Fig. 5e)",
                                     "length")),
        select(["strain_energy"], MECHANICS),
        dict(
            equilibrium_residual_rel=Metric(
                "the norm of int P F^T dV, the integral of the Cauchy stress over the deformed "
                "brain, relative to int |sigma| J dV: zero for a traction-free body in "
                "equilibrium"),
            c_min=Metric("the smallest nodal concentration c of misfolded protein over the "
                         "run, the initial state included"),
            c_max=Metric("the largest nodal concentration c over the run, the initial state "
                         "included"),
            c_integral=Metric("the amount of misfolded protein int c dV (lumped mass) at t_end",
                              "length^3"),
            front_radius=Metric("the largest distance from the seed's centre of a mesh vertex "
                                "where c >= 1/2 at t_end (a seed with a centre only)",
                                "length"),
            theta_min_reached=Metric("the smallest volume ratio theta (Fg = theta^(1/3) I, eq. "
                                     "13) over the body at t_end")),
        select(["G_norm_L2"], INCOMPATIBILITY),
        CURVATURE,
        dict(
            gray_volume=Metric("the reference volume of the gray matter", "length^3"),
            white_volume=Metric("the reference volume of the white matter", "length^3"),
            volume_surface_deviation=Metric(
                "the larger relative difference of the gray and the white matter's mesh "
                "volumes from the volumes the surfaces enclose, between the pial and the white "
                "surface and inside the white one (divergence theorem; fsaverage only)"),
            cortex_elements_across_min=Metric(
                "the smallest number of elements across the cortex over the columns between "
                "white and pial triangles off the medial wall (ngincompat.fem.resolution; "
                "fsaverage only)"),
            cortex_elements_across_median=Metric("the median of that number over the columns "
                                                 "(fsaverage only)"),
            cortex_thickness=Metric("the mean cortical thickness T: the gray matter's volume "
                                    "over the mean of the outer surface's and the gray/white "
                                    "interface's areas (reference)", "length"),
            burgers_interface_fraction=Metric(
                "the share of int |b| dV within T of the gray/white interface, on either side "
                "(Fig. 5d: |b| concentrated at the interface)"),
            interface_band_volume_fraction=Metric(
                "the share of the reference volume within T of the interface: "
                "burgers_interface_fraction for a uniform |b|"),
            stress_interface_over_surface=Metric(
                "the mean maximum principal stress in the gray band at the interface "
                "(7/8 <= xi < 1, xi the depth in local cortical thicknesses) over that in the "
                "band at the outer surface (0 <= xi < 1/8) (Fig. 5e)")))
    #: An unstable mixed pair left a residual far above the limit, the stable one round-off
    #: (``docs/measurements/mixed.md``, "What it changed in the atrophy scene"). (|Je - 1|:
    #: trust.)
    indicators = (
        Indicator("equilibrium_residual_rel", 1e-6, "the equilibrium is not met: refine, or "
                  "use formulation=mixed"),
    )

    order: int = ORDER(2, help="polynomial order of the displacement (>= 2 for mixed)")
    maxh: float = MAXH(1.0, help="mesh size (the voxel edge of mni152 and NIfTI brains)")
    g_order: int = G_ORDER(2, help="order of the H1 space that Fg is projected into for "
                                   "Curl Fg")
    geometry: str = param("idealized", "brain: idealized (ellipsoid), fsaverage (a hemisphere "
                          "from the pial and white surfaces, needs nilearn), mni152 (MNI "
                          "ICBM152 template, needs nilearn), or a file: NIfTI labels (1 gray, "
                          "2 white) or a Netgen mesh (materials gray, white)")
    elements: str = param("hex", "elements of a voxel brain (mni152, NIfTI): hex, or tet (six "
                          "per voxel, as the curvature output needs)", choices=ELEMENTS)
    semi_axes: tuple[float, float, float] = param(
        (8.5, 7.0, 6.0), "semi-axes of the idealized brain along e1, e2, e3", "length",
        range=f"[{LENGTH_FLOOR:g}, 100]")
    gray_thickness: float = param(0.3, "thickness of the gray-matter shell", "length",
                                  range=f"[{LENGTH_FLOOR:g}, 10]")
    d_ext: float = param(0.015, "extracellular (isotropic) diffusivity", "length^2/time",
                         range="[0, 100]")
    d_axn: float = param(0.0, "axonal diffusivity added along radial axons in white matter",
                         "length^2/time", range="[0, 100]")
    alpha: float = param(0.6, "conversion rate of misfolded protein", "1/time", range="[0, 100]")
    seed: Literal["uniform", "entorhinal"] | tuple[float, float, float] = param(
        IDEALIZED_SEED, "seed: uniform, entorhinal (cortex of the medial temporal lobe, on "
        "fsaverage its nearest pial vertex), or its centre X,Y,Z (in or on the body); the "
        "default is entorhinal on the anatomical brains (mni152, fsaverage)", "length",
        range="[-100, 100]")
    hemisphere: str = param("left", "hemisphere of the fsaverage brain and of a named seed",
                            choices=fsaverage.HEMISPHERES)
    ico: int = param(4, "icosahedral subdivision of the fsaverage surfaces (4: 2562, 5: 10242 "
                     "vertices)", range="[4, 5]")
    cortex_layers: int = param(2, "layers of prisms (3 tetrahedra each) across the cortex of "
                               "the fsaverage brain; 0: Netgen fills it from the surfaces",
                               range="[0, 8]")
    seed_radius: float = param(1.0, "radius s of the Gaussian seed", "length",
                               range=f"[{LENGTH_FLOOR:g}, 100]")
    c0: float = param(0.1, "concentration at the seed's centre (or everywhere if uniform)",
                      range="(0, 1]")
    rate_gray: float = param(0.03, "initial rate of volume loss of gray matter at c = 1",
                             "1/time", range="[0, 10]")
    rate_white: float = param(0.001, "initial rate of volume loss of white matter at c = 1",
                              "1/time", range="[0, 10]")
    theta_min: float = param(0.7, "smallest volume ratio theta (largest loss 1 - theta_min)",
                             range="(0, 1)")
    t_end: float = param(40.0, "duration (at most a lifetime)", "time",
                         range=f"[{TIME_FLOOR:g}, 150]")
    dt: float = param(0.2, "time step of transport and atrophy", "time",
                      range=f"[{TIME_FLOOR:g}, 150]")
    snapshots: int = param(4, "equilibria solved at this many equally spaced times",
                           range=f"[1, {MAX_STEPS}]")
    times: tuple[float, ...] = param((), "times of the equilibria and of the frames of "
                                     "fields.pvd instead: comma list in (0, t_end] (t_end is "
                                     "always one)", "time",
                                     range=f"[{TIME_FLOOR:g}, 150]")
    mu_gray: float = MU(1.0, help="shear modulus of gray matter")
    mu_white: float = MU(1.0, help="shear modulus of white matter")
    nu: float = NU(0.49)                # both tissues
    formulation: Literal["mixed", "displacement"] = param(
        "mixed", "mixed (pressure against volumetric locking, on Je) or displacement")
    linear_solver: str = LINEAR_SOLVER("auto")
    coarse: str = COARSE("edges")

    def trust(self, results: Results) -> list[str]:
        """The elastic volume change |Je - 1| = |J / theta - 1| above :data:`JE_DEVIATION`
        (nu = 0.49 allows about 1e-2), with the share of the volume where it is: elements
        that do not resolve the tissues' mismatch, or poorly shaped ones, whose stress and
        |b| the maxima may report. A cortex with fewer than :data:`CORTEX_ELEMENTS_ACROSS`
        elements across its thickness (median) does not resolve the gray/white mismatch it
        carries."""
        metrics, found = results.metrics, []
        deviation = metrics.get("Je_deviation_max")
        share = metrics.get("Je_deviation_volume_fraction")
        if deviation is not None and deviation > JE_DEVIATION:
            where = "" if share is None else f" over a volume fraction of {share:.2g}"
            found.append(f"Je_deviation_max = {deviation:.3g} > {JE_DEVIATION:g}{where}: the "
                         "elastic volume change is far from what nu allows there (an "
                         "unresolved gray matter or poorly shaped elements; the maxima of "
                         "stress and |b| may sit there): refine (smaller maxh, more "
                         "cortex_layers on the fsaverage brain)")
        across = metrics.get("cortex_elements_across_median")
        if across is not None and across < CORTEX_ELEMENTS_ACROSS:
            found.append(f"cortex_elements_across_median = {across:g} < "
                         f"{CORTEX_ELEMENTS_ACROSS}: the cortex is under-resolved; the stress "
                         "and |b| at the gray/white interface are not converged: refine (more "
                         "cortex_layers on the fsaverage brain, a smaller maxh or "
                         "gray_thickness / maxh >= 2 on the idealized one)")
        return found

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.geometry in ANATOMICAL and self.seed == IDEALIZED_SEED:
            object.__setattr__(self, "seed", "entorhinal")     # the default, outside them
        require(self.geometry in GEOMETRIES or self.geometry.endswith(USER_FILES), "geometry",
                self.geometry, f"{', '.join(GEOMETRIES)} or a file ending in "
                f"{', '.join(USER_FILES)}")
        axes = self.axes()
        require(self.gray_thickness < min(axes) / 2, "gray_thickness",
                self.gray_thickness, f"in (0, {min(axes) / 2:g}) (half the smallest semi-axis)")
        require(self.seed not in NAMED_SEEDS or self.geometry != "idealized", "seed",
                self.seed, "uniform or X,Y,Z on the idealized brain (named seeds need an "
                "anatomical one: geometry = fsaverage, mni152)")
        centre = self.seed_centre()
        if centre is not None and self.geometry == "idealized":
            inside = sum((x / a) ** 2 for x, a in zip(centre, axes, strict=True))
            require(inside <= 1 + 1e-9, "seed", self.seed,
                    "uniform, or X,Y,Z inside or on the body "
                    f"((X/{axes[0]:g})^2 + (Y/{axes[1]:g})^2 + (Z/{axes[2]:g})^2 <= 1)")
        require(self.dt <= self.t_end, "dt", self.dt, f"in (0, t_end = {self.t_end:g}]")
        check_time_steps("t_end", self.t_end, "dt", self.dt)
        require(self.snapshots <= self.n_steps(), "snapshots", self.snapshots,
                f"an integer in [1, {self.n_steps()}] (the number of time steps)")
        self.snapshot_steps()
        for law in self.laws().values():
            law.check_step(self.t_end / self.n_steps())
        self.material_moduli()
        check_formulation(NeoHookean.from_nu(self.mu_gray, self.nu), self.formulation,
                          self.order)

    def axes(self) -> tuple[float, float, float]:
        """The semi-axes as three floats."""
        return self.semi_axes

    def seed_centre(self) -> tuple[float, ...] | None:
        """The seed's centre, or None for a uniform seed (a named one in the brain's
        coordinates: :func:`geometries.fsaverage_brain.from_mni`)."""
        if self.seed == "uniform":
            return None
        if self.seed in NAMED_SEEDS:
            x, y, z = NAMED_SEEDS[self.seed]
            point = fsaverage.from_mni((-x if self.hemisphere == "right" else x, y, z))
            if self.geometry == "fsaverage":     # on the cortex: the nearest pial vertex
                pial = fsaverage.surfaces(self.hemisphere, self.ico)[0]
                point = pial[np.argmin(np.linalg.norm(pial - point, axis=1))]
            return tuple(float(v) for v in point)
        return self.seed  # type: ignore[return-value]  # X,Y,Z: the words returned above

    def n_steps(self) -> int:
        """Number of equal time steps, of length t_end / n <= dt."""
        return max(1, int(np.ceil(self.t_end / self.dt - 1e-9)))

    def snapshot_steps(self) -> list[int]:
        """The steps (counted from 0) after which the equilibrium is solved and a frame of the
        time series taken: ``times`` rounded to the nearest step, else ``snapshots`` equally
        spaced ones; the last step always."""
        n = self.n_steps()
        if not self.times:
            return [round(k * n / self.snapshots) for k in range(1, self.snapshots + 1)]
        allowed = f"a comma list of times in (0, t_end = {self.t_end:g}]"
        require(all(0 < t <= self.t_end + 1e-9 for t in self.times), "times", self.times,
                allowed)
        return sorted({max(1, round(t / self.t_end * n)) for t in self.times} | {n})

    def laws(self) -> dict[str, AtrophyLaw]:
        """The atrophy law of each tissue."""
        return {"gray": AtrophyLaw(self.rate_gray, self.theta_min, "rate_gray"),
                "white": AtrophyLaw(self.rate_white, self.theta_min, "rate_white")}

    def material_moduli(self) -> dict[str, tuple[float, float]]:
        """tissue -> (mu, nu), checked."""
        moduli = {"gray": (self.mu_gray, self.nu), "white": (self.mu_white, self.nu)}
        for mu, nu in moduli.values():
            NeoHookean.from_nu(mu, nu)
        return moduli

    def mesh_estimate(self) -> tuple[float, str] | None:
        # a user's voxel brain has at most the voxels of its image; fsaverage's size is set
        # by ico and cortex_layers
        if self.geometry == "mni152":
            return mni152_elements(self.maxh, self.elements), self.elements
        if self.geometry != "idealized":
            return None
        return estimate.brain_elements(semi_axes=self.axes(), maxh=self.maxh), "tet"

    def build(self) -> AtrophyCase:
        mesh = self.distributed_mesh()
        missing = set(TISSUES) - set(mesh.GetMaterials())
        if missing:
            raise ParameterError(f"geometry = {self.geometry}: the brain mesh lacks the "
                                 f"materials {', '.join(sorted(missing))}")
        centre = self.seed_centre()
        if centre is not None and parallel.maximum(mesh, mesh(*centre).nr) < 0:
            low, high = bounding_box(mesh)
            raise ParameterError(
                f"seed = {self.seed} is outside the body: allowed uniform, or X,Y,Z inside "
                f"it (bounding box {np.round(low, 2).tolist()} to "
                f"{np.round(high, 2).tolist()})")
        if "curvature" in self.output_set() and parallel.total(mesh, sum(
                el.type != ngs.ET.TET for el in mesh.Elements(ngs.VOL))):
            raise ParameterError(f"outputs = {self.outputs}: the curvature of the growth metric "
                                 f"(Regge elements) needs a tetrahedral mesh; geometry = "
                                 f"{self.geometry} is meshed with hexahedra (a voxel brain "
                                 f"takes --set elements=tet)")
        return AtrophyCase(self, mesh)

    def distributed_mesh(self) -> ngs.Mesh:
        """The brain of :meth:`mesh`, distributed over the ranks of an MPI run
        (:mod:`ngincompat.parallel`; the ellipsoid curved on every rank)."""
        if parallel.world() is None:
            return self.mesh()
        if self.geometry == "idealized":
            return parallel.distribute_geometry(
                brain_geometry(self.axes(), self.gray_thickness), self.maxh, self.order)
        return parallel.distribute(self.mesh)

    def mesh(self) -> ngs.Mesh:
        """The brain: the ellipsoid, the MNI152 template, or the user's file (cm)."""
        if self.geometry == "idealized":
            return brain(semi_axes=self.axes(), gray=self.gray_thickness, maxh=self.maxh,
                         curve_order=self.order)
        if self.geometry == "mni152":
            return mni152(self.maxh, self.elements)
        if self.geometry == "fsaverage":
            return fsaverage.fsaverage(self.hemisphere, self.ico, self.cortex_layers,
                                       maxh=self.maxh)
        if self.geometry.endswith((".nii", ".nii.gz")):
            return from_nifti(self.geometry, self.maxh, self.elements)
        if not Path(self.geometry).is_file():
            raise ParameterError(f"geometry = {self.geometry}: no such file")
        try:
            return ngs.Mesh(self.geometry)
        except Exception as err:   # Netgen raises its own kinds for unreadable files
            raise ParameterError(f"geometry = {self.geometry}: not a readable Netgen mesh "
                                 f"({err})") from None

