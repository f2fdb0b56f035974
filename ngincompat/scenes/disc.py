"""The disc of section 3.3: transversely isotropic area growth with GOH fibers."""

from dataclasses import dataclass
from typing import Any, Literal

import ngsolve as ngs
import numpy as np

from geometries import disc, estimate
from ngincompat import sampling
from ngincompat.fem import postprocess
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import AreaGrowth
from ngincompat.mechanics.materials import MaterialKind, make_material
from ngincompat.scenes import prescribed
from ngincompat.scenes.base import LENGTH_FLOOR, MAXH, ORDER, param
from ngincompat.scenes.material import K1, K2, MU, Fibers
from ngincompat.scenes.metrics import Metric, registry

FIBERS = {"radial": "radial_xy", "circumferential": "circumferential"}


@dataclass(frozen=True)
class DiscScene(Fibers, prescribed.PrescribedScene):
    """Disc R0 = 1 mm, height 0.5 mm; area growth theta = 1 + R t / 4 about N0 = e3 (eq. 51),
    R = sqrt(X1^2 + X2^2); traction-free.

    Material: GOH (eq. 39) with one fiber family, radial or circumferential, or neo-Hookean.
    The GOH parameters default to the media of Holzapfel, Gasser & Ogden, J. Elasticity 61
    (2000) 1-48, Table 1 (rabbit carotid artery): mu = c = 3.0 kPa, k1 = 2.3632 kPa,
    k2 = 0.8393, with no dispersion (kappa = 0, the GOH model's aligned limit); the volumetric
    parameter follows from nu = 0.4 as in the paper's other idealized scenes. The paper gives
    no values for this scene.

    Reports b on the plane e3 (Fig. 3b) against eq. (22), and sigma_r, sigma_theta and Psi
    against R at mid-height (Fig. 3e).
    """

    name = "disc"
    summary = "section 3.3: area growth of a disc, GOH with radial or circumferential fibers"
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=0.4, order=2, g_order=3), "paper": dict(order=4)}
    variant = ("fibers", "material")
    metrics = registry(
        prescribed.PrescribedScene.metrics,
        b_eq22_error=Metric("the largest deviation of b on the planes normal to e3 from its "
                            "closed form, eq. (22), relative to that form's largest |b| (away "
                            "from the axis, where theta has a cone)"),
        b_out_of_plane=Metric("the largest component of b along the disc's normal, relative "
                              "to the largest |b|: zero by eq. (22)"),
        b_along_grad_theta=Metric("the largest component of b along grad theta (radial), "
                                  "relative to the largest |b|: zero by eq. (22)"),
        sigma_r_rim_rel=Metric("the radial Cauchy stress at the free rim relative to its "
                               "largest value along the radius: zero at a traction-free rim"))

    order: int = ORDER(3)
    maxh: float = MAXH(0.2)
    R0: float = param(1.0, "radius", "length", range=f"[{LENGTH_FLOOR:g}, 1000]")
    height: float = param(0.5, "thickness", "length",
                           range=f"[{LENGTH_FLOOR:g}, 1000]")
    material: Literal["goh", "neo-hookean"] = param("goh", "goh or neo-hookean")
    fibers: str = param("radial", "GOH fiber family: radial or circumferential",
                        choices=FIBERS)
    mu: float = MU(0.003)               # the GOH ground matrix's c; nu = 0.4 of the block
    k1: float = K1(0.0023632)
    k2: float = K2(0.8393)

    def __post_init__(self) -> None:
        super().__post_init__()
        self.make_material()

    def make_material(self) -> MaterialKind:
        return make_material(self.material, self.mu, self.nu, self.k1, self.k2, self.kappa)

    def mesh_estimate(self) -> tuple[float, str]:
        return estimate.disc_elements(R0=self.R0, height=self.height, maxh=self.maxh), "tet"

    def build(self) -> prescribed.PrescribedCase:
        mesh = disc(R0=self.R0, height=self.height, maxh=self.maxh, curve_order=self.order)
        time = ngs.Parameter(0.0)
        R = ngs.sqrt(ngs.x * ngs.x + ngs.y * ngs.y)
        theta = 1 + R * time / 4
        N0 = fields.constant("e3")
        growth = AreaGrowth(theta, N0)
        material = self.make_material()
        e_r = fields.radial(axis="e3").cf
        e_t = fields.circumferential("e3").cf
        mid = self.height / 2

        def verify(problem: GrowthMechanics | None, flds: dict[str, Any]) -> dict[str, float]:
            b = flds["b_e3"]
            b22 = inc.burgers_area_closed_form(theta, inc.grad_scalar(theta), N0.cf)
            # theta has a cone along the axis: the projected G is inaccurate in the first
            # ring of elements around it, which the structural checks leave out
            away = ngs.IfPos(R - max(0.1 * self.R0, 2 * self.maxh), 1.0, 0.0)
            scale = sampling.maximum(ngs.Norm(b22), mesh)
            if not scale > 0:   # not grown (a first step that failed): nothing to check
                return {}
            metrics = {
                "b_eq22_error": sampling.maximum(away * ngs.Norm(b - b22), mesh) / scale,
                "b_out_of_plane": sampling.maximum(
                    ngs.sqrt(ngs.InnerProduct(b, N0.cf) ** 2), mesh) / scale,
                "b_along_grad_theta": sampling.maximum(
                    away * ngs.sqrt(ngs.InnerProduct(b, e_r) ** 2), mesh) / scale,
            }
            if problem is not None:
                sigma_r = postprocess.sample_line(mesh, {"s": flds["sigma_r"]}, (0, 0, mid),
                                                  (self.R0, 0, mid))[1]["s"]
                metrics["sigma_r_rim_rel"] = float(abs(sigma_r[-1]) / np.max(np.abs(sigma_r)))
            return metrics

        return prescribed.PrescribedCase(
            scene=self,
            mesh=mesh, growth=growth, material=material, time=time,
            planes={"e3": N0.cf},
            line=((0.0, 0.0, mid), (self.R0, 0.0, mid), "R"),
            fibers=(fields.from_name(FIBERS[self.fibers]),) if material.needs_fibers else (),
            components={"sigma_r": ("sigma", e_r, e_r), "sigma_theta": ("sigma", e_t, e_t)},
            verify=verify)
