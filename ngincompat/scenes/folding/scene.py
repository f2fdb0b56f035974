"""The folding scene's parameters (section 3.7): the bilayer, its growth, the steps, the
contact and the release, with their presets and metrics."""

from dataclasses import dataclass

from geometries import bilayer, estimate
from ngincompat.errors import require
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import ConstantRateLaw, StrainDrivenLaw
from ngincompat.references.bifurcation import Bilayer
from ngincompat.scenes.base import (
    G_ORDER,
    LENGTH_FLOOR,
    MAXH,
    MODULUS_FLOOR,
    ORDER,
    RATE_FLOOR,
    TIME_FLOOR,
    Scene,
    check_time_steps,
    param,
)
from ngincompat.scenes.folding.case import FoldingCase
from ngincompat.scenes.metrics import INCOMPATIBILITY, MECHANICS, Metric, registry, select
from ngincompat.scenes.trust import Indicator

#: The axon fields of Fig. 7 (left to right), and "none": no axon growth.
AXONS = (*fields.AXONS, "none")


@dataclass(frozen=True)
class FoldingScene(Scene):
    """A 3 x 1 cm cortex-subcortex bilayer growing between fixed ends (section 3.7)."""

    name = "folding"
    summary = "section 3.7: cortical folding, a growing cortex on a subcortex with axon growth"
    variant = ("axons",)
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"; the
    # preview is the paper's bilayer to its 75 days, its subcortex coarse, its cortex two
    # elements thick (it does not crease) and its steps and records longer
    # (docs/measurements/folding.md, "The section", "Convergence at the paper's 75 days")
    presets = {"preview": dict(maxh=0.5, cortex_maxh=0.025, dt=10.0, onset_dt=5.0,
                               approach_dt=10.0, observe_dt=10.0),
               "paper": dict(maxh=0.1)}
    # far above what converged runs give (docs/measurements/folding.md, the release)
    indicators = (
        Indicator("equilibrium_residual", 1e-6, "the grown state is not an equilibrium: the "
                  "relaxation stopped short of it"),
        Indicator("release_reaction_rel", 1e-6, "the released body is not self-equilibrated: "
                  "its pins carry load"))
    metrics = registry(
        dict(
            onset_growth=Metric("the cortex growth theta_c at the onset of buckling: the "
                                "earliest zero crossing of the smallest eigenvalues of the "
                                "elastic tangent at frozen growth, interpolated linearly in "
                                "theta_c between the first step with a negative one and the "
                                "step before"),
            onset_wavelength=Metric("the wavelength of that onset's buckling mode along the top "
                                    "surface, twice the mean distance between the zero "
                                    "crossings of its u2 (reference length)", "length"),
            onset_time=Metric("the growth time of the onset, (onset_growth - 1) / cortex_rate",
                              "time"),
            fold_amplitude=Metric("half the peak-to-peak vertical displacement u2 along the top "
                                  "surface of the final grown equilibrium, before the release",
                                  "length"),
            sulci=Metric("the number of sulci of the final grown equilibrium: the troughs of u2 "
                         "along the top, with a hysteresis of a tenth of its peak-to-peak "
                         "height, one on a roller end counting one half"),
            sulcus_depth=Metric("the depth of the deepest of those sulci below the lower of "
                                "its two neighbouring crests of u2", "length"),
            t_reached=Metric("the growth time of the last converged growth step: t_end where "
                             "the run grew to its end", "time"),
            theta_c_reached=Metric("the cortex growth there, 1 + cortex_rate t_reached"),
            Je_min=Metric("the smallest elastic Jacobian Je = det F / theta over the "
                          "integration points and vertices, over the records of the growth and "
                          "the final grown and released states: positive where no element has "
                          "inverted"),
            self_contact_area=Metric("the reference length of the top line in self-contact "
                                     "(where it penetrates the other wall or an image, gap < 0) "
                                     "in the final grown state: the section's contact area",
                                     "length"),
            self_contact_penetration_max=Metric(
                "the largest penetration -gap of the top surface's self-contact at its "
                "integration points, over the records of the growth and the final grown and "
                "released states", "length"),
            burgers_interface_mean=Metric(
                "the mean |b| on the plane normal to e3 (eq. 11) over the band of one cortex "
                "thickness centred on the cortex-subcortex interface (reference X2), where "
                "Fig. 7b has it largest", "1/length"),
            theta_a_max=Metric("the largest axon growth theta_a (theta of the subcortex's "
                               "fiber growth, eqs. 23 and 45) over the section at the end")),
        select(["burgers_max"], INCOMPATIBILITY),
        dict(
            burgers_max_depth=Metric("the reference depth below the top surface (height - X2) "
                                     "of the point where |b| is largest", "length"),
            burgers_max_X1=Metric("the reference X1 of that point", "length"),
            equilibrium_residual=Metric("the residual without viscosity at the equilibrium "
                                        "found at t_end with the growth held, relative to that "
                                        "at the end of the viscous march"),
            equilibrium_eigenvalue=Metric(
                "the smallest eigenvalue omega of the elastic tangent at frozen growth, "
                "K w = omega M w with M the L2 mass matrix, at that equilibrium: not negative "
                "where it is stable", "stress/length^2")),
        select(["max_principal_stress"], MECHANICS),
        dict(
            max_principal_stress_released=Metric(
                "the largest principal Cauchy stress over the integration points and vertices "
                "after the release (supports removed, growth frozen): the residual stress of "
                "the incompatibility alone (Fig. 7c)", "stress"),
            top_curvature_released=Metric(
                "the signed curvature of the circle fitted to the deformed top line (X1 + u1, "
                "X2 + u2) over the central third of the length after the release: positive "
                "where the top bulges upward (section 3.7's bending of the top layer)",
                "1/length"),
            peak_tension_depth=Metric("the reference depth below the top surface where "
                                      "max_principal_stress is reached (the grown state on its "
                                      "supports)", "length"),
            peak_tension_depth_released=Metric(
                "the reference depth below the top surface where max_principal_stress_released "
                "is reached: below the interface where it exceeds cortex_thickness (Fig. 7c)",
                "length"),
            release_reaction_rel=Metric("the norm of the reactions of the rigid-body pins at "
                                        "the released equilibrium relative to the forces the "
                                        "removed supports carried: zero for a "
                                        "self-equilibrated body"),
            top_stretch_min=Metric("the smallest elastic stretch of the top surface along it, "
                                   "lambda_e = |F e1| / theta_c, over the records of the "
                                   "perfect branch and the march (a neo-Hookean surface "
                                   "creases below CREASE_STRETCH)"),
            strain_energy=Metric("the elastic energy per unit depth of the grown state on its "
                                 "supports, int Jg Psi dA over the reference section (Psi of "
                                 "eq. 36)", "stress length^2"),
            strain_energy_released=Metric("the elastic energy per unit depth after the release, "
                                          "int Jg Psi dA over the reference section",
                                          "stress length^2")))
    units = {"length": "cm", "stress": "kPa", "energy": "kPa cm^3 (mJ)", "time": "day"}

    order: int = ORDER(2, help="polynomial order of the displacement: 2 (across the cortex at "
                               "least quadratic; from order 3 the triangles have element-"
                               "internal dofs, which the tangent's eigenpairs leave out)")
    maxh: float = MAXH(0.15, help="mesh size in the subcortex")
    cortex_maxh: float = param(0.0125, "mesh size in the cortex and on the interface "
                                       "(>= 2 quadratic elements across the cortex; 4 by "
                                       "default, where the folds crease)", "length",
                               range=f"[{LENGTH_FLOOR:g}, 100]")
    top_refinement: float = param(1.0, "cortex_maxh / the mesh size on the top surface, "
                                       "graded to cortex_maxh below (where the folds "
                                       "crease); 1: not refined", range="[1, 100]")
    g_order: int = G_ORDER(3, help="order of the H1 space that Fg is projected into for "
                                   "Curl Fg")
    growth_order: int = param(1, "order of the (L2) growth field theta", range="[0, 5]")
    length: float = param(3.0, "length of the bilayer (X1)", "length",
                          range=f"[{LENGTH_FLOOR:g}, 100]")
    height: float = param(1.0, "height of the bilayer (X2)", "length",
                          range=f"[{LENGTH_FLOOR:g}, 100]")
    cortex_thickness: float = param(0.05, "thickness of the cortex", "length",
                                    range=f"[{LENGTH_FLOOR:g}, 100]")
    mu_white: float = param(1.0, "shear modulus of the subcortex (white matter)", "stress",
                            range=f"[{MODULUS_FLOOR:g}, 1e6]")
    mu_ratio: float = param(3.0, "mu_gray / mu_white", range="[1e-3, 1000]")
    lam_ratio: float = param(100.0, "lambda / mu in both layers (nearly incompressible; "
                                    "1e6: nu = 0.4999995)",
                             range="[1e-3, 1e6]")
    cortex_rate: float = param(0.008, "cortex growth rate: theta_c = 1 + cortex_rate t",
                               "1/time", range=f"[{RATE_FLOOR:g}, 10]")
    axon_rate: float = param(0.08, "G_axn of d theta_a/dt = G_axn <lambda_e - "
                                   "stretch_crit>", "1/time", range=f"[{RATE_FLOOR:g}, 100]")
    stretch_crit: float = param(1.0, "axon stretch lambda_e below which axons do not grow",
                                range="[0.1, 10]")
    axon_max: float = param(3.0, "saturation of axon growth (eq. 45, gamma = 0)",
                            range="(1, 10]")
    axons: str = param("curved", "axon field: " + ", ".join(AXONS), choices=AXONS)
    t_end: float = param(75.0, "end of growth (the paper's 75 days: theta_c = 1.6 with "
                               "cortex_rate read per day)", "time", range=f"[{TIME_FLOOR:g}, 1000]")
    dt: float = param(2.5, "first time step (adaptive: cut on failure, doubled on ease)",
                      "time", range=f"[{TIME_FLOOR:g}, 1000]")
    approach_dt: float = param(10.0, "largest time step on the perfect branch (at least "
                                     "onset_dt) until 2 onset_dt before the bifurcation "
                                     "analysis' onset", "time", range=f"[{TIME_FLOOR:g}, 1000]")
    onset_dt: float = param(1.25, "largest time step on the perfect branch (resolution of "
                                  "the onset)", "time", range=f"[{TIME_FLOOR:g}, 1000]")
    observe_dt: float = param(1.25, "growth time between the records of the viscous march "
                                    "(smallest eigenvalue, fold amplitude, top stretch); 0: "
                                    "every step", "time", range="[0, 1000]")
    imperfection: float = param(0.01, "amplitude of the first buckling mode added at the "
                                      "onset / cortex_thickness", range="[1e-6, 0.1]")
    buckle: bool = param(True, "past the onset, perturb by the buckling mode and follow the "
                               "folds to t_end (false: end at the onset)")
    release: bool = param(True, "at the end remove the supports but the rigid-motion pins "
                                "(growth frozen)")
    contact_penalty: float = param(1e4, "penalty kappa of the top surface's self-contact "
                                        "(pressure per penetration)", "stress/length",
                                   range="[1e-3, 1e8]")
    contact_width: float = param(0.0005, "penetration over which the contact penalty's ramp "
                                         "is rounded", "length", range="[0, 1]")
    viscosity: float = param(100.0, "viscous regularisation after the onset: eta / mu_white "
                                   "(eta in stress x time / length^2)", "time/length^2",
                             range="[1e-3, 1e6]")

    def __post_init__(self) -> None:
        super().__post_init__()
        require(self.order == 2, "order", self.order, "2 (quadratic elements across the "
                "cortex; from order 3 the triangles have element-internal dofs, which the "
                "tangent's eigenpairs leave out)")
        require(self.cortex_thickness < self.height, "cortex_thickness",
                self.cortex_thickness, f"in (0, height = {self.height:g})")
        # a section shorter than its cortex is thick is a column, not a bilayer: its folds
        # (half a wavelength at most the length) would be shorter than the layer that folds
        require(self.length >= self.cortex_thickness, "length", self.length,
                f">= cortex_thickness = {self.cortex_thickness:g} (a section shorter than its "
                "cortex is thick has no room for a fold)")
        require(self.cortex_maxh <= self.maxh, "cortex_maxh", self.cortex_maxh,
                f"in (0, maxh = {self.maxh:g}]")
        require(self.cortex_maxh <= self.cortex_thickness / 2, "cortex_maxh",
                self.cortex_maxh, f"<= cortex_thickness / 2 = {self.cortex_thickness / 2:g} "
                "(two quadratic elements across the cortex)")
        for step in ("dt", "approach_dt", "onset_dt"):     # observe_dt = 0: every step
            check_time_steps("t_end", self.t_end, step, getattr(self, step))
        self.axon_law()

    def axon_law(self) -> ConstantRateLaw | StrainDrivenLaw:
        """The subcortex's law: stretch-driven (eq. 45, gamma = 0) or, without axons, none."""
        if self.axons == "none":
            return ConstantRateLaw(0.0)
        return StrainDrivenLaw(tau=1.0 / self.axon_rate, theta_max=self.axon_max, gamma=0.0,
                               theta_crit=self.stretch_crit)

    @property
    def top_maxh(self) -> float:
        """The mesh size on the top surface, cortex_maxh / top_refinement."""
        return self.cortex_maxh / self.top_refinement

    @property
    def mu_gray(self) -> float:
        return self.mu_ratio * self.mu_white

    def bifurcation_bilayer(self) -> Bilayer:
        """The same bilayer for the independent linear bifurcation analysis
        (:mod:`ngincompat.references.bifurcation`)."""
        lam = self.lam_ratio
        return Bilayer(self.height, self.cortex_thickness, self.mu_gray, lam * self.mu_gray,
                       self.mu_white, lam * self.mu_white)

    def mesh_estimate(self) -> tuple[float, str]:
        return (estimate.bilayer_elements(length=self.length, height=self.height,
                                          cortex=self.cortex_thickness,
                                          maxh=self.maxh, cortex_maxh=self.cortex_maxh,
                                          top_maxh=self.top_maxh),
                "triangle")

    def build(self) -> FoldingCase:
        mesh = bilayer(length=self.length, height=self.height,
                       cortex=self.cortex_thickness, maxh=self.maxh,
                       cortex_maxh=self.cortex_maxh, top_maxh=self.top_maxh)
        return FoldingCase(self, mesh)

