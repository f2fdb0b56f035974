"""What every scene shares: typed parameters settable by name, their validation, and the
entry to the pipeline.

A scene is a frozen dataclass. Its fields are its parameters, each with a default, a help text
and a unit in the field's metadata; ``Scene.from_settings`` builds one from ``KEY=VALUE``
strings (the command line's ``--set``), converting each value to the field's type and naming
the key and the allowed values in every error. ``scene.build()`` returns its case (see
:mod:`ngincompat.workflow.pipeline`); ``scene.run(out=None)`` runs the whole pipeline and returns
the
:class:`~ngincompat.workflow.results.Results`, writing files only when ``out`` is given.
"""

import dataclasses
import sys
from dataclasses import dataclass, field
from typing import ClassVar

from ngincompat import parallel
from ngincompat.errors import ParameterError, require
from ngincompat.progress import SILENT, Progress
from ngincompat.workflow import io, pipeline
from ngincompat.workflow.output import OUTPUTS
from ngincompat.workflow.results import MeshInfo, Results


def param(default, help, unit=""):
    """A scene parameter with its documentation."""
    return field(default=default, metadata={"help": help, "unit": unit})


@dataclass(frozen=True)
class Scene:
    """Base of all scenes: discretisation parameters common to every scene."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    units: ClassVar[dict] = {"length": "mm", "stress": "MPa", "energy": "N mm"}
    #: Every metric the scene can report (a run reports those its settings produce); sweeps
    #: check the metrics they ask for against it before running anything.
    metrics: ClassVar[tuple[str, ...]] = ()
    #: The quantity each dimensional metric measures, spelled in the scene's units by
    #: :meth:`unit_of`; every other metric is a ratio (relative errors, growth multipliers).
    metric_quantities: ClassVar[dict[str, str]] = {
        "strain_energy": "energy", "strain_energy_clamped": "energy",
        "strain_energy_released": "energy",
        "max_principal_stress": "stress", "max_principal_stress_clamped": "stress",
        "max_principal_stress_released": "stress", "pressure_inflated": "stress",
        "pressure_end_of_hold": "stress",
        "burgers_max": "1/length", "burgers_apex": "1/length", "rotation_rate": "1/length",
        "rotation_rate_expected": "1/length",
        "burgers_max_radius": "length", "volume_inflated": "volume",
        "G_norm_L2": "length^(1/2)",
        "scalar_curvature_min": "1/length^2", "scalar_curvature_max": "1/length^2",
        "einstein_norm_L2": "length^(-1/2)", "einstein_norm_L2_error": "length^(-1/2)",
    }
    #: Parameters that name the scene's variant in titles and labels (profile, fibers, ...).
    variant: ClassVar[tuple[str, ...]] = ()
    #: Whether the scene distributes its mesh when launched on several MPI ranks
    #: (:mod:`ngincompat.parallel`); the others refuse to run under MPI.
    distributed: ClassVar[bool] = False

    order: int = param(4, "polynomial order of the displacement")
    maxh: float = param(0.25, "mesh size", "length")
    steps: int = param(1, "initial number of load steps (adaptive: cut on failure)")
    g_order: int = param(6, "order of the H1 space that Fg given as data is projected into "
                            "for Curl Fg (analytic growth is differentiated exactly)")
    outputs: str = param("vtk,figures", "files besides results.json: comma list of "
                                        "vtk, figures, growth (mesh.vol + growth.npz), "
                                        "curvature (of the growth metric); or none")
    mechanics: bool = param(True, "solve the mechanics (stresses, energy); false: "
                                  "incompatibility of the growth field only")

    def __post_init__(self):
        require(isinstance(self.order, int) and 1 <= self.order <= 10, "order", self.order,
                "an integer in [1, 10]")
        require(self.maxh > 0, "maxh", self.maxh, "> 0")
        require(isinstance(self.steps, int) and self.steps >= 1, "steps", self.steps,
                "an integer >= 1")
        require(isinstance(self.g_order, int) and 1 <= self.g_order <= 12, "g_order",
                self.g_order, "an integer in [1, 12]")
        unknown = self.output_set() - set(OUTPUTS)
        require(not unknown, "outputs", self.outputs,
                f"a comma list of {', '.join(sorted(OUTPUTS))}, or none")

    def output_set(self):
        """The optional files this run writes, as a set of names."""
        if self.outputs.strip() in ("", "none"):
            return set()
        return {item.strip() for item in self.outputs.split(",")}

    def build(self):
        """The scene's case (see :mod:`ngincompat.workflow.pipeline`)."""
        raise TypeError(f"{type(self).__name__} must define build()")

    def run(self, out=None, *, overwrite: bool = False, progress: Progress = SILENT,
            label: str | None = None) -> Results:
        """Build, solve and measure the scene; write the folder ``out`` if given.

        See :func:`ngincompat.workflow.pipeline.run` (errors, interruption, what is written)."""
        comm = parallel.world()
        require(comm is None or self.distributed, "MPI ranks", comm and comm.size,
                f"1: the {self.name} scene does not run distributed (launch it without "
                "mpiexec)")
        return pipeline.run(self, out, overwrite=overwrite, progress=progress, label=label)

    def title(self) -> str:
        """The scene's name with its variant, for figure titles: "disc (fibers=radial)"."""
        parts = [f"{k}={getattr(self, k)}" for k in self.variant]
        return f"{self.name} ({', '.join(parts)})" if parts else self.name

    def resumes(self, out) -> bool:
        """Whether this run continues one already in the folder ``out`` (no by default)."""
        return False

    def record(self, mesh, order=None, **kwargs) -> Results:
        """An empty :class:`Results` of this scene on ``mesh`` (an ngsolve.Mesh)."""
        ne, nv = parallel.counts(mesh)
        info = MeshInfo(ne=ne, nv=nv, order=self.order if order is None else order,
                        maxh=self.maxh)
        return Results(scene=self.name, params=self.settings(), units=dict(self.units),
                       metric_units={m: self.metric_unit(m) for m in self.metrics}, mesh=info,
                       versions=io.versions(), argv=list(sys.argv), domain=mesh, **kwargs)

    @classmethod
    def parameters(cls):
        """name -> (default, help, unit) of every parameter."""
        return {f.name: (f.default, f.metadata.get("help", ""), f.metadata.get("unit", ""))
                for f in dataclasses.fields(cls)}

    @classmethod
    def typed_settings(cls, settings):
        """A mapping of parameter names to strings or values with each string converted to
        its parameter's type (that of its default; "3" -> 3.0 for maxh).

        Raises
        ------
        ParameterError
            An unknown parameter, or a string that is not a value of its parameter's type.
        """
        fields = {f.name: f for f in dataclasses.fields(cls)}
        typed = {}
        for key, raw in settings.items():
            if key not in fields:
                raise ParameterError(
                    f"unknown parameter {key!r} for scene {cls.name!r}: allowed "
                    f"{', '.join(sorted(fields))}")
            typed[key] = _convert(key, raw, type(fields[key].default))
        return typed

    @classmethod
    def from_settings(cls, settings):
        """Build the scene from a mapping of parameter names to strings or values."""
        return cls(**cls.typed_settings(settings))

    @classmethod
    def metric_unit(cls, metric):
        """The unit of ``metric`` in the scene's units ("-" for a ratio), from the quantity
        it measures (:attr:`metric_quantities`)."""
        quantity = cls.metric_quantities.get(metric)
        return cls.unit_of(quantity) if quantity else "-"

    @classmethod
    def unit_of(cls, unit):
        """A parameter's unit spelled in the scene's units ("length" -> "mm")."""
        for quantity, symbol in cls.units.items():
            unit = unit.replace(quantity, symbol)
        return unit

    def describe(self, skip=("outputs", "mechanics")):
        """The parameters with their values, units and help texts, one line each."""
        lines = []
        for name, (_, help_text, unit) in self.parameters().items():
            if name not in skip:
                unit = f"[{self.unit_of(unit)}]" if unit else ""
                lines.append(f"{name:14s} = {getattr(self, name)!s:14.14s} {unit:10s} {help_text}")
        return "\n".join(lines)

    def settings(self):
        """The parameters as a plain dict (for results.json)."""
        return dataclasses.asdict(self)


def _convert(key, raw, kind):
    if not isinstance(raw, str):
        return raw
    try:
        if kind is bool:
            if raw.lower() in ("1", "true", "yes", "on"):
                return True
            if raw.lower() in ("0", "false", "no", "off"):
                return False
            raise ValueError
        if kind is int:
            return int(raw)
        if kind is float:
            return float(raw)
    except ValueError:
        raise ParameterError(f"{key} = {raw!r} is not a valid {kind.__name__}") from None
    return raw
