"""The folding scene's measures of a solved case: the folds, the contact, the stresses before
and after the release, the incompatibility, and the section and depth profiles of Fig. 7."""

from collections.abc import Mapping
from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat import sampling
from ngincompat.fem import postprocess
from ngincompat.fem.shape import sulci
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics import kinematics
from ngincompat.mechanics.growth import FiberGrowth
from ngincompat.progress import Progress
from ngincompat.sampling import element_points
from ngincompat.scenes.folding.figures import DEPTH_FIELDS, PANELS, figures
from ngincompat.workflow.pipeline import Solution, timed
from ngincompat.workflow.results import Results


def measure(case: Any, solution: Solution, progress: Progress) -> Results:
    """The record of the solved ``case`` (a :class:`~ngincompat.scenes.folding.case.FoldingCase`)
    with its metrics, fields, profiles and figures."""
    results = case.interrupted(solution)
    results.profiles = {branch: {k: np.array(v) for k, v in series.items()}
                        for branch, series in case.series.items() if series["t"]}
    if case.series["buckling"]["t"] and solution.converged:
        _, u2 = case.top_profile(case.grown_u)    # of the final equilibrium
        results.metrics["fold_amplitude"] = float(np.ptp(u2) / 2)
        count, depth = sulci(u2)
        results.metrics.update(sulci=count, sulcus_depth=depth)
    stretches = case.series["perfect"]["stretch"] + case.series["buckling"]["stretch"]
    if stretches:
        results.metrics["top_stretch_min"] = min(stretches)
    flds = {"u": case.grown_u, "theta": case.growth.theta,
            **stresses(case, case.growth, case.grown_u, "", results.metrics)}
    results.metrics["strain_energy"] = strain_energy(case, case.grown_u)
    results.metrics.update(contact_metrics(case, solution))
    if case.released and solution.converged:
        flds["u_released"] = case.problem.u
        flds.update(stresses(case, case.growth, case.problem.u, "_released",
                             results.metrics))
        results.metrics["top_curvature_released"] = case.top_curvature(case.problem.u)
        results.metrics["strain_energy_released"] = strain_energy(case, case.problem.u)
    if case.mode is not None:
        flds["buckling_mode"] = case.mode
        x, w = case.top_profile(case.mode)
        results.profiles["mode"] = {"X1": x, "u2": w}
    with progress.phase("incompatibility"), timed(results.timings, "incompatibility"):
        flds.update(incompatibility(case))
        results.metrics.update(burgers_metrics(case, flds["|b|"]))
        results.metrics["burgers_interface_mean"] = interface_mean(case, flds["|b|"])
    mesh = case.mesh
    results.metrics["theta_a_max"] = sampling.maximum(flds["theta_a"], mesh)
    with progress.phase("sampling"), timed(results.timings, "sampling"):
        results.profiles["section"] = section(case, flds)
        results.profiles["depth"] = depth_profile(case, flds)
    results.fields = flds
    results.figures = figures(case.scene, results.profiles)
    return results


def contact_metrics(case: Any, solution: Solution) -> dict[str, float]:
    """``Je_min`` over the records of the growth and the final states (grown and, if
    released, released), the final grown state's
    ``self_contact_area`` (length of the top line in contact) and the largest
    ``self_contact_penetration_max`` of the records and those states."""
    final = case.contact.measures() if case.grown_contact is None else case.grown_contact
    jacobians = [case.elastic_jacobian_min(case.growth, case.grown_u)]
    penetrations = [final["self_contact_penetration_max"]]
    for series in case.series.values():
        jacobians += series["Je_min"]
        penetrations += series["penetration"]
    if case.released and solution.converged:
        jacobians.append(case.elastic_jacobian_min(case.growth, case.problem.u))
        penetrations.append(case.contact.measures()["self_contact_penetration_max"])
    return {"Je_min": min(jacobians), "self_contact_area": final["self_contact_area"],
            "self_contact_penetration_max": max(penetrations)}


def strain_energy(case: Any, u: ngs.GridFunction) -> float:
    """The strain energy per unit depth of the section at the displacement ``u`` and
    the current growth, int Jg Psi(F Fg^-1) dA (eq. 36): the residual stress's energy
    after the release, where the largest principal stress is a value at one point."""
    density = case.growth.energy_density(kinematics.deformation_gradient(u))
    return float(ngs.Integrate(density, case.mesh, order=2 * case.scene.order))


def interface_mean(case: Any, cf: ngs.CoefficientFunction) -> float:
    """The mean of ``cf`` over the band of one cortex thickness centred on the interface
    (reference X2 within cortex_thickness / 2 of it)."""
    s = case.scene
    interface = s.height - s.cortex_thickness
    band = ngs.IfPos(s.cortex_thickness / 2 - ngs.sqrt((ngs.y - interface) ** 2), 1.0, 0.0)
    return float(ngs.Integrate(band * cf, case.mesh, order=6)
                 / (s.cortex_thickness * s.length))


def incompatibility(case: Any) -> dict[str, ngs.CoefficientFunction]:
    """theta_a and the incompatibility of the current growth on the paper's plane normal
    to e3 (projected path: :class:`~ngincompat.incompatibility.measure.Incompatibility`)."""
    theta = case.growth.theta
    measured = Incompatibility.projected(FiberGrowth(theta, case.f0).Fg, case.mesh,
                                         case.scene.g_order, {"e3": (0, 0, 1)})
    return {"theta_a": case.mesh.MaterialCF({"subcortex": theta, "cortex": 1.0}),
            **measured.fields()}


def stresses(case: Any, growth: GrowthEnergy, u: ngs.GridFunction, suffix: str,
             metrics: dict[str, float]) -> dict[str, ngs.CoefficientFunction]:
    """The Cauchy stress of the growth term ``growth`` at the displacement ``u`` and its
    largest principal value (fields
    ``sigma``, ``sigma_max`` + ``suffix``); into ``metrics`` that value's maximum over
    the integration points and vertices (``max_principal_stress`` + ``suffix``) and the
    reference depth below the top surface where it is reached (``peak_tension_depth``
    + ``suffix``)."""
    sigma = postprocess.stresses(growth.energy_density, u)["sigma"]
    largest = postprocess.largest_principal_value(sigma)
    points = element_points(case.mesh, 4)
    values = np.asarray(largest(points)).ravel()
    peak = int(np.nanargmax(values))
    metrics[f"max_principal_stress{suffix}"] = float(values[peak])
    metrics[f"peak_tension_depth{suffix}"] = float(
        case.scene.height - np.asarray(ngs.y(points)).ravel()[peak])
    return {f"sigma{suffix}": sigma, f"sigma_max{suffix}": largest}


def burgers_metrics(case: Any, b_norm: ngs.CoefficientFunction) -> dict[str, float]:
    """The largest |b|, its depth below the top and its X1."""
    value, where = sampling.argmax(b_norm, case.mesh)
    return {"burgers_max": value, "burgers_max_depth": case.scene.height - where[1],
            "burgers_max_X1": where[0]}


def section(case: Any, flds: Mapping[str, Any], n: int = 241,
            band: float = 5) -> dict[str, np.ndarray]:
    """The fields of ``PANELS`` that ``flds`` has on the section, on a grid of n
    columns over the length and rows refined in the top ``band`` cortical thicknesses
    (40 rows there, 30 below); displacements as their (u1, u2)."""
    s = case.scene
    top = max(s.height - band * s.cortex_thickness, 0.0)
    x1 = np.linspace(0.0, s.length, n)
    x2 = np.unique(np.concatenate([np.linspace(0.0, top, 30),
                                   np.linspace(top, s.height, 41)]))
    keys = {k for pair in PANELS.values() for k in pair if all(p in flds for p in pair)}
    sampled = postprocess.sample_plane(case.mesh, {k: flds[k] for k in keys},
                                       (0.0, 0.0, 0.0), (1, 0, 0), (0, 1, 0), x1, x2)
    return {"X1": x1, "X2": x2, **sampled}


def depth_profile(case: Any, flds: Mapping[str, Any], n: int = 401) -> dict[str, np.ndarray]:
    """``DEPTH_FIELDS`` along the vertical through the middle, from the top down."""
    s = case.scene
    depth, values = postprocess.sample_line(
        case.mesh, {k: flds[k] for k in DEPTH_FIELDS if k in flds},
        (s.length / 2, s.height), (s.length / 2, 0.0), n=n)
    return {"depth": depth, **values}
