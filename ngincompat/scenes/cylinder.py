"""The cylinder of section 3.4: fiber growth whose incompatibility is relieved by rotation."""

from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from geometries import cylinder, estimate
from ngincompat import sampling
from ngincompat.fem import postprocess
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import FiberGrowth
from ngincompat.mechanics.kinematics import deformation_gradient, elastic_part
from ngincompat.scenes import prescribed
from ngincompat.scenes.base import LENGTH_FLOOR, MAXH, ORDER, param
from ngincompat.scenes.metrics import Metric, registry


@dataclass(frozen=True)
class CylinderScene(prescribed.PrescribedScene):
    """Cylinder along e1, cross-section pi/4 mm^2, length 1 mm, X2 in [0, 1]; fiber growth along
    f0 = e1 with theta = 1 + a X2 t (eq. 52, a = 1/4): no growth at the bottom, 25 % at the
    top; neo-Hookean mu = 0.55 MPa, nu = 0.4; traction-free.

    The exact solution is stress-free: Fe is the rotation about e3 by the angle a X1
    (eq. 54-56), so the strain energy must vanish under refinement. Reports b on the plane e3
    against eq. (27) with beta = 90 degrees, the deviation of Fe from a rotation and the
    rotation rate along the axis.
    """

    name = "cylinder"
    summary = "section 3.4: fiber growth of a cylinder, relieved by a stress-free rotation"
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=0.5, order=2, g_order=3), "paper": dict(order=4)}
    metrics = registry(
        prescribed.PrescribedScene.metrics,
        b_eq27_error=Metric("the largest deviation of |b| on the cross-sections from its "
                            "closed form, eq. (27), relative to that form's largest value"),
        Fe_rotation_deviation=Metric("the largest |Fe^T Fe - I| over the body: zero when the "
                                     "elastic part is a rotation, as eq. (54) says"),
        rotation_rate=Metric("the rate at which the elastic rotation about e3 turns along the "
                             "axis, fitted over the axis", "1/length"),
        rotation_rate_expected=Metric("that rate by eq. (54): -a", "1/length"))

    order: int = ORDER(3)
    maxh: float = MAXH(0.25)
    # as the cube's: a tissue sample of at most a metre, theta at most 1000-fold per mm
    area: float = param(float(np.pi / 4), "cross-section", "length^2",
                         range=f"[{LENGTH_FLOOR ** 2:g}, 1e6]")
    length: float = param(1.0, "length", "length", range=f"[{LENGTH_FLOOR:g}, 1000]")
    a: float = param(0.25, "growth gradient a in theta = 1 + a X2 t", "1/length",
                     range="[-1000, 1000]")

    def mesh_estimate(self) -> tuple[float, str]:
        return (estimate.cylinder_elements(area=self.area, length=self.length, maxh=self.maxh),
                "tet")

    def build(self) -> prescribed.PrescribedCase:
        mesh = cylinder(area=self.area, length=self.length, maxh=self.maxh,
                        curve_order=self.order)
        time = ngs.Parameter(0.0)
        theta = 1 + self.a * ngs.y * time
        f0 = fields.constant("e1")
        growth = FiberGrowth(theta, f0)
        radius = float(np.sqrt(self.area / np.pi))
        e = [fields.constant(k).cf for k in ("e1", "e2", "e3")]

        def verify(problem: GrowthMechanics | None, flds: dict[str, Any]) -> dict[str, float]:
            b = flds["b_e3"]
            expected = inc.burgers_fiber_magnitude(theta, inc.grad_scalar(theta), f0.cf)
            # relative to the largest |b| of eq. (27); absolute for a = 0, where b = 0 exactly
            scale = sampling.maximum(expected, mesh)
            metrics = {"b_eq27_error": sampling.maximum(
                ngs.sqrt((ngs.Norm(b) - expected) ** 2), mesh) / (scale if scale > 0 else 1.0)}
            if problem is None:
                return metrics
            Fe = elastic_part(deformation_gradient(problem.u), growth.Fg)
            stretch = Fe.trans * Fe - ngs.Id(3)
            xs = np.linspace(0, self.length, 21)
            _, along = postprocess.sample_line(mesh, {"Fe": Fe}, (0, radius, radius),
                                               (self.length, radius, radius), n=21)
            F_axis = along["Fe"].reshape(-1, 3, 3)
            angle = np.unwrap(np.arctan2(F_axis[:, 1, 0], F_axis[:, 0, 0]))
            metrics.update({
                "Fe_rotation_deviation": sampling.maximum(ngs.Norm(stretch), mesh),
                "rotation_rate": float(np.polyfit(xs, angle, 1)[0]),
                # eq. (54): Fe = [[cos, sin], [-sin, cos]] with angle a X1, i.e. a rotation
                # about e3 by -a X1 (up to the constant rotation the supports leave)
                "rotation_rate_expected": 0.0 - self.a,
            })
            return metrics

        return prescribed.PrescribedCase(
            scene=self,
            mesh=mesh, growth=growth, material=self.make_material(),
            time=time, planes={"e3": e[2]},
            line=((self.length / 2, 0.0, radius), (self.length / 2, 2 * radius, radius), "X2"),
            components={"S11": ("S", e[0], e[0])},
            verify=verify)
