"""The pipeline of a scene whose growth field is prescribed (eq. 47): theta = theta(X, t).

    growth field -> mechanics (solve) -> incompatibility (G, b) -> stresses -> outputs

G depends on Fg alone (eq. 10): it is computed by the projected path (Fg interpolated into a
high-order H1 matrix space, then Curl), compared with the closed form of section 2.3 where one
exists, and with G from the elastic deformation (eq. 12) of the solved body.
"""

import logging
import time as _time
from dataclasses import dataclass, field
from pathlib import Path

import ngsolve as ngs
import numpy as np

from .. import incompatibility as inc
from .. import io, plots, postprocess
from ..errors import ConvergenceError, require
from ..growth import check_positive
from ..kinematics import deformation_gradient, elastic_part
from ..problem import GrowthMechanics
from ..solver import NewtonOptions, solve_growth
from .base import Scene, param, timed

log = logging.getLogger(__name__)


@dataclass(eq=False)
class PrescribedCase:
    """Everything a prescribed-growth scene hands to :func:`run`.

    Attributes
    ----------
    mesh : ngsolve.Mesh
    growth : growth model whose theta depends on ``time``
    material : material
    time : ngsolve.Parameter
    planes : dict
        label -> unit normal (intermediate configuration) of the planes on which Burgers vectors
        are reported.
    line : tuple
        (start, end, label): the profile line and the name of its coordinate.
    fibers : tuple of DirectionField
        Reference fiber directions for anisotropic materials.
    dirichlet : str
        Clamped boundaries (empty: traction-free, rigid-body motions removed).
    symmetry : dict
        Symmetry planes, boundary name -> normal axis (see ``GrowthMechanics``).
    components : dict
        label -> (tensor, a, b): the component a . T b of T = "S" (second Piola-Kirchhoff) or
        "sigma" (Cauchy), reported as a field and along the profile line.
    verify : callable, optional
        ``verify(problem, fields) -> dict`` of scene-specific verification metrics (errors
        against closed forms or reference solutions); ``problem`` is None when the scene
        was asked for incompatibility only.
    mirror : int
        How many mirror copies of the mesh make the body (4 for a quarter model): integrals
        over the body (strain energy, norm of G) are reported for the whole body.
    """

    mesh: ngs.Mesh
    growth: object
    material: object
    time: ngs.Parameter
    planes: dict
    line: tuple
    fibers: tuple = ()
    dirichlet: str = ""
    symmetry: dict = field(default_factory=dict)
    components: dict = field(default_factory=dict)
    verify: object = None
    mirror: int = 1


@dataclass(frozen=True)
class PrescribedScene(Scene):
    """A scene with a prescribed growth field; subclasses implement ``build()``."""

    formulation: str = param("displacement", "displacement, or mixed (a condensed pressure "
                             "against volumetric locking as nu -> 0.5; neo-Hookean only)")
    reuse_tangent: bool = param(False, "keep the factorised tangent while Newton contracts "
                                "tenfold per iteration (cheaper at high order)")

    def __post_init__(self):
        super().__post_init__()
        require(self.formulation in ("displacement", "mixed"), "formulation",
                self.formulation, "displacement or mixed")

    def build(self):
        """Return the scene's :class:`PrescribedCase` (mesh included)."""
        raise TypeError(f"{type(self).__name__} must define build()")

    def run(self, out, quiet=True):
        """Build, solve, measure and write the scene into the folder ``out``."""
        start = _time.perf_counter()
        case = self.build()
        return run(self, case, out, quiet=quiet, mesh_seconds=_time.perf_counter() - start)


def run(scene, case, out, quiet=True, mesh_seconds=0.0):
    """Solve, measure and write a prescribed-growth scene; returns the results dict.

    On a :class:`ConvergenceError` the results of the last converged state are written (with
    ``solver.converged = false`` and the error) before the error is raised again. Everything
    runs under NGSolve's TaskManager (all cores: element loops, projections, integrals).
    """
    with ngs.TaskManager():
        return _run(scene, case, Path(out), quiet, mesh_seconds)


def _run(scene, case, out, quiet, mesh_seconds):
    timings = {"mesh": mesh_seconds}
    mesh, growth, time = case.mesh, case.growth, case.time
    with timed(timings, "validate"):
        check_positive(growth.theta, mesh, time)
    results = {"scene": scene.name, "params": scene.settings(), "units": scene.units,
               **io.provenance(),
               "mesh": {"ne": mesh.ne, "nv": mesh.nv, "order": scene.order,
                        "maxh": scene.maxh}}
    problem, error = None, None
    if scene.mechanics:
        with timed(timings, "setup"):
            problem = GrowthMechanics(mesh, growth, case.material, order=scene.order,
                                      fibers=case.fibers, dirichlet=case.dirichlet,
                                      symmetry=case.symmetry, formulation=scene.formulation)
        with timed(timings, "solve"):
            time.Set(0.0)
            try:
                options = NewtonOptions(steps=scene.steps, reuse_tangent=scene.reuse_tangent)
                history = solve_growth(problem, time, options, quiet=quiet)
            except ConvergenceError as err:
                history, error = err.history, err
        results["mesh"]["ndof"] = problem.ndof
        results["solver"] = history.as_dict()
        if error is not None:
            results["error"] = str(error)
    else:
        # G depends on Fg alone (eq. 10): no mechanics problem is built
        time.Set(1.0)

    with timed(timings, "incompatibility"):
        fields, metrics = _incompatibility(scene, case, problem)
    with timed(timings, "postprocess"):
        fields["theta"] = growth.theta
        if problem is not None:
            metrics.update(_mechanics(case, problem, fields))
        if case.verify is not None:
            metrics.update(case.verify(problem, fields))
        start, end, coord = case.line
        sampled = [k for k in ("theta", "Psi", "curlFg_sq", *case.components,
                               *(f"|b_{label}|" for label in case.planes)) if k in fields]
        s, values = postprocess.sample_line(mesh, {k: fields[k] for k in sampled}, start, end)
        profile = {coord: np.asarray(start)[_axis(start, end)] + s, **values}
        results["profiles"] = {"line": profile}
    results["metrics"] = metrics

    with timed(timings, "output"):
        wanted = scene.output_set()
        results["files"] = ["results.json"]
        if "vtk" in wanted:
            vtk_fields = {k: v for k, v in fields.items() if k != "G"}
            io.write_vtk(out / "fields.vtu", mesh, vtk_fields, subdivision=2)
            results["files"].append("fields.vtu")
        if "figures" in wanted:
            results["files"] += _figures(scene.name, out, profile, coord, case)
    results["timings"] = timings
    io.write_json(out / "results.json", results)
    if error is not None:
        raise error
    return results


def _mechanics(case, problem, fields):
    """Stress fields and metrics of the solved body; adds the fields, returns the metrics."""
    stress = postprocess.stresses(problem.energy_density, problem.u)
    fields.update({"u": problem.u, "Psi": stress["W"] / case.growth.Jg,
                   "sigma_max_principal": postprocess.principal_values(stress["sigma"])[2]})
    for label, (tensor, a, b) in case.components.items():
        fields[label] = postprocess.component(stress[tensor], a, b)
    return {"strain_energy": case.mirror * problem.strain_energy(),
            "max_principal_stress": postprocess.maximum(fields["sigma_max_principal"],
                                                        case.mesh)}


def _figures(name, out, profile, coord, case):
    """The profile figures of a scene; returns the file names written."""
    x = profile[coord]
    xlabel = f"{coord} [mm]"
    curl = (r"Curl $F^g$ : Curl $F^g$ [1/mm$^2$]", profile["curlFg_sq"])
    if "Psi" in profile:
        plots.profile_pair(out / "profile.png", x, (r"$\Psi$ [MPa]", profile["Psi"]), curl,
                           xlabel=xlabel, title=f"{name}: energy and incompatibility")
    else:
        plots.profiles(out / "profile.png", x, {curl[0]: curl[1]}, xlabel=xlabel,
                       ylabel=curl[0], title=f"{name}: incompatibility")
    files = ["profile.png"]
    if case.planes:
        plots.profiles(out / "burgers.png", x,
                       {f"|b| on {label}": profile[f"|b_{label}|"] for label in case.planes},
                       xlabel=xlabel, ylabel="|b| [1/mm]", title=f"{name}: Burgers vectors")
        files.append("burgers.png")
    if case.components and all(k in profile for k in case.components):
        plots.profiles(out / "stress.png", x, {k: profile[k] for k in case.components},
                       xlabel=xlabel, ylabel="stress [MPa]", title=f"{name}: residual stress")
        files.append("stress.png")
    return files


def _incompatibility(scene, case, problem):
    """G by the projected path; its errors against the closed form and against eq. (12)."""
    mesh, growth = case.mesh, case.growth
    Fg = growth.Fg
    curl_Fg, _ = inc.curl_projected(Fg, mesh, scene.g_order)
    G = inc.incompatibility_tensor(Fg, curl_Fg)
    fields = {"G": G, "curlFg_sq": inc.curl_norm_squared(curl_Fg)}
    metrics = {}
    norms = []
    for label, n in case.planes.items():
        b = inc.burgers_vector(G, n)
        fields[f"b_{label}"] = b
        fields[f"|b_{label}|"] = ngs.Norm(b)
        norms.append(postprocess.maximum(ngs.Norm(b), mesh))
    metrics["burgers_max"] = max(norms) if norms else 0.0
    exact = inc.closed_form_G(growth)
    if exact is not None:
        metrics["G_error_L2_rel"] = inc.relative_l2_error(G, exact, mesh)
        metrics["G_norm_L2"] = (case.mirror * ngs.Integrate(ngs.InnerProduct(exact, exact), mesh,
                                                            order=10)) ** 0.5
    if problem is not None:
        F = deformation_gradient(problem.u)
        Fe_inv = ngs.Inv(elastic_part(F, Fg))
        G_e = inc.incompatibility_from_elastic(*inc.project_tensor(Fe_inv, mesh, scene.g_order),
                                               F)
        metrics["G_elastic_vs_growth_L2_rel"] = inc.relative_l2_error(G_e, G, mesh)
    return fields, metrics


def _axis(start, end):
    return int(np.argmax(np.abs(np.asarray(end, float) - np.asarray(start, float))))
