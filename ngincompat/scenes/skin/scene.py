"""The skin scene (section 3.6): its parameters, presets and metrics; the case it builds is
:class:`~ngincompat.scenes.skin.case.SkinCase`."""

import os
from dataclasses import dataclass

from geometries import FOOTPRINTS, estimate, footprint_area, footprint_size, skin_patch
from geometries.skin_patch import SIDE, THICKNESS
from ngincompat.errors import require
from ngincompat.fem import contact
from ngincompat.mechanics.laws import HillLaw
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.scenes.base import (
    G_ORDER,
    MAX_STEPS,
    MAXH,
    ORDER,
    RATE_FLOOR,
    TIME_FLOOR,
    Scene,
    check_time_steps,
    param,
)
from ngincompat.scenes.material import MU, Elastic
from ngincompat.scenes.metrics import CURVATURE, INCOMPATIBILITY, Metric, registry, select
from ngincompat.scenes.skin.case import SkinCase
from ngincompat.scenes.trust import Indicator

#: How the expander pushes the skin: a rigid dome in contact (the default), or a uniform
#: pressure on the footprint (for comparison).
EXPANDERS = ("contact", "pressure")
#: What the contact model measures of the expander and its contact
#: (:func:`ngincompat.fem.contact.measure`), each taken at the :data:`MOMENTS`.
CONTACT_MEASURES = {
    "expander_height": Metric("the height H of the expander's dome x3 = H phi over the "
                              "footprint", "length"),
    "contact_area": Metric("the reference area of the footprint where the skin penetrates the "
                           "dome (gap g < 0)", "area"),
    "contact_force": Metric("the contact force, the integral of the contact pressure over the "
                            "footprint's reference area", "stress area"),
    "penetration_max": Metric("the largest penetration -g of the skin's lower surface into the "
                              "dome, on a grid of the footprint of a fiftieth of its size",
                              "length"),
    "contact_pressure_max": Metric("the largest contact pressure (per reference area) on that "
                                   "grid", "stress"),
    "contact_pressure_max_radius": Metric("the distance from the footprint's centre of the "
                                          "point of that grid where the contact pressure is "
                                          "largest", "length"),
    "contact_pressure_mean": Metric("the mean contact pressure, the contact force over the "
                                    "contact area (0 without contact)", "stress"),
}
#: When the contact model's measures are taken: the suffix of their metrics' names.
MOMENTS = {"inflated": "at the end of the inflation, after the volume control",
           "end_of_hold": "at the end of the hold"}
#: The contact model's metrics: each of :data:`CONTACT_MEASURES` at each of :data:`MOMENTS`.
CONTACT_METRICS = {f"{k}_{when}": Metric(f"{m.meaning}, {moment} (contact model only)",
                                         m.quantity)
                   for when, moment in MOMENTS.items() for k, m in CONTACT_MEASURES.items()}



@dataclass(frozen=True)
class SkinExpansionScene(Elastic, Scene):
    """Tissue expansion of a 10 x 10 x 0.3 cm skin patch (section 3.6)."""

    name = "skin"
    summary = ("section 3.6: skin expansion, an expander dome in contact inflated to 50 cc, "
               "7 days of area growth")
    variant = ("footprint",)
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=2.0),
               "paper": dict(maxh=0.7)}
    # the contact stage corrects the volume to 1e-4 (the pressure model holds it exactly)
    indicators = (Indicator("volume_error_rel", 1e-3, "the volume under the skin is not the "
                            "expander's: the inflation did not reach its target"),)
    units = {"length": "cm", "stress": "MPa", "energy": "MPa cm^3 (J)", "volume": "cm^3",
             "area": "cm^2", "time": "day"}
    metrics = registry(
        dict(
            volume_inflated=Metric("the volume enclosed under the skin over the footprint, "
                                   "int x3 det(dx_a/dX_b) dA, at the end of the inflation "
                                   "(contact model: after the volume control)", "volume"),
            volume_error_rel=Metric("|volume_inflated - volume| / volume, volume the target: "
                                    "how far the inflation missed its target"),
            pressure_inflated=Metric("the uniform pressure on the footprint that holds the "
                                     "enclosed volume at the target (the multiplier of the "
                                     "volume constraint) at the end of the inflation (pressure "
                                     "model only)", "stress"),
            pressure_end_of_hold=Metric("that pressure at the end of the hold (pressure model "
                                        "only)", "stress")),
        CONTACT_METRICS,
        dict(
            theta_max=Metric("the largest area growth theta (eq. 18) over the patch at the end "
                             "of the hold (Fig. 6a)"),
            theta_mean_footprint=Metric("the mean over the footprint's reference area of "
                                        "theta's continuous (H1) interpolant at the end of "
                                        "the hold"),
            theta_apex=Metric("theta at the apex, the centre of the bottom face (X1 = X2 = X3 "
                              "= 0), where section 3.6 has the largest growth")),
        select(["burgers_max"], INCOMPATIBILITY),
        dict(
            burgers_apex=Metric("|b| on the plane normal to e3 (eq. 11) at the apex: free of "
                                "incompatibility in section 3.6", "1/length"),
            burgers_max_radius=Metric("the distance sqrt(X1^2 + X2^2) of the point where |b| "
                                      "is largest from the patch's central axis, in the "
                                      "reference configuration", "length"),
            max_principal_stress_clamped=Metric(
                "the largest principal Cauchy stress over the patch in the clamped equilibrium "
                "after the deflation: expander removed, periphery still clamped, growth "
                "frozen", "stress"),
            strain_energy_clamped=Metric("the elastic energy int Jg Psi dV of that clamped "
                                         "equilibrium", "energy"),
            max_principal_stress_released=Metric(
                "the largest principal Cauchy stress over the patch in the released "
                "equilibrium, the clamp removed too: the residual stress of the grown skin's "
                "incompatibility alone (Fig. 6c)", "stress"),
            strain_energy_released=Metric("the elastic energy int Jg Psi dV of that released "
                                          "equilibrium", "energy"),
            min_principal_stress_contact_zone=Metric(
                "the smallest principal Cauchy stress of the released patch over the former "
                "contact zone, the points of the lower surface (on a grid of the footprint) "
                "that the expander pressed at the end of the hold: the compression of section "
                "3.6 (contact model only)", "stress"),
            min_principal_stress_contact_zone_mean=Metric(
                "the mean of that smallest principal stress over the same points (contact "
                "model only)", "stress")),
        CURVATURE)

    order: int = ORDER(2)
    maxh: float = MAXH(1.0)
    g_order: int = G_ORDER(4, help="order of the H1 space that Fg is projected into for "
                                   "Curl Fg")
    growth_order: int = param(3, "order of the (L2) growth field theta", range="[0, 5]")
    footprint: str = param("rectangle", "expander base: " + ", ".join(FOOTPRINTS),
                           choices=FOOTPRINTS)
    footprint_area: float = param(24.5, "area of the expander's base, the same for every "
                                        "footprint (7 x 3.5 cm for the rectangle), within "
                                        "the 10 x 10 cm patch; at least 1 cm^2: the "
                                        "smallest expanders' bases", "area",
                                  range="[1, 100]")
    expander: str = param("contact", "how the expander acts: contact (a rigid dome the skin "
                                     "rests on) or pressure (uniform on the footprint)",
                          choices=EXPANDERS)
    penalty: float = param(1000.0, "contact: pressure per unit penetration (at most 1e6: "
                                   "a millionfold skin's modulus per cm; at least "
                                   "1e-3, a thousandth of it)", "stress/length",
                           range="[1e-3, 1e6]")
    contact_width: float = param(0.005, "contact: penetration over which the penalty's ramp "
                                        "is rounded (at most the skin's thickness)", "length",
                                 range=f"[0, {THICKNESS}]")
    volume: float = param(50.0, "expander volume at the end of inflation (at most 500: over "
                                "the largest footprint a dome about as high as the patch is "
                                "wide; at least 0.1 cc: the footprint's first "
                                "millimetre)", "volume", range="[0.1, 500]")
    inflation_steps: int = param(10, "initial number of inflation steps",
                                 range=f"[1, {MAX_STEPS}]")
    hold_days: float = param(7.0, "duration of the hold (at most a year)", "time",
                             range="[0, 365]")
    dt: float = param(1.0, "time step of the hold (halved where Newton needs it)", "time",
                      range=f"[{TIME_FLOOR:g}, 365]")
    mu: float = MU(0.55)                # ref. [77], as section 3.1; nu = 0.4 of the block
    k: float = param(0.1, "Hill law: largest growth rate", "1/time",
                     range=f"[{RATE_FLOOR:g}, 100]")
    K: float = param(0.2, "Hill law: stimulus of half the largest rate",
                     range="[1e-3, 10]")
    n: float = param(2.0, "Hill law exponent (at most 20: a switch at K already)",
                     range="[1, 20]")
    theta_crit: float = param(1.05, "elastic area stretch below which skin does not grow",
                              range="[0.1, 10]")
    theta_max: float = param(3.0, "saturation of area growth (at most tenfold area)",
                             range="(1, 10]")
    resume: bool = param(False, "continue an interrupted hold from the folder's checkpoint")

    def __post_init__(self) -> None:
        super().__post_init__()
        largest = footprint_area(self.footprint, SIDE - 2 * THICKNESS)
        require(self.footprint_area <= largest, "footprint_area", self.footprint_area,
                f"in (0, {largest:.4g}] for the {self.footprint} (a margin of one thickness "
                "to the patch's edge)")
        check_time_steps("hold_days", self.hold_days, "dt", self.dt)
        self.expander_body()
        NeoHookean.from_nu(self.mu, self.nu)
        self.law()

    def law(self) -> HillLaw:
        return HillLaw(self.k, self.K, self.n, self.theta_crit, self.theta_max)

    def expander_body(self) -> contact.Expander | None:
        """The contact model's expander (None for the pressure model)."""
        if self.expander == "pressure":
            return None
        return contact.Expander(self.footprint, footprint_size(self.footprint, self.footprint_area),
                                self.penalty, self.contact_width)

    def resumes(self, out: str | os.PathLike) -> bool:
        return self.resume

    def mesh_estimate(self) -> tuple[float, str]:
        return estimate.skin_patch_elements(maxh=self.maxh), "tet"

    def build(self) -> SkinCase:
        """The patch, the coupled problem and the stages of section 3.6."""
        # the dome vanishes on the true footprint's edge, where the skin is held on the base:
        # a straight-sided edge lies inside a circle, and there the dome stood up to
        # H (1 - cos^2(pi / n)) above the held skin (0.03 H at maxh 1); curved elements
        # of the displacement's order put the edge on the circle
        curve = self.order if self.expander == "contact" else 1
        mesh = skin_patch(footprint=self.footprint,
                          footprint_size=footprint_size(self.footprint, self.footprint_area),
                          maxh=self.maxh, curve_order=curve)
        return SkinCase(self, mesh)
