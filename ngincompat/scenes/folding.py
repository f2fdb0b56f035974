"""Cortical folding (section 3.7, Fig. 7): a growing cortex buckles on a subcortex whose axons
grow when stretched; then the constraints are released.

Axes: the paper's. The paper's slab is one element thick, a two-dimensional model: a body
in plane strain, whose fields do not depend on the out-of-plane X3 and whose u3 is zero. It
is solved on its section (:func:`geometries.bilayer`, triangles): X1 along the 3 cm length,
X2 vertical, the displacement (u1, u2), the tensors three-dimensional with F33 = 1
(:func:`~ngincompat.mechanics.kinematics.displacement_gradient`). Energies, forces and
lengths of contact are per unit length out of plane.

Growth is fiber growth, eq. (23), Fg = I + (theta - 1) f0 (x) f0, with

* in the cortex f0 = e1 and theta_c = 1 + r_c t, prescribed (not mechanically coupled);
* in the subcortex f0 the axon field (curved outward, concentric, straight = normal to the
  interface, or none) and stretch-driven growth, eq. (45) with gamma = 0:
  d theta_a / dt = G_axn <lambda_e - lambda_crit>, lambda = |F f0|, lambda_e = lambda / theta_a,

both in one :class:`~ngincompat.fem.coupled.CoupledProblem` (implicit Euler at the integration
points with the consistent tangent), the cortex through a constant-rate law. Both layers are
neo-Hookean (eq. 36) with lambda / mu = ``lam_ratio`` (100 by default: nearly incompressible,
as the bifurcation oracle :mod:`ngincompat.references.bifurcation` assumes) and mu_cortex /
mu_subcortex =
``mu_ratio`` = 3.

Boundary conditions while growing: u1 = 0 at both ends, u2 = 0 at the bottom. Stages:

1. **perfect**: the perfect bilayer grows on its flat branch; after every step the smallest
   eigenvalues of the elastic tangent (:mod:`ngincompat.fem.buckling`) are computed. At the
   first step with a negative one the bilayer has buckled: ``onset_growth`` (theta_c where
   the first of the modes negative there crossed zero, interpolated) and
   ``onset_wavelength`` (that mode's, along the top surface, reference length) are
   measured, and the stage ends. With ``buckle`` false the run ends there, without stages
   2 to 4 (the onset alone, for a refinement study). Only the steps near the onset need to
   be short (``onset_dt``); before them (stage ``approach``) they may grow to
   ``approach_dt``: the short steps start 2 ``onset_dt`` before the onset that the
   bifurcation analysis (:mod:`ngincompat.references.bifurcation`) predicts, which so places the
   steps
   but not the onset, still found where the tangent's eigenvalue crosses zero.
2. **buckling**: the state of that step (the first with a negative eigenvalue) is perturbed
   by the onset's buckling mode, scaled so that the top surface moves by ``imperfection`` x
   ``cortex_thickness`` at most (a perturbation of the displacement, not of the body: the
   flat state is unstable there, so it grows by itself), and growth goes on to ``t_end`` in
   adaptive steps with a viscous regularisation, eta / (2 dt) int |u - u_n|^2 dV
   (:class:`~ngincompat.fem.terms.ViscousRegularisation`), eta = ``viscosity`` x
   ``mu_white``. An unstable mode (eigenvalue omega < 0) then grows at the rate |omega| / eta;
   implicit Euler follows that growth, and the step's tangent K + eta / dt M stays positive
   definite, only for dt < eta / |omega| (a longer step converges back to the flat state: seen
   with eta = 10 mu and 5-day steps), so the steps are capped at eta / (2 |omega_onset|),
   omega_onset the first negative eigenvalue: the mode at most doubles per step; and at
   ``onset_dt`` (longer steps of the default bilayer's march all failed). A fold that
   snaps is a steeper mode, which such steps follow only a few thousandths of a day at a
   time: where a step is cut below :data:`SNAP_STEP` of the longest, the growth is held
   and the state relaxes to a stable equilibrium (as in stage 3) before the march goes on
   (:class:`~ngincompat.fem.relaxation.SnappingMarch`). The fold
   amplitude (half the peak-to-peak u2 along the top), the smallest eigenvalue and the
   smallest elastic stretch of the top surface along it are recorded at the first step,
   then every ``observe_dt`` of growth (the eigenpairs cost more than a Newton iteration),
   and at ``t_end``. That
   stretch, lambda_e = |F e1| / theta_c (the cortex's Fe = F Fg^-1, Fg e1 = theta_c e1), is
   1 / theta_c on the flat branch and falls at the bottoms of the sulci as the folds deepen;
   below :data:`CREASE_STRETCH` a neo-Hookean surface creases: the walls of a sulcus fold
   onto each other. They are kept apart by the frictionless self-contact of the top
   surface (:class:`~ngincompat.fem.self_contact.SelfContact`, penalty
   ``contact_penalty``, in every coupled problem of the scene; while the ends are rollers,
   also with its mirror images in them: a sulcus on an end has its other wall in the
   image), and the mesh can be
   refined toward the top (``top_refinement``); the march reports how far it went
   (``t_reached``, ``theta_c_reached``), the smallest elastic Jacobian of its records
   (``Je_min``) and the contact (``self_contact_area``, the length of the top line in
   contact, and ``self_contact_penetration_max``). Where its steps are cut until it gives
   up, its error says where the stretch fell below the threshold. The default bilayer
   reaches the paper's 75 days (theta_c = 1.6) and its folds crease into contact at 48-56
   days; with the cortex's mesh twice as coarse (the preview's) they deepen without their
   walls touching (``docs/measurements/folding.md``, "Convergence at the paper's 75
   days").
3. **equilibrium**: the viscous march's end is not an equilibrium (residual without the
   viscosity 5.4e-5 on the small bilayer of the tests), and plain Newton without the
   viscosity diverged from it. At ``t_end`` the growth is held and the same viscous term
   drives a gradient flow in pseudo time (:class:`~ngincompat.fem.relaxation.RelaxationStage`:
   steps that lower the energy, doubling) toward a stable equilibrium, which Newton then
   solves without the viscosity; it is kept only if the smallest eigenvalue of the tangent
   there is >= 0 (a saddle is refused and the flow goes on). Reported:
   ``equilibrium_residual`` (the residual without viscosity there, relative to the
   viscous end's) and ``equilibrium_eigenvalue``. Without an onset before ``t_end`` the
   perfect branch's end is that equilibrium already.
4. **release**: growth frozen, the end and bottom supports are removed; the rigid motions
   of the section (the two in-plane translations and the rotation about X3) are removed by
   the statically determinate pins of :func:`~ngincompat.fem.problem.rigid_pins` (three
   displacement components at vertices), whose reactions vanish for the
   self-equilibrated body: ``release_reaction_rel``, their norm relative to the forces the
   removed supports carried, measures it. The relaxation, started with those forces
   unbalanced, finds the released equilibrium. The remaining stress is the
   incompatibility's.

Measured after the stages: ``fold_amplitude`` of the final equilibrium, its ``sulci`` (the
troughs of the deformed top, one on a roller end counting one half) and ``sulcus_depth`` (the
deepest one's depth below its lower neighbouring crest; :func:`~ngincompat.fem.shape.sulci`),
``top_stretch_min`` (the smallest elastic stretch of the top surface recorded while growing),
the max principal
Cauchy stress before (``sigma_max`` field,
``max_principal_stress``) and after the release (``sigma_max_released``,
``max_principal_stress_released``, with the displacement ``u_released``), the reference
depth below the top surface of the released peak tension (``peak_tension_depth_released``:
below the interface if > ``cortex_thickness``), the strain energy per unit depth before
and after the release (``strain_energy``, ``strain_energy_released``: int Jg Psi dA, eq.
36), and ``top_curvature_released``: the mean
curvature of the top surface over the central third of the length after release, the
curvature of the circle fitted (:func:`~ngincompat.fem.shape.circle_curvature`) to the deformed
top line (X1 + u1, X2 + u2) sampled along it; positive where the top
bulges upward (the cortex on the convex side).

Outputs (``measure``): the axon growth theta_a (theta in the subcortex, 1 in the cortex);
G = (1/Jg) Fg Curl Fg (eq. 10) by the projected path, the Burgers vector density on the
paper's plane normal to e3, b = G^T e3 (eq. 11), its norm and Curl Fg : Curl Fg;
``burgers_max`` with its depth below the top (``burgers_max_depth``) and its X1; the
largest principal Cauchy stress. The fields are sampled on the section
(profile "section", a reference grid refined near the top, with the in-plane displacement
components) for the figure of Fig. 7 a-c, the fields drawn on the deformed shape (``PANELS``:
a panel whose fields a run has, e.g. after the release, is drawn), and along the vertical
through the middle (profile "depth").

Why one module: the scene's parameters, the stages of its case (approach, perfect branch,
buckling, equilibrium, release) and its measures all turn on the same bilayer and
its bifurcation onset, and a split would pass that state between modules; a sixth of the
lines are this description.
"""

import functools
from dataclasses import dataclass, field, replace

import ngsolve as ngs
import numpy as np

from geometries import bilayer, estimate
from ngincompat import sampling
from ngincompat.errors import require
from ngincompat.fem import buckling, postprocess
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import pin_reactions
from ngincompat.fem.relaxation import RelaxationStage, SnappingMarch
from ngincompat.fem.self_contact import SelfContact
from ngincompat.fem.shape import circle_curvature, sulci
from ngincompat.fem.solver import NewtonOptions, NewtonSolver
from ngincompat.fem.stages import CoupledStage
from ngincompat.fem.terms import GrowthEnergy, RigidPins, ViscousRegularisation
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.growth import FiberGrowth
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw, StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean, Regional
from ngincompat.progress import Progress
from ngincompat.references.bifurcation import Bilayer, onset
from ngincompat.sampling import element_points
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
from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.trust import Indicator
from ngincompat.workflow.frames import Frames
from ngincompat.workflow.pipeline import Solution, solve_stages, timed
from ngincompat.workflow.results import Figure, Results

#: The axon fields of Fig. 7 (left to right), and "none": no axon growth.
AXONS = (*fields.AXONS, "none")

#: Eigenpairs computed per step: Lanczos asked for one alone can settle on another of the
#: cluster of nearly equal wrinkling modes and miss the smallest (seen: 10.8 after 3.5).
EIGENPAIRS = 6

#: Elastic compressive stretch at which the surface of a neo-Hookean half-space creases in
#: plane strain (critical strain 0.35: Hong, Zhao and Suo, Appl. Phys. Lett. 95 (2009)
#: 111901), well before the wrinkling stretch 0.54 of Biot's analysis.
CREASE_STRETCH = 0.65

#: The self-contact's pairs are sought within this many cortex thicknesses of a point. The
#: search costs about the number of boundary elements within reach per point, which on a
#: refined top is most of a step (``docs/measurements/folding.md``, "Past the creasing
#: threshold"). The walls of a sulcus approach by far less than a quarter thickness per step.
CONTACT_REACH = 0.25

#: Newton's linear solver in every stage (:class:`~ngincompat.fem.solver.NewtonOptions`): GMRES
#: preconditioned by the sparse Cholesky factorisation of the tangent's symmetric part. The
#: coupled tangent (growth condensed) is symmetric but for the stretch-driven axons' coupling
#: (under 1 % of its norm); on the default bilayer GMRES takes a few iterations per direction
#: and a Newton step costs about half of one with UMFPACK's LU, with the same residuals
#: (``docs/measurements/folding.md``, "Where the time goes").
#: At most ``KRYLOV_MAXITER`` iterations: where the preconditioner is poor the step is cut.
LINEAR_SOLVER = "symmetric-gmres"
KRYLOV_MAXITER = 100

#: Relative residual to which the viscous march's steps are solved: its states are a path
#: whose error in time (implicit Euler over steps of days) is far above this, and the
#: equilibrium at its end is solved to ``rtol`` without the viscosity. Against Newton's
#: 1e-9 it saves the last iteration of most steps, and starting each step from the
#: extrapolation of the last two saves more (``docs/measurements/folding.md``, "The
#: section").
MARCH_RTOL = 1e-6

#: The relaxations try Newton without the viscosity each time the flow's residual has fallen
#: this much (:class:`~ngincompat.fem.relaxation.RelaxationStage`'s ``switch``), within at most
#: ``RELAXATION_STEPS`` accepted pseudo-time steps of one Newton step each. The default
#: bilayer released at 75 days creeps toward its equilibrium along a soft mode: with a
#: tenfold fall asked for and 60 steps, Newton was never tried
#: (``docs/measurements/folding.md``, "The paper's 75 days"). The curved field with every
#: mesh size halved needed 174 steps, its step falling to a thousandth of a day and
#: doubling back up several times ("The release in contact").
RELAXATION_SWITCH = 0.3
RELAXATION_STEPS = 500


#: After a cut step, this many converged steps keep the step before it may double again
#: (:class:`~ngincompat.fem.solver.NewtonOptions`' ``step_hold``, also in the relaxations);
#: the viscous march gives a step up once its residual has stayed above its best for
#: ``STALL`` iterations (``stall``). The march meets short events where a fold snaps, which
#: only steps of a few thousandths of a day get through: doubling after each easy step
#: failed again at each, and each failed try cost the 12 iterations of its cap
#: (docs/measurements/folding.md, "The march's failed steps").
STEP_HOLD = 2
STALL = 3

#: The viscous march hands a snap to a relaxation at held growth
#: (:class:`~ngincompat.fem.relaxation.SnappingMarch`) where its step is cut below this fraction
#: of its longest.
SNAP_STEP = 1 / 16


def newton(**settings):
    """The Newton options of every stage: at most 12 iterations per step, the directions
    by :data:`LINEAR_SOLVER`, :data:`STEP_HOLD` steps held after a cut, and the stage's own
    ``settings`` (which may change those)."""
    return NewtonOptions(**{"max_iter": 12, "linear_solver": LINEAR_SOLVER,
                            "krylov_maxiter": KRYLOV_MAXITER, "step_hold": STEP_HOLD,
                            **settings})


@functools.lru_cache(maxsize=32)
def _placing_onset(bilayer, length):
    """theta_c at the onset of the bifurcation analysis of ``bilayer`` with roller ends at
    ``length``, scanned in theta_c steps of 0.02 (it places the perfect branch's steps), or
    None if it finds none. Cached: it only depends on the bilayer (seconds per call), which
    the variants of a scene in time steps, axons or outputs share."""
    try:
        return onset(bilayer, length=length, resolution=0.02).growth
    except ValueError:
        return None


#: Boundary conditions while growing: ends on rollers, bottom on rollers.
GROWING = {"left": "x", "right": "x", "bottom": "y"}

#: After the release: no support (the rigid motions are pinned).
RELEASED = {}


#: The panels of Fig. 7 a-c: label -> (field, the displacement it is drawn deformed by);
#: "{L}" and "{stress}" stand for the units. A panel is drawn when the run has its fields.
PANELS = {"axon growth theta_a [-]": ("theta_a", "u"),
          "|b| on the plane normal to e3 [1/{L}]": ("|b|", "u"),
          "max principal Cauchy stress [{stress}]": ("sigma_max", "u"),
          "after release: max principal Cauchy stress [{stress}]":
              ("sigma_max_released", "u_released")}

#: The fields sampled along the vertical through the middle (profile "depth").
DEPTH_FIELDS = ("theta_a", "|b|", "curlFg_sq", "sigma_max", "sigma_max_released")


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
    metrics = ("onset_growth", "onset_wavelength", "onset_time", "fold_amplitude", "sulci",
               "sulcus_depth",
               "t_reached", "theta_c_reached", "Je_min", "self_contact_area",
               "self_contact_penetration_max", "burgers_interface_mean",
               "theta_a_max", "burgers_max", "burgers_max_depth", "burgers_max_X1",
               "equilibrium_residual", "equilibrium_eigenvalue", "max_principal_stress",
               "max_principal_stress_released", "top_curvature_released",
               "peak_tension_depth", "peak_tension_depth_released", "release_reaction_rel",
               "top_stretch_min", "strain_energy", "strain_energy_released")
    metric_quantities = {"burgers_max": "1/length", "max_principal_stress": "stress",
                         "max_principal_stress_released": "stress",
                         "onset_wavelength": "length",
                         "fold_amplitude": "length", "sulcus_depth": "length",
                         "onset_time": "time",
                         "t_reached": "time", "self_contact_area": "length",
                         "self_contact_penetration_max": "length",
                         "burgers_interface_mean": "1/length",
                         "burgers_max_depth": "length", "burgers_max_X1": "length",
                         "equilibrium_eigenvalue": "stress/length^2",
                         "top_curvature_released": "1/length",
                         "peak_tension_depth": "length",
                         "peak_tension_depth_released": "length",
                         "strain_energy": "stress length^2",
                         "strain_energy_released": "stress length^2"}
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

    def __post_init__(self):
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

    def axon_law(self):
        """The subcortex's law: stretch-driven (eq. 45, gamma = 0) or, without axons, none."""
        if self.axons == "none":
            return ConstantRateLaw(0.0)
        return StrainDrivenLaw(tau=1.0 / self.axon_rate, theta_max=self.axon_max, gamma=0.0,
                               theta_crit=self.stretch_crit)

    @property
    def top_maxh(self):
        """The mesh size on the top surface, cortex_maxh / top_refinement."""
        return self.cortex_maxh / self.top_refinement

    @property
    def mu_gray(self):
        return self.mu_ratio * self.mu_white

    def bifurcation_bilayer(self):
        """The same bilayer for the independent linear bifurcation analysis
        (:mod:`ngincompat.references.bifurcation`)."""
        lam = self.lam_ratio
        return Bilayer(self.height, self.cortex_thickness, self.mu_gray, lam * self.mu_gray,
                       self.mu_white, lam * self.mu_white)

    def mesh_estimate(self):
        return (estimate.bilayer_elements(length=self.length, height=self.height,
                                          cortex=self.cortex_thickness,
                                          maxh=self.maxh, cortex_maxh=self.cortex_maxh,
                                          top_maxh=self.top_maxh),
                "triangle")

    def build(self):
        mesh = bilayer(length=self.length, height=self.height,
                       cortex=self.cortex_thickness, maxh=self.maxh,
                       cortex_maxh=self.cortex_maxh, top_maxh=self.top_maxh)
        return FoldingCase(self, mesh)


@dataclass(eq=False)
class FoldingCase(SceneCase):
    """The folding scene's case: the coupled bilayer and the observations of its growth.

    ``series`` holds, per converged step of the perfect branch and per record (every
    ``observe_dt`` of growth) of the buckling stage,
    the time, the cortex growth, the smallest tangent eigenvalue, the fold amplitude (half
    the peak-to-peak u2 along the top surface) and the top surface's smallest elastic
    stretch (:meth:`top_stretch`).
    """

    scene: FoldingScene
    mesh: ngs.Mesh
    noted: dict = field(default_factory=dict)
    series: dict = field(default_factory=lambda: {
        branch: {"t": [], "theta_c": [], "eigenvalue": [], "amplitude": [], "stretch": [],
                 "Je_min": [], "contact_length": [], "penetration": []}
        for branch in ("perfect", "buckling")})

    def __post_init__(self):
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
        self.grown = self.grown_contact = None       # kept by the release
        self.reactions = float("nan")
        self.mode = None
        self.pairs = None
        self.frames = Frames.of(scene, mesh, lambda: {"u": self.problem.u,
                                                      "theta": self.growth.theta})

    def coupled(self):
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
        problem = CoupledProblem(self.mesh, [growth, viscous, contact, RigidPins()],
                                 order=scene.order, symmetry=GROWING,
                                 realcompile=True if self.marches() else None)
        return problem, growth, viscous, contact

    def _along_top(self, cf, n):
        """X1 and the values of ``cf`` at ``n`` points along the top surface."""
        s = self.scene
        x, values = postprocess.sample_line(self.mesh, {"v": cf}, (0.0, s.height),
                                            (s.length, s.height), n=n)
        return x, values["v"]

    def top_profile(self, u, n=301, component=1):
        """X1 and the displacement ``component`` along the top surface (default u2, the
        vertical)."""
        return self._along_top(u[component], n)

    def top_curvature(self, u, n=301):
        """The curvature of the circle fitted to the deformed top line (X1 + u1, X2 + u2)
        over the central third of the length (1/length; > 0: bulging upward)."""
        x, u1 = self.top_profile(u, n, component=0)
        _, u2 = self.top_profile(u, n)
        third = (x >= self.scene.length / 3) & (x <= 2 * self.scene.length / 3)
        return circle_curvature(x[third] + u1[third], self.scene.height + u2[third])

    def top_stretch(self, u, theta_c, n=301):
        """The smallest elastic stretch of the top surface along it, lambda_e = |F e1| /
        theta_c (F = I + Grad u; the cortex grows along e1 by theta_c), over ``n`` points
        along the top."""
        F_e1 = kinematics.deformation_gradient(u) * ngs.CF((1, 0, 0))
        _, values = self._along_top(ngs.Norm(F_e1), n)
        return float(np.nanmin(values)) / theta_c

    def _observe(self, branch, t, negative=False):
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

    def _reached(self, t):
        """Note ``t`` and its cortex growth as the furthest the growth has gone."""
        self.noted.update(t_reached=float(t),
                          theta_c_reached=float(1 + self.scene.cortex_rate * t))

    def elastic_jacobian_min(self, growth, u):
        """The smallest Je = det F / Jg (Jg = theta for fiber growth) over the integration
        points and vertices of the mesh: > 0 where no element has inverted."""
        Je = ngs.Det(kinematics.deformation_gradient(u)) / growth.theta
        return float(np.min(np.asarray(Je(element_points(self.mesh, 4))).ravel()))

    def _observe_perfect(self, t):
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
            onset, x, _ = buckling.earliest_crossing(
                theta, previous[0], values, buckling.overlaps(previous[1], modes))
            self.mode = buckling.combine(modes, x)
            self.noted.update(onset_growth=onset,
                              onset_time=(onset - 1) / self.scene.cortex_rate)
        x, w = self.top_profile(self.mode)
        self.noted["onset_wavelength"] = buckling.wavelength(x, w)
        return True

    def _observe_buckling(self, t):
        """Record the march's state (:meth:`_observe`: its eigenpairs cost as much as a
        Newton iteration and more) at its first step, then once at least ``observe_dt`` of
        growth has passed since the last record, and at ``t_end``."""
        series, scene = self.series["buckling"], self.scene
        self._reached(t)
        if (not series["t"] or t >= series["t"][-1] + scene.observe_dt - 1e-9
                or t >= scene.t_end - 1e-9 * max(1.0, scene.t_end)):
            self._observe("buckling", t)
        return False

    def perturb(self):
        """Add the onset's buckling mode to the displacement, scaled to ``imperfection`` x
        ``cortex_thickness`` on the top surface, and start the viscous regularisation
        (:attr:`eta`) from there."""
        _, w = self.top_profile(self.mode)
        scale = self.scene.imperfection * self.scene.cortex_thickness / np.max(np.abs(w))
        self.problem.u.vec.data += scale * self.mode.vec
        self.viscous.restart(self.eta)

    def analysis_onset_time(self):
        """The time of the onset of the bifurcation analysis
        (:func:`~ngincompat.references.bifurcation.onset`, roller ends, scanned in theta_c
        steps of 0.02: it places steps, it is not the measured onset), or None if it finds
        none."""
        scene = self.scene
        growth = _placing_onset(scene.bifurcation_bilayer(), scene.length)
        return None if growth is None else (growth - 1) / scene.cortex_rate

    def marches(self):
        """Whether the run is expected to follow folds past the onset (``buckle``, and the
        analysis' onset before ``t_end``): hundreds of Newton iterations, for which the
        residual is compiled to C++ whatever the number of unknowns
        (:data:`~ngincompat.fem.problem.REALCOMPILE_NDOF`): the compilation, seconds, is
        repaid within the march (``docs/measurements/folding.md``, "The section")."""
        onset_time = self.analysis_onset_time()
        return self.scene.buckle and onset_time is not None and onset_time < self.scene.t_end

    def approach_end(self):
        """Where the perfect branch's short steps begin: 2 ``onset_dt`` before the
        analysis' onset (:meth:`analysis_onset_time`), or 0 (no approach) if that is not
        after two of the approach's longest steps, beyond ``t_end`` or not found."""
        scene, onset_time = self.scene, self.analysis_onset_time()
        if onset_time is None:
            return 0.0
        t = onset_time - 2 * scene.onset_dt
        return t if 2 * max(scene.approach_dt, scene.onset_dt) <= t < scene.t_end else 0.0

    def stages(self):
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
    def eta(self):
        """The viscosity of the regularisation (stress x time / length^2)."""
        return self.scene.viscosity * self.scene.mu_white

    def viscous_step(self):
        """The largest step of the viscous march, eta / (2 |omega_onset|), or ``dt``."""
        eigenvalue = self.series["perfect"]["eigenvalue"][-1]
        return min(self.scene.dt, self.eta / (2 * abs(eigenvalue)))

    def buckling_stage(self):
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

    def relaxation(self, name, problem, viscous):
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
    def released(self):
        """Whether :meth:`release` has begun (the supports removed)."""
        return self.grown is not None

    @property
    def grown_u(self):
        """The displacement of the grown state: kept by the release, else the current one."""
        return self.problem.u if self.grown is None else self.grown

    def release(self):
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

    def plan(self, branch, onset=True):
        """The names of the stages a run goes through after the stages ``branch`` of the
        perfect branch (``onset``: if that reaches the onset, where the buckling starts)."""
        names = [stage.name for stage in branch]
        if onset and self.scene.buckle:
            names += ["buckling", "equilibrium"]
        return names + (["release"] if self.scene.release else [])

    def solve(self, solution: Solution, progress: Progress, workdir=None) -> None:
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

    def _explain_crease(self, solution):
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

    def _note(self, stage):
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
        results = self.interrupted(solution)
        results.profiles = {branch: {k: np.array(v) for k, v in series.items()}
                            for branch, series in self.series.items() if series["t"]}
        if self.series["buckling"]["t"] and solution.converged:
            _, u2 = self.top_profile(self.grown_u)    # of the final equilibrium
            results.metrics["fold_amplitude"] = float(np.ptp(u2) / 2)
            count, depth = sulci(u2)
            results.metrics.update(sulci=count, sulcus_depth=depth)
        stretches = self.series["perfect"]["stretch"] + self.series["buckling"]["stretch"]
        if stretches:
            results.metrics["top_stretch_min"] = min(stretches)
        flds = {"u": self.grown_u, "theta": self.growth.theta,
                **self._stresses(self.growth, self.grown_u, "", results.metrics)}
        results.metrics["strain_energy"] = self.strain_energy(self.grown_u)
        results.metrics.update(self._contact_metrics(solution))
        if self.released and solution.converged:
            flds["u_released"] = self.problem.u
            flds.update(self._stresses(self.growth, self.problem.u, "_released",
                                       results.metrics))
            results.metrics["top_curvature_released"] = self.top_curvature(self.problem.u)
            results.metrics["strain_energy_released"] = self.strain_energy(self.problem.u)
        if self.mode is not None:
            flds["buckling_mode"] = self.mode
            x, w = self.top_profile(self.mode)
            results.profiles["mode"] = {"X1": x, "u2": w}
        with progress.phase("incompatibility"), timed(results.timings, "incompatibility"):
            flds.update(self.incompatibility())
            results.metrics.update(self.burgers_metrics(flds["|b|"]))
            results.metrics["burgers_interface_mean"] = self.interface_mean(flds["|b|"])
        mesh = self.mesh
        results.metrics["theta_a_max"] = sampling.maximum(flds["theta_a"], mesh)
        with progress.phase("sampling"), timed(results.timings, "sampling"):
            results.profiles["section"] = self.section(flds)
            results.profiles["depth"] = self.depth_profile(flds)
        results.fields = flds
        results.figures = _figures(self.scene, results.profiles)
        return results

    def _contact_metrics(self, solution):
        """``Je_min`` over the records of the growth and the final states (grown and, if
        released, released), the final grown state's
        ``self_contact_area`` (length of the top line in contact) and the largest
        ``self_contact_penetration_max`` of the records and those states."""
        final = self.contact.measures() if self.grown_contact is None else self.grown_contact
        jacobians = [self.elastic_jacobian_min(self.growth, self.grown_u)]
        penetrations = [final["self_contact_penetration_max"]]
        for series in self.series.values():
            jacobians += series["Je_min"]
            penetrations += series["penetration"]
        if self.released and solution.converged:
            jacobians.append(self.elastic_jacobian_min(self.growth, self.problem.u))
            penetrations.append(self.contact.measures()["self_contact_penetration_max"])
        return {"Je_min": min(jacobians), "self_contact_area": final["self_contact_area"],
                "self_contact_penetration_max": max(penetrations)}

    def strain_energy(self, u):
        """The strain energy per unit depth of the section at the displacement ``u`` and
        the current growth, int Jg Psi(F Fg^-1) dA (eq. 36): the residual stress's energy
        after the release, where the largest principal stress is a value at one point."""
        density = self.growth.energy_density(kinematics.deformation_gradient(u))
        return float(ngs.Integrate(density, self.mesh, order=2 * self.scene.order))

    def interface_mean(self, cf):
        """The mean of ``cf`` over the band of one cortex thickness centred on the interface
        (reference X2 within cortex_thickness / 2 of it)."""
        s = self.scene
        interface = s.height - s.cortex_thickness
        band = ngs.IfPos(s.cortex_thickness / 2 - ngs.sqrt((ngs.y - interface) ** 2), 1.0, 0.0)
        return float(ngs.Integrate(band * cf, self.mesh, order=6)
                     / (s.cortex_thickness * s.length))

    def incompatibility(self):
        """theta_a and the incompatibility of the current growth on the paper's plane normal
        to e3 (projected path: :class:`~ngincompat.incompatibility.measure.Incompatibility`)."""
        theta = self.growth.theta
        measured = Incompatibility.projected(FiberGrowth(theta, self.f0).Fg, self.mesh,
                                             self.scene.g_order, {"e3": (0, 0, 1)})
        return {"theta_a": self.mesh.MaterialCF({"subcortex": theta, "cortex": 1.0}),
                **measured.fields()}

    def _stresses(self, growth, u, suffix, metrics):
        """The Cauchy stress of the growth term ``growth`` at the displacement ``u`` and its
        largest principal value (fields
        ``sigma``, ``sigma_max`` + ``suffix``); into ``metrics`` that value's maximum over
        the integration points and vertices (``max_principal_stress`` + ``suffix``) and the
        reference depth below the top surface where it is reached (``peak_tension_depth``
        + ``suffix``)."""
        sigma = postprocess.stresses(growth.energy_density, u)["sigma"]
        largest = postprocess.largest_principal_value(sigma)
        points = element_points(self.mesh, 4)
        values = np.asarray(largest(points)).ravel()
        peak = int(np.nanargmax(values))
        metrics[f"max_principal_stress{suffix}"] = float(values[peak])
        metrics[f"peak_tension_depth{suffix}"] = float(
            self.scene.height - np.asarray(ngs.y(points)).ravel()[peak])
        return {f"sigma{suffix}": sigma, f"sigma_max{suffix}": largest}

    def burgers_metrics(self, b_norm):
        """The largest |b|, its depth below the top and its X1."""
        value, where = sampling.argmax(b_norm, self.mesh)
        return {"burgers_max": value, "burgers_max_depth": self.scene.height - where[1],
                "burgers_max_X1": where[0]}

    def section(self, flds, n=241, band=5):
        """The fields of ``PANELS`` that ``flds`` has on the section, on a grid of n
        columns over the length and rows refined in the top ``band`` cortical thicknesses
        (40 rows there, 30 below); displacements as their (u1, u2)."""
        s = self.scene
        top = max(s.height - band * s.cortex_thickness, 0.0)
        x1 = np.linspace(0.0, s.length, n)
        x2 = np.unique(np.concatenate([np.linspace(0.0, top, 30),
                                       np.linspace(top, s.height, 41)]))
        keys = {k for pair in PANELS.values() for k in pair if all(p in flds for p in pair)}
        sampled = postprocess.sample_plane(self.mesh, {k: flds[k] for k in keys},
                                           (0.0, 0.0, 0.0), (1, 0, 0), (0, 1, 0), x1, x2)
        return {"X1": x1, "X2": x2, **sampled}

    def depth_profile(self, flds, n=401):
        """``DEPTH_FIELDS`` along the vertical through the middle, from the top down."""
        s = self.scene
        depth, values = postprocess.sample_line(
            self.mesh, {k: flds[k] for k in DEPTH_FIELDS if k in flds},
            (s.length / 2, s.height), (s.length / 2, 0.0), n=n)
        return {"depth": depth, **values}


def panels(scene):
    """``PANELS`` with the scene's units: label -> (field, displacement)."""
    units = {"L": scene.units["length"], "stress": scene.units["stress"]}
    return {label.format(**units): keys for label, keys in PANELS.items()}


def fields_figure(scene, section):
    """The figure of Fig. 7 a-c of one run: the panels whose fields ``section`` has."""
    L = scene.units["length"]
    present = {label: keys for label, keys in panels(scene).items()
               if all(k in section for k in keys)}
    return Figure("fields.png", "X1", f"X1 [{L}]", {k: f for k, (f, _) in present.items()},
                  f"X2 [{L}]", f"{scene.title()}: deformed state", profile="section",
                  kind="deformed", y="X2", deform={k: d for k, (_, d) in present.items()},
                  floor=1e-3 * scene.mu_white)


def _figures(scene, profiles):
    L, title = scene.units["length"], scene.title()
    stress = scene.units["stress"]
    stresses = {label: k for label, k in (("grown", "sigma_max"),
                                           ("released", "sigma_max_released"))
                if k in profiles["depth"]}
    return [
        fields_figure(scene, profiles["section"]),
        Figure("depth.png", "depth", f"depth below the top [{L}]",
               {"|b| on the plane normal to e3": "|b|"}, f"|b| [1/{L}]",
               f"{title}: through the middle", right={"axon growth theta_a": "theta_a"},
               right_label="theta_a [-]", profile="depth"),
        Figure("stress_depth.png", "depth", f"depth below the top [{L}]",
               stresses, f"max principal Cauchy stress [{stress}]",
               f"{title}: through the middle", profile="depth",
               floor=1e-3 * scene.mu_white),
        Figure("eigenvalue.png", "theta_c", "cortex growth theta_c [-]",
               {"smallest eigenvalue": "eigenvalue"},
               f"smallest tangent eigenvalue [{scene.units['stress']}/{L}^2]",
               f"{title}: perfect branch", profile="perfect",
               marks={"onset (the eigenvalue crosses zero): theta_c = {value:.4g}":
                      "onset_growth"}),
        Figure("folds.png", "theta_c", "cortex growth theta_c [-]",
               {"fold amplitude": "amplitude"}, f"fold amplitude [{L}]",
               f"{title}: after the onset", right={"smallest eigenvalue": "eigenvalue"},
               right_label=f"smallest tangent eigenvalue [{scene.units['stress']}/{L}^2]",
               profile="buckling"),
        Figure("mode.png", "X1", f"X1 [{L}]", {"u2 on top": "u2"}, "buckling mode u2 [-]",
               f"{title}: first buckling mode", profile="mode"),
    ]
