"""The case of a scene whose growth field is prescribed (eq. 47): theta = theta(X, t).

    growth field -> mechanics (one stage, "growth") -> incompatibility (G, b) -> stresses

G depends on Fg alone (eq. 10): for analytic growth it is evaluated from the exact gradient of
Fg (symbolic differentiation), for growth given as data from the projected path (Fg
interpolated into a high-order H1 space, then Curl); it is compared with the closed form of
section 2.3 where one exists, and with G from the elastic deformation (eq. 12) of the solved
body.
"""

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import ngsolve as ngs
import numpy as np

from ngincompat import config, sampling
from ngincompat.fem import postprocess
from ngincompat.fem.problem import GrowthMechanics, check_formulation
from ngincompat.fem.quadrature import CHECK_DEGREE, QUADRATURES, check_quadrature
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stages import PrescribedGrowthStage
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility import operators as inc
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics.growth import GrowthModel, check_positive
from ngincompat.mechanics.kinematics import deformation_gradient
from ngincompat.mechanics.materials import MaterialKind, NeoHookean
from ngincompat.progress import Progress
from ngincompat.scenes import curvature as curvature_report
from ngincompat.scenes.base import COARSE, LINEAR_SOLVER, Scene, param
from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.material import Elastic
from ngincompat.scenes.metrics import CURVATURE, INCOMPATIBILITY, MECHANICS, Metric, registry
from ngincompat.workflow.pipeline import Solution, solve_stages, timed
from ngincompat.workflow.results import Figure, ProfileFigure, Results

#: Contraction a reused tangent must achieve per Newton iteration. A reused iteration costs a
#: residual and two triangular solves, about a thirtieth of assembling and factorising a fresh
#: tangent at order 5, so a tangent that only halves the residual is still worth keeping; at
#: 0.8 the concave hemisphere stalls and runs out of iterations (the tangents per Newton
#: iteration at each contraction: ``docs/measurements/solver-costs.md``, the prescribed
#: scenes).
REUSE_CONTRACTION = 0.5


@dataclass(eq=False)
class PrescribedCase(SceneCase):
    """What a prescribed-growth scene builds: the case of :mod:`ngincompat.workflow.pipeline`.

    Attributes
    ----------
    scene : PrescribedScene
        The parameters it was built from.
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
    analytic : bool
        theta is an analytic expression (closed forms of G apply); False for growth given as
        data on the mesh.
    expression : str or None
        The text theta was parsed from, when the user gave one: theta > 0 is then proven
        between the sampled points too (:func:`~ngincompat.mechanics.growth.check_positive`).
    """

    scene: "PrescribedScene"
    mesh: ngs.Mesh
    growth: GrowthModel
    material: MaterialKind
    time: ngs.Parameter
    planes: dict
    line: tuple
    fibers: tuple = ()
    dirichlet: str = ""
    symmetry: dict = field(default_factory=dict)
    components: dict = field(default_factory=dict)
    verify: Callable[[GrowthMechanics | None, dict[str, Any]], dict[str, float]] | None = None
    mirror: int = 1
    analytic: bool = True
    expression: str | None = None

    def mechanics(self, linear_solver: str | None = None) -> GrowthMechanics:
        """The scene's mechanics problem (:class:`~ngincompat.fem.problem.GrowthMechanics`), at
        the growth time the case's ``time`` holds, for Newton's ``linear_solver`` (default
        the scene's; "auto" resolved for the problem's size): its energy form on the
        component spaces for a direct solver, on VectorH1 for BDDC."""
        scene = self.scene
        return GrowthMechanics(self.mesh, self.growth, self.material, order=scene.order,
                               fibers=self.fibers, dirichlet=self.dirichlet,
                               symmetry=self.symmetry, formulation=scene.formulation,
                               quadrature=scene.quadrature,
                               linear_solver=linear_solver or scene.linear_solver,
                               coarse=scene.coarse)

    def solve(self, solution: Solution, progress: Progress,
              workdir: Path | None = None) -> None:
        """See :func:`_solve`."""
        _solve(self, solution, progress)

    def measure(self, solution: Solution, progress: Progress) -> Results:
        """See :func:`_measure`."""
        return _measure(self, solution, progress)


#: Poisson's ratio from which the displacement formulation is flagged as locking, at order
#: 4 and above, and below (``docs/measurements/stability.md``, "Where the locking warning
#: starts").
LOCKING_NU, LOW_ORDER_LOCKING_NU = 0.499, 0.49


@dataclass(frozen=True)
class PrescribedScene(Elastic, Scene):
    """A scene with a prescribed growth field; subclasses implement ``build()``.

    Its material is neo-Hookean from mu and nu (:class:`~ngincompat.scenes.material.Elastic`)
    unless a scene says otherwise."""

    formulation: Literal["displacement", "mixed"] = param(
        "displacement", "displacement, or mixed (a condensed pressure against volumetric "
        "locking as nu -> 0.5; neo-Hookean only)")
    reuse_tangent: bool = param(True, "keep the factorised tangent while each Newton "
                                "iteration at least halves the residual (the free hemisphere: "
                                "6 tangents for 18 iterations against 14 fresh ones)")
    linear_solver: str = LINEAR_SOLVER("auto")
    coarse: str = COARSE("edges")
    quadrature: str = param("auto", "rule of energy, residual and tangent: gauss (NGSolve's, "
                            "degree 2 order - 2), or symmetric on tetrahedra (the same degree, "
                            "74 points instead of 216 at order 6, order <= 8; the energy "
                            f"reported is integrated again at degree {CHECK_DEGREE}); auto: "
                            "symmetric on tetrahedra of order 6 to 8, else gauss",
                            choices=QUADRATURES)

    #: Metrics of every prescribed-growth scene; subclasses add their verification metrics.
    metrics = registry(
        MECHANICS, INCOMPATIBILITY, CURVATURE,
        G_error_L2_rel=Metric("the L2 error of the computed G against the closed form of "
                              "eqs. (10), (13), relative to the closed form's norm (growth "
                              "with a closed form only)"),
        G_elastic_vs_growth_L2_rel=Metric(
            "the L2 difference of G computed from the elastic deformation (eq. 12) and from "
            "the growth (eq. 10) of the solved body, relative to the latter: zero in exact "
            "arithmetic"))

    def __post_init__(self) -> None:
        super().__post_init__()
        # every parameter is checked before anything is computed
        check_formulation(self.make_material(), self.formulation, self.order)
        check_quadrature(self.quadrature, self.order)

    def make_material(self) -> MaterialKind:
        """The scene's material (neo-Hookean from mu and nu unless a scene says otherwise)."""
        return NeoHookean.from_nu(self.mu, self.nu)

    def trust(self, results: Results) -> list[str]:
        """A warning when the displacement formulation runs at a Poisson's ratio where it
        locks (:data:`LOCKING_NU` at order 4 and above, :data:`LOW_ORDER_LOCKING_NU` below):
        its stress is too stiff there and Newton needs hundreds of iterations, while the mixed
        form neither locks nor struggles (``docs/measurements/stability.md``, "Where the
        locking warning starts")."""
        if not self.mechanics:
            return []
        limit = LOCKING_NU if self.order >= 4 else LOW_ORDER_LOCKING_NU
        if self.formulation == "displacement" and self.nu >= limit:
            return [f"nu = {self.nu:g} >= {limit} in the displacement formulation at order "
                    f"{self.order}: volumetric locking stiffens the response; use --set "
                    "formulation=mixed"]
        return []


def _solve(case: PrescribedCase, solution: Solution, progress: Progress) -> None:
    """Check theta > 0, build the mechanics (unless the scene asks for incompatibility only)
    and apply the growth in one stage, "growth". Everything runs under NGSolve's TaskManager.
    """
    scene, time = case.scene, case.time
    with config.task_manager():
        with timed(solution.timings, "validate"):
            check_positive(case.growth.theta, case.mesh, time,
                           expression=case.expression)
        if not scene.mechanics:
            # G depends on Fg alone (eq. 10): no mechanics problem is built
            time.Set(1.0)
            return
        with progress.phase("setting up the mechanics"), timed(solution.timings, "setup"):
            problem = case.mechanics()
        solution.state = problem
        time.Set(0.0)
        options = NewtonOptions(steps=scene.steps, reuse_tangent=scene.reuse_tangent,
                                reuse_contraction=REUSE_CONTRACTION,
                                linear_solver=scene.linear_solver)
        solve_stages([PrescribedGrowthStage("growth", problem, time, options)], progress,
                     solution)


def _measure(case: PrescribedCase, solution: Solution, progress: Progress) -> Results:
    """G and b (exact or projected path), stresses and the scene's checks, profiles, figures.

    A run that did not converge is measured in its last converged state."""
    scene, mesh, growth = case.scene, case.mesh, case.growth
    problem = solution.state
    results = case.interrupted(solution)
    timings = results.timings
    with config.task_manager():
        with progress.phase("incompatibility"), timed(timings, "incompatibility"):
            measured, fields, metrics = _incompatibility(scene, case, problem)
        if "curvature" in scene.output_set():
            with progress.phase("curvature"), timed(timings, "curvature"):
                metrics.update(_curvature(case, measured, fields))
        with progress.phase("stresses and profiles"), timed(timings, "postprocess"):
            fields["theta"] = growth.theta
            if problem is not None:
                metrics.update(_mechanics(case, problem, fields))
            if case.verify is not None:
                metrics.update(case.verify(problem, fields))
            start, end, coord = case.line
            sampled = [k for k in ("theta", "Psi", "curlFg_sq", "scalar_curvature",
                                   "einstein_norm_g", *case.components,
                                   *(f"|b_{label}|" for label in case.planes)) if k in fields]
            s, values = postprocess.sample_line(mesh, {k: fields[k] for k in sampled},
                                                start, end)
    results.metrics = metrics
    results.fields = fields
    results.profiles = {"line": {coord: np.asarray(start)[_axis(start, end)] + s, **values}}
    results.figures = _figures(scene, coord, case, problem is not None)
    if "curvature" in scene.output_set():
        curvature_report.report(scene, results, coord,
                                {f"|b| on {label}": f"|b_{label}|" for label in case.planes})
    return results


def _curvature(case: PrescribedCase, measured: Incompatibility,
               fields: dict[str, Any]) -> dict[str, float]:
    """The curvature of Cg: exact path for analytic growth; for growth given as data, the
    Regge path of degree 2 on the continuous interpolant of Fg that G is computed from
    (``measured.Fg_h``, the incompatibility's). Adds S and |Ein|_g to the fields, returns
    the metrics."""
    Fg = measured.Fg if case.analytic else measured.Fg_h
    extra, metrics = cv.measure_growth(Fg, case.mesh, fields["G"], exact=case.analytic,
                                       mirror=case.mirror)
    fields.update(extra)
    return metrics


def _mechanics(case: PrescribedCase, problem: GrowthMechanics,
               fields: dict[str, Any]) -> dict[str, float]:
    """Stress fields and metrics of the solved body; adds the fields, returns the metrics."""
    stress = postprocess.stresses(problem.energy_density, problem.u)
    F = deformation_gradient(problem.u)
    Fg = case.growth.Fg
    # compiled: the stress is evaluated once per point for the VTK interpolants
    fields.update({"u": problem.u, "Psi": (stress["W"] / case.growth.Jg).Compile(),
                   "sigma_max_principal": postprocess.largest_principal_value(stress["sigma"]),
                   **{k: stress[k].Compile() for k in ("P", "S", "sigma")},
                   "Fg": Fg, "Fe": (F * ngs.Inv(Fg)).Compile(), "J": ngs.Det(F),
                   "Je": (ngs.Det(F) / case.growth.Jg).Compile()})
    for label, (tensor, a, b) in case.components.items():
        fields[label] = postprocess.component(stress[tensor], a, b).Compile()
    # a cheaper rule's energy is integrated again: a mode it does not see would show there
    degree = None if problem.quadrature == "gauss" else CHECK_DEGREE
    return {"strain_energy": case.mirror * problem.strain_energy(degree),
            "max_principal_stress": sampling.maximum(fields["sigma_max_principal"],
                                                        case.mesh)}


def _figures(scene: PrescribedScene, coord: str, case: PrescribedCase,
             mechanics: bool) -> list[Figure]:
    """The profile figures of a scene, in its units, titled with its variant."""
    L, stress = scene.units["length"], scene.units["stress"]
    title = scene.title()
    xlabel = f"{coord} [{L}]"
    curl = {"Curl Fg : Curl Fg": "curlFg_sq"}
    curl_label = f"Curl $F^g$ : Curl $F^g$ [1/{L}$^2$]"
    mu = case.material.mu
    if mechanics:
        # floors from the stress scale mu: 1e-3 mu for stresses, 1e-6 mu for energy densities
        figures: list[Figure] = [ProfileFigure("profile.png", coord, xlabel, {r"$\Psi$": "Psi"},
                                 rf"$\Psi$ [{stress}]", f"{title}: energy and incompatibility",
                                 right=curl, right_label=curl_label, floor=1e-6 * mu)]
    else:
        figures = [ProfileFigure("profile.png", coord, xlabel, curl, curl_label,
                                 f"{title}: incompatibility")]
    if case.planes:
        figures.append(ProfileFigure("burgers.png", coord, xlabel,
                                     {f"|b| on {label}": f"|b_{label}|" for label in case.planes},
                                     f"|b| [1/{L}]", f"{title}: Burgers vectors"))
    if case.components and mechanics:
        figures.append(ProfileFigure("stress.png", coord, xlabel, {k: k for k in case.components},
                                     f"stress [{stress}]", f"{title}: residual stress",
                                     floor=1e-3 * mu))
    return figures


def _incompatibility(scene: PrescribedScene, case: PrescribedCase, problem: GrowthMechanics | None
                     ) -> tuple[Incompatibility, dict[str, Any], dict[str, float]]:
    """The measured incompatibility
    (:class:`~ngincompat.incompatibility.measure.Incompatibility`), its fields, and G's
    checks: the closed form where there is one, and G from the elastic deformation (eq. 12)
    of the solved body.

    The reference gradient of Fg is exact for analytic growth (symbolic differentiation, so G
    costs an evaluation where it is needed) and that of its H1 interpolant of ``g_order`` for
    growth given as data. Eq. (12) takes the gradient of Fe^-1 = Fg F^-1 from that of Fg and
    the second derivatives of the displacement (no projection either)."""
    mesh, growth = case.mesh, case.growth
    Fg = growth.Fg
    measured = (Incompatibility.exact(Fg, case.planes) if case.analytic
                else Incompatibility.projected(Fg, mesh, scene.g_order, case.planes))
    fields = measured.fields()
    G, dFg = fields["G"], measured.dFg
    metrics = {"burgers_max": measured.burgers_max(mesh)}
    exact = growth.closed_form_G() if case.analytic else None
    if exact is None:
        metrics["G_norm_L2"] = measured.norm_L2(mesh, 10, scale=case.mirror)
    else:       # ||G||_L2 of the closed form
        metrics["G_error_L2_rel"] = inc.relative_l2_error(G, exact, mesh)
        metrics["G_norm_L2"] = (case.mirror * ngs.Integrate(ngs.InnerProduct(exact, exact),
                                                            mesh, order=10)) ** 0.5
    if problem is not None:
        F = deformation_gradient(problem.u)
        dF = problem.u.Operator("hesse").Reshape((3, 3, 3))
        G_e = inc.incompatibility_from_elastic(*inc.inverse_elastic_gradient(Fg, dFg, F, dF), F)
        # order 6: the value of order 10 to two digits (round-off of ~1e-10 on the hemisphere)
        # at a ninth of the cost
        metrics["G_elastic_vs_growth_L2_rel"] = inc.relative_l2_error(G_e.Compile(), G, mesh,
                                                                      order=6)
    return measured, fields, metrics


def _axis(start: Sequence[float], end: Sequence[float]) -> int:
    return int(np.argmax(np.abs(np.asarray(end, float) - np.asarray(start, float))))
