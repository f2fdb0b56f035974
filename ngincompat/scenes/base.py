"""What every scene shares: typed parameters settable by name, their validation, and the
entry to the pipeline.

A scene is a frozen dataclass. Its fields are its parameters, each with its type (the
annotation) and a declaration (:class:`~ngincompat.parameters.Param`: help, unit, allowed
range); ``Scene.from_settings`` builds one from ``KEY=VALUE`` strings (the command line's
``--set``) or values, and every value, a Python keyword argument too, is converted to its
parameter's type and checked against its range before the scene's own checks (those that
relate several parameters) in ``__post_init__``. ``scene.build()`` returns its case (see
:mod:`ngincompat.workflow.pipeline`); ``scene.run(out=None)`` runs the whole pipeline and returns
the :class:`~ngincompat.workflow.results.Results`, writing files only when ``out`` is given.
"""

import os
import sys
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Self

import ngsolve as ngs

from ngincompat import parallel
from ngincompat.errors import ParameterError, require
from ngincompat.fem.problem import COARSE_SPACES, mixed_unknowns_per_element
from ngincompat.fem.solver import ITERATIVE_NDOF, LINEAR_SOLVERS
from ngincompat.parameters import (
    PRESETS,
    Outputs,
    Param,
    Parameter,
    convert_fields,
    declarations,
    param,
    to_json,
)
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes import trust
from ngincompat.scenes.metrics import Metric, registry
from ngincompat.workflow import io, pipeline
from ngincompat.workflow.results import MeshInfo, Results

#: Physical lower bounds, in a scene's own units (mm or cm, MPa or kPa, its time unit): a
#: value below them is no tissue, and the meshing and solving beneath it break in their own
#: ways (an OCC or Netgen error, a singular matrix, a division by zero in a metric). A length
#: at least 1e-3 (1 um in mm, 10 um in cm: a cell, below which tissue is no continuum); a
#: modulus at least 1e-6 (1 Pa in MPa, softer than any tissue: brain is about 1 kPa); a time
#: at least 1e-3 of the scene's unit (a minute and a half of a day: growth takes days); a rate
#: at least 1e-6 per time unit (a millionth of the growth per day or year: none at all).
LENGTH_FLOOR = 1e-3
MODULUS_FLOOR = 1e-6
TIME_FLOOR = 1e-3
RATE_FLOOR = 1e-6

#: The discretisation parameters of every scene; a scene with other defaults (or its own
#: help text) calls the same declaration: ``order: int = ORDER(3)``.
ORDER = Param("polynomial order of the displacement", range="[1, 10]")
#: A mesh size past the body's is one element across it: at most 1000, a metre in mm.
MAXH = Param("mesh size", "length", range=f"[{LENGTH_FLOOR:g}, 1000]")
#: The displacement unknowns of order k per element, by the element's shape: its share of
#: the nodes (a tetrahedron's k^3 / 6, a hexahedron's k^3, a triangle's k^2 / 2) times the
#: components (3; 2 on the section of a body in plane strain, :func:`geometries.bilayer`).
UNKNOWNS_PER_ELEMENT = {"tet": lambda k: 3 * k ** 3 / 6, "hex": lambda k: 3 * k ** 3,
                        "triangle": lambda k: 2 * k ** 2 / 2}
#: Upper bounds of counts: more load steps or a higher growth order than this is no longer a
#: finer computation but a run that does not end (each step is a Newton solve).
MAX_STEPS = 1000
STEPS = Param("initial number of load steps (adaptive: cut on failure)", range=f"[1, {MAX_STEPS}]")
#: Newton's linear solver (:func:`~ngincompat.fem.solver.resolve_linear_solver`).
LINEAR_SOLVER = Param(f"Newton's linear solver: direct, cg or gmres (BDDC preconditioned), "
                      "amg (CG with smoothed-aggregation multigrid); "
                      f"auto: cg with MPI, amg from {ITERATIVE_NDOF:,} unknowns on in the "
                      "displacement formulation, else direct", choices=LINEAR_SOLVERS)
#: BDDC's coarse space (:data:`~ngincompat.fem.problem.COARSE_SPACES`).
COARSE = Param("coarse space of the BDDC preconditioner of linear_solver cg and gmres: edges "
               "(vertex and edge dofs, few CG iterations, the coarse problem on MPI rank 0) or "
               "vertices (rank 0 lighter, several times the CG iterations; Newton failed with "
               "it on the fsaverage brain)",
               choices=COARSE_SPACES)
#: The most time steps a scene's duration may take at its time step (atrophy's 40 / 0.2 is
#: 200): past it a run is a hang, not a finer result.
MAX_TIME_STEPS = 10_000


def check_time_steps(duration_name: str, duration: float, step_name: str, step: float) -> None:
    """Refuse a time step that takes more than :data:`MAX_TIME_STEPS` over the duration."""
    require(duration / step <= MAX_TIME_STEPS, step_name, step,
            f">= {duration_name} / {MAX_TIME_STEPS} = {duration / MAX_TIME_STEPS:g} (at most "
            f"{MAX_TIME_STEPS} time steps)")


MAX_ELEMENTS = Param("refuse before meshing a mesh estimated to have more elements than this "
                     "(geometries.estimate); raise it for finer meshes", range="[1, 1e9]")
MAX_DOFS = Param("refuse before meshing a mesh estimated to have more unknowns than this (the "
                 "displacement's, and the mixed formulation's pressure and bubbles); raise it "
                 "for finer meshes", range="[1, 1e10]")
G_ORDER = Param("order of the H1 space that Fg given as data is projected into for Curl Fg "
                "(analytic growth is differentiated exactly)", range="[1, 12]")


@dataclass(frozen=True)
class Scene:
    """Base of all scenes: discretisation parameters common to every scene."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    units: ClassVar[dict] = {"length": "mm", "stress": "MPa", "energy": "N mm"}
    #: Every metric the scene can report (a run reports those its settings produce), each
    #: with its quantity and meaning (:mod:`ngincompat.scenes.metrics`); sweeps check the
    #: metrics they ask for against it before running anything.
    metrics: ClassVar[Mapping[str, Metric]] = registry()
    #: Parameters that name the scene's variant in titles and labels (profile, fibers, ...).
    variant: ClassVar[tuple[str, ...]] = ()
    #: Accuracy indicators over the scene's metrics, each with its threshold
    #: (:class:`~ngincompat.scenes.trust.Indicator`).
    indicators: ClassVar[tuple] = ()
    #: Whether the scene distributes its mesh when launched on several MPI ranks
    #: (:mod:`ngincompat.parallel`); the others refuse to run under MPI.
    distributed: ClassVar[bool] = False
    #: The settings of each named preset but ``default`` (:data:`PRESETS`): parameter name ->
    #: value, applied under the explicit settings by :meth:`from_settings`.
    presets: ClassVar[dict[str, dict]] = {}

    order: int = ORDER(4)
    maxh: float = MAXH(0.25)
    steps: int = STEPS(1)
    g_order: int = G_ORDER(6)
    outputs: Outputs = param(Outputs("vtk,figures"), "files besides results.json: comma "
                             "list of vtk, figures, growth (mesh.vol + growth.npz), "
                             "curvature (of the growth metric); or none")
    mechanics: bool = param(True, "solve the mechanics (stresses, energy); false: "
                                  "incompatibility of the growth field only")
    max_elements: int = MAX_ELEMENTS(1_000_000)
    # the default: about what a direct factorization of a 3-D problem holds in a
    # workstation's memory (the atrophy's paper preset: docs/measurements/paper-job.md)
    max_dofs: int = MAX_DOFS(500_000)

    def __post_init__(self) -> None:
        # every value to its parameter's type and range; a subclass checks the relations
        # between parameters after calling this
        convert_fields(self)
        self.check_mesh_size()

    def mesh_estimate(self) -> tuple[float, str] | None:
        """``(elements, shape)``: the estimated number of elements of the mesh :meth:`build`
        would make (:mod:`geometries.estimate`) and their shape, a key of
        :data:`UNKNOWNS_PER_ELEMENT`; None when it cannot be told before meshing (a mesh
        file)."""
        return None

    def unknowns_per_element(self, shape: str) -> float:
        """About how many unknowns the scene's problem has per element of ``shape``: the
        displacement's (:data:`UNKNOWNS_PER_ELEMENT`) and, in a scene's mixed formulation,
        its pressure and bubbles
        (:func:`~ngincompat.fem.problem.mixed_unknowns_per_element`)."""
        unknowns = UNKNOWNS_PER_ELEMENT[shape](self.order)
        if getattr(self, "formulation", "displacement") == "mixed":
            unknowns += mixed_unknowns_per_element(shape, self.order)
        return unknowns

    def check_mesh_size(self) -> None:
        """Refuse, before meshing, a mesh estimated past ``max_elements`` elements or
        ``max_dofs`` unknowns (:meth:`unknowns_per_element`), naming ``maxh``."""
        estimate = self.mesh_estimate()
        if estimate is None:
            return
        elements, shape = estimate
        dofs = elements * self.unknowns_per_element(shape)
        for what, value, limit in (("elements", elements, self.max_elements),
                                   ("unknowns", dofs, self.max_dofs)):
            key = "max_" + ("elements" if what == "elements" else "dofs")
            require(value <= limit, "maxh", self.maxh,
                    f"a coarser mesh (or a smaller body): the {self.name} mesh would have about "
                    f"{value:.2g} {what} at order {self.order}, more than {key} = {limit} "
                    f"(raise it with --set {key}=N if the machine has the memory)")

    def unmeshable(self, error: BaseException) -> str:
        """The message for a geometry the mesher failed on (``error``, Netgen's), naming the
        scene's lengths: a body far thinner than its mesh size (a disc 1e-3 high with
        ``maxh`` 0.2) passes every range and stops the mesher."""
        lengths = ", ".join(f"{name} = {getattr(self, name):g}"
                            for name, p in self.declarations().items()
                            if p.unit == "length" and isinstance(getattr(self, name), float))
        return (f"the mesher failed on this {self.name} geometry ({str(error).strip()}): "
                f"its lengths are {lengths} ({self.units['length']}); a body much thinner "
                "than its mesh size cannot be meshed: make its thinnest dimension at least "
                "about the mesh size, or the mesh sizes smaller")

    def output_set(self) -> set[str]:
        """The optional files this run writes, as a set of names."""
        return set(self.outputs)

    def build(self) -> pipeline.Case:
        """The scene's case (see :mod:`ngincompat.workflow.pipeline`)."""
        raise TypeError(f"{type(self).__name__} must define build()")

    def run(self, out: str | os.PathLike | None = None, *, overwrite: bool = False,
            progress: Progress = SILENT, label: str | None = None) -> Results:
        """Build, solve and measure the scene; write the folder ``out`` if given.

        See :func:`ngincompat.workflow.pipeline.run` (errors, interruption, what is written)."""
        comm = parallel.world()
        require(comm is None or self.distributed, "MPI ranks", comm and comm.size,
                f"1: the {self.name} scene does not run distributed (launch it without "
                "mpiexec)")
        return pipeline.run(self, out, overwrite=overwrite, progress=progress, label=label)

    def trust(self, results: Results) -> list[str]:
        """Warnings from the scene's settings and results beyond its :attr:`indicators` (none
        by default); see :mod:`ngincompat.scenes.trust`."""
        return []

    def warnings(self, results: Results) -> list[str]:
        """Every warning on ``results`` (:func:`ngincompat.scenes.trust.warnings`)."""
        return trust.warnings(self, results)

    def title(self) -> str:
        """The scene's name with its variant, for figure titles: "disc (fibers=radial)"."""
        parts = [f"{k}={getattr(self, k)}" for k in self.variant]
        return f"{self.name} ({', '.join(parts)})" if parts else self.name

    def resumes(self, out: str | os.PathLike) -> bool:
        """Whether this run continues one already in the folder ``out`` (no by default)."""
        return False

    def record(self, mesh: ngs.Mesh, order: int | None = None, **kwargs: Any) -> Results:
        """An empty :class:`Results` of this scene on ``mesh`` (an ngsolve.Mesh)."""
        ne, nv = parallel.counts(mesh)
        info = MeshInfo(ne=ne, nv=nv, order=self.order if order is None else order,
                        maxh=self.maxh)
        return Results(scene=self.name, params=self.settings(), preset=self.preset(),
                       units=dict(self.units),
                       metric_units={m: self.metric_unit(m) for m in self.metrics}, mesh=info,
                       versions=io.versions(), argv=list(sys.argv),
                       provenance=io.run_record(), domain=mesh, **kwargs)

    @classmethod
    def declarations(cls) -> dict[str, Parameter]:
        """name -> :class:`~ngincompat.parameters.Parameter` (type, default, help, unit,
        allowed range) of every parameter."""
        return declarations(cls)

    @classmethod
    def parameters(cls) -> dict[str, tuple[Any, str, str]]:
        """name -> (default, help, unit) of every parameter."""
        return {name: (p.default, p.help, p.unit) for name, p in cls.declarations().items()}

    @classmethod
    def typed_settings(cls, settings: Mapping[str, Any]) -> dict[str, Any]:
        """A mapping of parameter names to strings or values with each value converted to
        its parameter's type and checked ("3" -> 3.0 for maxh), in the JSON-ready form
        results.json records (tuples as lists, outputs as "vtk,figures").

        Raises
        ------
        ParameterError
            An unknown parameter, or a value that is not of its parameter's type or outside
            its range.
        """
        declared = cls.declarations()
        typed = {}
        for key, raw in settings.items():
            if key not in declared:
                raise ParameterError(
                    f"unknown parameter {key!r} for scene {cls.name!r}: allowed "
                    f"{', '.join(sorted(declared))}")
            typed[key] = declared[key].to_json(declared[key].convert(raw))
        return typed

    @classmethod
    def preset_names(cls) -> tuple[str, ...]:
        """The presets of the scene, cheapest first (``default`` always among them)."""
        return tuple(n for n in PRESETS if n == "default" or n in cls.presets)

    @classmethod
    def preset_settings(cls, preset: str) -> dict[str, Any]:
        """The settings of the named preset (``{}`` for ``default``).

        Raises
        ------
        ParameterError
            A preset the scene does not have.
        """
        names = cls.preset_names()
        require(preset in names, "preset", preset,
                f"one of {', '.join(names)} for scene {cls.name!r}")
        return dict(cls.presets.get(preset, {}))

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any], preset: str = "default") -> Self:
        """Build the scene from a mapping of parameter names to strings or values, over the
        settings of ``preset`` (the explicit settings win)."""
        return cls(**cls.typed_settings({**cls.preset_settings(preset), **settings}))

    def preset(self) -> str:
        """The preset whose settings this scene has: the finest of ``paper`` and ``preview``
        whose every setting it shares, else ``default`` when it is at the declared default of
        every parameter a preset sets, else ``custom``. Other parameters (the growth law, a
        variant) do not count: ``preview`` with ``fibers=radial`` is still ``preview``."""
        typed = {name: self.typed_settings(values) for name, values in self.presets.items()}
        for name in reversed(PRESETS):
            if name in typed and all(getattr(self, k) == self.declarations()[k].convert(v)
                                     for k, v in typed[name].items()):
                return name
        keys = {k for values in typed.values() for k in values}
        defaults = self.declarations()
        return ("default" if all(getattr(self, k) == defaults[k].default for k in keys)
                else "custom")

    @classmethod
    def metric_unit(cls, metric: str) -> str:
        """The unit of ``metric`` in the scene's units ("-" for a ratio or a count), from
        the quantity it measures (:attr:`metrics`).

        Raises
        ------
        KeyError
            A metric the scene does not declare.
        """
        quantity = cls.metrics[metric].quantity
        return cls.unit_of(quantity) if quantity else "-"

    @classmethod
    def unit_of(cls, unit: str) -> str:
        """A parameter's unit spelled in the scene's units ("length" -> "mm")."""
        for quantity, symbol in cls.units.items():
            unit = unit.replace(quantity, symbol)
        return unit

    @classmethod
    def parameter_line(cls, key: str) -> str:
        """``key (type, default value unit): allowed values`` of the parameter ``key`` (for
        ``ngincompat list -v``)."""
        p = cls.declarations()[key]
        default = p.to_json(p.default)
        if isinstance(default, list):
            default = ",".join(f"{v:g}" if isinstance(v, float) else str(v)
                               for v in default) or "none"
        elif isinstance(default, bool):
            default = str(default).lower()
        unit = f" {cls.unit_of(p.unit)}" if p.unit else ""
        return f"{key} ({p.kind.name}, default {default}{unit}): allowed {p.allowed()}"

    @classmethod
    def preset_line(cls, preset: str) -> str:
        """The settings of ``preset`` as ``key=value`` (for ``ngincompat list -v``)."""
        settings = cls.typed_settings(cls.preset_settings(preset))
        return " ".join(f"{k}={v}" for k, v in settings.items()) or "the defaults above"

    def describe(self, skip: Collection[str] = ("outputs", "mechanics")) -> str:
        """The parameters with their values, units and help texts, one line each."""
        lines = []
        for name, (_, help_text, unit) in self.parameters().items():
            if name not in skip:
                unit = f"[{self.unit_of(unit)}]" if unit else ""
                lines.append(f"{name:14s} = {getattr(self, name)!s:14.14s} {unit:10s} {help_text}")
        return "\n".join(lines)

    def settings(self) -> dict[str, Any]:
        """The parameters as a JSON-ready dict (for results.json): tuples as lists, outputs
        as "vtk,figures"; :meth:`from_settings` reads it back (so does the string form of
        earlier results.json files, "8.5,7.0,6.0")."""
        return to_json(self)
