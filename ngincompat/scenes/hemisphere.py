"""The hemisphere of section 3.2: isotropic growth driven by a radial field."""

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import ngsolve as ngs
import numpy as np

from geometries import estimate, hemisphere
from ngincompat import sampling
from ngincompat.errors import require
from ngincompat.fem import postprocess
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.references.radial import RadialSolution, solve_radial
from ngincompat.scenes import prescribed
from ngincompat.scenes.base import LENGTH_FLOOR, MAXH, ORDER, STEPS, param
from ngincompat.scenes.metrics import Metric, registry

#: The growth profiles f(R / R0) of Fig. 2f: f(0) = 0, f(1) = 1, as (CF builder, numpy).
PROFILES = {
    "linear": (lambda s: s, lambda s: s),
    "concave": (lambda s: 2 * s - s * s, lambda s: 2 * s - s * s),  # rapid near the core
    "convex": (lambda s: s * s, lambda s: s * s),                   # rapid near the surface
}


@dataclass(frozen=True)
class HemisphereScene(prescribed.PrescribedScene):
    """Half ball R0 = 1 mm, theta = 1 + f(R / R0) t / 4 (Table 1), neo-Hookean mu = 0.55 MPa,
    nu = 0.4.

    ``flat_face = free`` is the paper's setting (rigid-body constraints only);
    ``flat_face = symmetry`` removes the normal displacement of the flat face, which makes the
    body exactly half of a growing ball: the Cauchy stresses are then checked against the
    independent 1-D radial solution (:mod:`ngincompat.references.radial`).

    Body, growth and material are symmetric about the planes X1 = 0 and X2 = 0, so
    ``model = "quarter"`` solves the quarter X1, X2 >= 0 with the normal displacement held on
    those planes: the same solution at a quarter of the unknowns (integrals such as the strain
    energy are reported for the whole hemisphere). Burgers vectors are reported on
    the radial, meridional and circumferential planes (Fig. 2b, 2c); profiles along the ray
    (1, 1, 1) / sqrt(3) from the centre (Fig. 2d-2h).
    """

    name = "hemisphere"
    summary = "section 3.2: radial isotropic growth of a half ball (linear/concave/convex)"
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=0.5, centre_maxh=0.25, order=2, g_order=3),
               "paper": dict(maxh=0.4)}
    variant = ("profile", "flat_face", "model")
    metrics = registry(
        prescribed.PrescribedScene.metrics,
        b_radial_rel=Metric("the largest |b| on the radial planes relative to the largest on "
                            "the meridional plane: zero in section 3.2"),
        b_meridional_off_circumferential=Metric(
            "the largest part of b on the meridional plane off the circumferential direction, "
            "relative to the largest |b| there: zero in section 3.2"),
        b_circumferential_off_meridional=Metric(
            "the largest part of b on the circumferential plane off the meridional direction, "
            "relative to the largest meridional |b|: zero in section 3.2"),
        **{f"radial_sigma_{c}_error": Metric(
            f"the largest deviation of the Cauchy stress sigma_{c} along a ray from the 1-D "
            "radial solution (ngincompat.references.radial), relative to that solution's "
            "largest stress (symmetric flat face only)")
           for c in ("rr", "thetatheta", "phiphi")})

    order: int = ORDER(5)
    maxh: float = MAXH(0.5)
    steps: int = STEPS(2, help="initial number of load steps (two take 4 Newton iterations "
                               "each, one 7-9)")
    centre_maxh: float = param(0.05, "mesh size at the centre (theta has a cone point there)",
                               "length", range=f"[{LENGTH_FLOOR:g}, 1000]")
    R0: float = param(1.0, "radius", "length", range=f"[{LENGTH_FLOOR:g}, 1000]")
    profile: str = param("linear", "growth profile f: linear, concave or convex",
                         choices=PROFILES)
    flat_face: Literal["free", "symmetry"] = param("free", "flat face: free (the paper's) "
                                                   "or symmetry")
    model: Literal["full", "quarter"] = param("full", "full hemisphere, or quarter (mirror "
                                              "planes X1 = 0, X2 = 0)")

    def __post_init__(self) -> None:
        super().__post_init__()
        require(self.centre_maxh <= self.maxh, "centre_maxh", self.centre_maxh,
                f"in (0, maxh = {self.maxh}]")

    def mesh_estimate(self) -> tuple[float, str]:
        return (estimate.hemisphere_elements(R0=self.R0, maxh=self.maxh,
                                             centre_maxh=self.centre_maxh,
                                             quarter=self.model == "quarter"), "tet")

    def build(self) -> prescribed.PrescribedCase:
        quarter = self.model == "quarter"
        mesh = hemisphere(R0=self.R0, maxh=self.maxh, curve_order=self.order,
                          centre_maxh=self.centre_maxh, quarter=quarter)
        time = ngs.Parameter(0.0)
        X = ngs.CF((ngs.x, ngs.y, ngs.z))
        R = ngs.Norm(X)
        f_cf, f_np = PROFILES[self.profile]
        growth = IsotropicGrowth(1 + f_cf(R / self.R0) * time / 4)
        basis = spherical_basis()
        material = self.make_material()
        ray = np.ones(3) / np.sqrt(3)

        def verify(problem: GrowthMechanics | None, fields: dict[str, Any]) -> dict[str, float]:
            metrics = burgers_alignment(fields, basis, mesh)
            if metrics and problem is not None and self.flat_face == "symmetry":
                # the scene's material is neo-Hookean (PrescribedScene.make_material)
                reference = solve_radial(lambda r: 1 + f_np(r / self.R0) / 4,
                                         material.mu, material.lam, R0=self.R0)
                metrics.update(radial_errors(reference, fields, mesh, ray, self.R0))
            return metrics
        return prescribed.PrescribedCase(
            scene=self,
            mesh=mesh, growth=growth, material=material, time=time,
            planes={"radial": basis["r"], "meridional": basis["phi"],
                    "circumferential": basis["theta"]},
            line=((0.0, 0.0, 0.0), tuple(self.R0 * ray), "R"),
            symmetry={**({"flat": "z"} if self.flat_face == "symmetry" else {}),
                      **({"xmirror": "x", "ymirror": "y"} if quarter else {})},
            mirror=4 if quarter else 1,
            components={"sigma_rr": ("sigma", basis["r"], basis["r"]),
                        "sigma_thetatheta": ("sigma", basis["theta"], basis["theta"]),
                        "sigma_phiphi": ("sigma", basis["phi"], basis["phi"])},
            verify=verify)


def spherical_basis() -> dict[str, ngs.CoefficientFunction]:
    """Unit vectors e_r (radial), e_theta (circumferential, about e3) and e_phi (meridional)
    as CoefficientFunctions; undefined on the e3 axis (regularised there)."""
    X = ngs.CF((ngs.x, ngs.y, ngs.z))
    e_r = X / (ngs.Norm(X) + 1e-30)
    around = ngs.Cross(ngs.CF((0, 0, 1)), X)
    e_theta = around / (ngs.Norm(around) + 1e-30)
    return {"r": e_r, "theta": e_theta, "phi": ngs.Cross(e_theta, e_r)}


def burgers_alignment(fields: Mapping[str, ngs.CoefficientFunction],
                      basis: Mapping[str, ngs.CoefficientFunction],
                      mesh: ngs.Mesh) -> dict[str, float]:
    """How far b is from the directions of section 3.2, relative to the largest |b|: zero on
    radial planes, circumferential on the meridional plane, meridional on the circumferential
    plane (measured away from the e3 axis, where the basis is undefined). Empty where b
    vanishes (a state that never grew: a first step that failed), where no direction is
    defined."""
    away = ngs.IfPos(ngs.x * ngs.x + ngs.y * ngs.y - 0.01, 1.0, 0.0)
    scale = sampling.maximum(ngs.Norm(fields["b_meridional"]), mesh)
    if not scale > 0:
        return {}

    def off(b: ngs.CoefficientFunction, direction: ngs.CoefficientFunction) -> float:
        rest = b - ngs.InnerProduct(b, direction) * direction
        return sampling.maximum(away * ngs.Norm(rest), mesh) / scale

    return {
        "b_radial_rel": sampling.maximum(away * ngs.Norm(fields["b_radial"]), mesh) / scale,
        "b_meridional_off_circumferential": off(fields["b_meridional"], basis["theta"]),
        "b_circumferential_off_meridional": off(fields["b_circumferential"], basis["phi"]),
    }


def radial_errors(reference: RadialSolution, fields: Mapping[str, ngs.CoefficientFunction],
                  mesh: ngs.Mesh, ray: np.ndarray, R0: float,
                  radii: np.ndarray = np.linspace(0.1, 0.95, 35)) -> dict[str, float]:
    """Largest deviation of the Cauchy stresses from the 1-D radial solution along ``ray``,
    relative to the largest stress, for R / R0 in [0.1, 0.95] (the centre is a cone point of
    the linear and concave profiles)."""
    R = radii * R0
    pts = np.outer(R, ray)
    _, fe = postprocess.sample_line(mesh, {k: fields[k] for k in
                                           ("sigma_rr", "sigma_thetatheta", "sigma_phiphi")},
                                    pts[0], pts[-1], n=len(R))
    srr, stt = reference.cauchy(R)
    scale = max(np.max(np.abs(srr)), np.max(np.abs(stt)))
    return {
        "radial_sigma_rr_error": float(np.max(np.abs(fe["sigma_rr"] - srr)) / scale),
        "radial_sigma_thetatheta_error":
            float(np.max(np.abs(fe["sigma_thetatheta"] - stt)) / scale),
        "radial_sigma_phiphi_error": float(np.max(np.abs(fe["sigma_phiphi"] - stt)) / scale),
    }
