"""The typed record of a run: what every reader of results (command line, ``paper``,
``expansion``, benchmarks, sweeps, notebooks) consumes.

A :class:`Results` holds the scene's parameters and units, the versions that produced it, the
mesh, the solver history of every stage, timings per phase, scalar metrics, sampled profiles,
the figures to draw from those profiles, and the NGSolve fields themselves (for
``ngsolve.webgui.Draw`` or VTK). Everything but the fields round-trips through JSON
(:meth:`Results.to_dict`, :meth:`Results.from_dict`); :func:`ngincompat.workflow.output.write`
writes it to a folder, :func:`ngincompat.workflow.output.read` reads it back.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, fields
from typing import Any, ClassVar

import numpy as np

from ngincompat.fem.solver import SolverHistory, StepRecord
from ngincompat.workflow import io

#: The ending of a run, as written to results.json.
DONE, NOT_CONVERGED, INTERRUPTED = "done", "not converged", "interrupted"


@dataclass
class MeshInfo:
    """Size of the discretisation: elements, vertices, unknowns, order and mesh size."""

    ne: int
    nv: int
    order: int
    maxh: float
    ndof: int | None = None


@dataclass
class Figure:
    """A figure drawn from one profile of a :class:`Results`, by
    :func:`ngincompat.workflow.plots.draw`; its kind is its class (:data:`FIGURES`):
    :class:`ProfileFigure`, :class:`MapsFigure`, :class:`DeformedFigure`,
    :class:`SurfaceFigure`.

    Attributes
    ----------
    file : str
        PNG file name.
    x : str
        Key of the abscissa in the profile (of a map, its first axis).
    xlabel, ylabel : str
        Axis labels, with units.
    curves : dict
        Legend or panel label -> profile key.
    title : str
        Title; names the scene and its variant.
    floor : float
        Smallest range of the values shown (besides 1e-4 of the largest value, which
        :mod:`ngincompat.workflow.plots` always keeps): values that vary by less (round-off
        around a constant, discretisation error of a stress-free body) are shown flat, not
        magnified into noise.
    profile : str
        Which profile of the results.
    """

    #: The kind's name in results.json.
    kind: ClassVar[str] = ""

    file: str
    x: str
    xlabel: str
    curves: dict[str, str]
    ylabel: str
    title: str
    floor: float = 0.0
    profile: str = "line"

    def keys(self) -> tuple[str, ...]:
        """The keys of the profile that the figure draws (it is drawn where all are)."""
        return (self.x, *self.curves.values())

    def to_dict(self) -> dict[str, Any]:
        """The figure as JSON-ready data, its kind named."""
        return {"kind": self.kind, **asdict(self)}

    @staticmethod
    def from_dict(data: dict[str, Any]) -> Figure:
        """The figure that :meth:`to_dict` wrote (keys another kind has are left out)."""
        cls = FIGURES[data.get("kind", "profile")]
        names = {f.name for f in fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in names})


@dataclass
class ProfileFigure(Figure):
    """Curves against ``x``, on a left and possibly a right axis.

    Attributes
    ----------
    right : dict
        Legend label -> profile key, on a second (right) axis.
    right_label : str
        Label of the right axis, with units.
    right_floor : float
        Smallest range of the right axis (as ``floor``).
    marks : dict
        Legend label (``{value}`` stands for the metric's value) -> metric key; a dashed
        vertical line at the metric's value (e.g. the onset of folding on the eigenvalue's
        curve), left out where it is not finite.
    """

    kind: ClassVar[str] = "profile"

    right: dict[str, str] = field(default_factory=dict)
    right_label: str = ""
    right_floor: float = 0.0
    marks: dict[str, str] = field(default_factory=dict)

    def keys(self) -> tuple[str, ...]:
        return (*super().keys(), *self.right.values())


@dataclass
class MapsFigure(Figure):
    """Colour maps, one panel per curve, of 2-D arrays keyed "<plane>_<field>" whose axes are
    the profile's "<plane>_u" and "<plane>_v" (one row per plane, one column per field;
    ``x`` names the first axis).

    Attributes
    ----------
    arrows : dict
        Panel label -> profile key of an array of the grid's shape with 2 components along
        the plane's axes, drawn as arrows over the panel's map (the paper's Burgers vectors
        in their plane).
    """

    kind: ClassVar[str] = "maps"

    arrows: dict[str, str] = field(default_factory=dict)


@dataclass
class DeformedFigure(Figure):
    """Colour maps of 2-D arrays (one panel per curve) sampled on a reference grid whose axes
    are the profile's ``x`` (columns) and ``y`` (rows), each drawn on the grid moved by a
    displacement (:func:`ngincompat.workflow.plots.deformed_figure`).

    Attributes
    ----------
    y : str
        Key of the grid's second axis in the profile.
    deform : dict
        Panel label -> profile key of the displacement, an array of the grid's shape with
        3 components.
    """

    kind: ClassVar[str] = "deformed"

    y: str = ""
    deform: dict[str, str] = field(default_factory=dict)

    def keys(self) -> tuple[str, ...]:
        return (*super().keys(), *self.deform.values(), *([self.y] if self.y else []))


@dataclass
class SurfaceFigure(Figure):
    """The surface of the profile's "points" and "triangles" coloured by each curve's values
    at the points, seen from ``view``, with ``xlabel`` the length unit of its axes
    (:func:`ngincompat.workflow.surface.triangulated_figure`).

    Attributes
    ----------
    deform : dict
        Panel label -> profile key of the displacements at the points, by which the panel's
        surface is moved (if any).
    view : tuple
        Elevation and azimuth of the camera [degrees].
    """

    kind: ClassVar[str] = "surface"

    deform: dict[str, str] = field(default_factory=dict)
    view: tuple[float, float] = (10.0, 90.0)

    def keys(self) -> tuple[str, ...]:
        return (*super().keys(), *self.deform.values())


#: The kinds of figure by their name in results.json.
FIGURES: dict[str, type[Figure]] = {cls.kind: cls for cls in (
    ProfileFigure, MapsFigure, DeformedFigure, SurfaceFigure)}


@dataclass(eq=False)
class Results:
    """Everything a run produced.

    Attributes
    ----------
    scene : str
        Scene name.
    params : dict
        The scene's parameters (as ``Scene.settings()``).
    units : dict
        Quantity -> unit symbol ("length" -> "mm").
    mesh : MeshInfo
    status : str
        ``"done"``, ``"not converged"`` (the state is the last converged one) or
        ``"interrupted"``.
    error : str or None
        Why the run did not finish.
    preset : str or None
        The named settings the scene's parameters match (``preview``, ``default``, ``paper``
        or ``custom``; :meth:`ngincompat.scenes.base.Scene.preset`); None in older runs.
    solver : dict
        Stage name -> :class:`~ngincompat.fem.solver.SolverHistory`, in the order of the stages.
    timings : dict
        Phase -> wall time [s].
    metrics : dict
        Name -> float (units: the scene's).
    metric_units : dict
        Metric name -> unit symbol ("-" for a ratio).
    profiles : dict
        Profile name -> {key: array}: fields sampled along lines.
    figures : list of Figure
    verdicts : list of str
        Findings in words, made by the scene from its metrics (e.g. whether the growth is
        compatible), shown after the metrics.
    warnings : list of str
        Why a result may not be trusted, one line per accuracy indicator past its threshold
        (:mod:`ngincompat.scenes.trust`); empty for a run that passed them all.
    versions : dict
        Package versions.
    argv : list
        The command line of the process.
    provenance : dict
        Date, host, threads, the full command line and the git commit
        (:func:`ngincompat.workflow.io.run_record`), and ``peak_mib``: the peak memory of
        each rank (one in a serial run) [MiB], rank 0 first, as the measures ended; empty
        in results.json of older runs.
    files : list
        Files written for this run, relative to its folder.
    fields : dict
        Name -> ngsolve CoefficientFunction on ``domain`` (not serialised).
    domain : ngsolve.Mesh or None
        The mesh the fields live on (not serialised).
    frames : list of (float, dict)
        (time, name -> field) at chosen times of a time-dependent scene, frozen copies on
        ``domain`` (not serialised): the frames of the ``fields.pvd`` time series.
    """

    scene: str
    params: dict[str, Any]
    units: dict[str, str]
    mesh: MeshInfo
    status: str = DONE
    error: str | None = None
    preset: str | None = None
    solver: dict[str, SolverHistory] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    metrics: dict[str, float] = field(default_factory=dict)
    metric_units: dict[str, str] = field(default_factory=dict)
    profiles: dict[str, dict[str, np.ndarray]] = field(default_factory=dict)
    figures: list[Figure] = field(default_factory=list)
    verdicts: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    versions: dict[str, str] = field(default_factory=dict)
    argv: list[str] = field(default_factory=list)
    provenance: dict[str, Any] = field(default_factory=dict)
    files: list[str] = field(default_factory=list)
    fields: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)
    domain: Any = field(default=None, repr=False, compare=False)
    frames: list[tuple[float, dict[str, Any]]] = field(default_factory=list, repr=False,
                                                       compare=False)

    @property
    def converged(self) -> bool:
        """Did every stage reach its end?"""
        return self.status == DONE

    def non_finite(self) -> list[str]:
        """The metrics that are not finite numbers (NaN, inf, None): their state is not one
        the run computed (:func:`ngincompat.workflow.output.write` writes none of its
        files)."""
        return [k for k, v in self.metrics.items() if v is None or not math.isfinite(v)]

    @property
    def newton_iterations(self) -> int:
        """Newton iterations of the converged steps of every stage."""
        return sum(h.newton_iterations for h in self.solver.values())

    @property
    def solve_seconds(self) -> float:
        """Wall time of the solver stages (the timings whose phase is a stage)."""
        return sum(self.timings.get(stage, 0.0) for stage in self.solver)

    def summary(self) -> str:
        """One line: status, size, Newton iterations per stage, solve and total time."""
        total = sum(self.timings.values())
        if not self.solver:
            return f"{self.scene}: incompatibility only (no mechanics), {total:.2f} s"
        stages = ", ".join(f"{stage} {h.newton_iterations}" for stage, h in self.solver.items())
        return (f"{self.scene}: {self.status}; ndof {self.mesh.ndof}, Newton iterations "
                f"{self.newton_iterations} ({stages}), solve {self.solve_seconds:.2f} s, "
                f"total {total:.2f} s")

    def metric_lines(self) -> list[str]:
        """One line per metric: name, value and unit; then the scene's verdicts (the
        warnings are logged as the run ends)."""
        lines = [f"  {key:32s} {value:<12.6g} {self.metric_units.get(key, '')}".rstrip()
                 for key, value in self.metrics.items()]
        lines += [f"  {v}" for v in self.verdicts]
        return lines

    def profile(self, name: str = "line") -> dict[str, np.ndarray]:
        """A sampled profile by name."""
        return self.profiles[name]

    def to_dict(self) -> dict:
        """A JSON-ready dict (non-finite floats become None, arrays lists)."""
        return io.jsonable({
            "scene": self.scene, "status": self.status, "error": self.error,
            "preset": self.preset, "params": self.params, "units": self.units,
            "mesh": asdict(self.mesh),
            "solver": {stage: h.as_dict() for stage, h in self.solver.items()},
            "timings": self.timings, "metrics": self.metrics,
            "metric_units": self.metric_units, "profiles": self.profiles,
            "figures": [f.to_dict() for f in self.figures], "verdicts": self.verdicts,
            "warnings": self.warnings,
            "versions": self.versions,
            "argv": self.argv, "provenance": self.provenance, "files": self.files,
        })

    @classmethod
    def from_dict(cls, data: dict) -> Results:
        """The record of :meth:`to_dict` (profiles as arrays; fields are not restored)."""
        def number(v: float | None) -> float:
            return math.nan if v is None else float(v)

        return cls(
            scene=data["scene"], params=dict(data["params"]), units=dict(data["units"]),
            mesh=MeshInfo(**data["mesh"]), status=data.get("status", DONE),
            error=data.get("error"), preset=data.get("preset"),
            solver={stage: _history(h) for stage, h in data.get("solver", {}).items()},
            timings={k: number(v) for k, v in data.get("timings", {}).items()},
            metrics={k: number(v) for k, v in data.get("metrics", {}).items()},
            metric_units=dict(data.get("metric_units", {})),
            profiles={name: {k: np.asarray(v, dtype=float) for k, v in p.items()}
                      for name, p in data.get("profiles", {}).items()},
            figures=[Figure.from_dict(f) for f in data.get("figures", [])],
            verdicts=list(data.get("verdicts", [])),
            warnings=list(data.get("warnings", [])),
            versions=dict(data.get("versions", {})), argv=list(data.get("argv", [])),
            provenance=dict(data.get("provenance", {})),
            files=list(data.get("files", [])))


def _history(data: dict) -> SolverHistory:
    steps = []
    for s in data.get("steps", []):
        s = dict(s)
        s["energy"] = math.nan if s.get("energy") is None else s["energy"]
        s["residuals"] = [math.nan if r is None else r for r in s.get("residuals", [])]
        steps.append(StepRecord(**s))
    return SolverHistory(steps=steps, converged=data["converged"],
                         t_reached=data["t_reached"], work=dict(data.get("work", {})))
