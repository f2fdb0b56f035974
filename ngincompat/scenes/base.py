"""What every scene shares: typed parameters settable by name, and their validation.

A scene is a frozen dataclass. Its fields are its parameters, each with a default, a help text
and a unit in the field's metadata; ``Scene.from_settings`` builds one from ``KEY=VALUE``
strings (the command line's ``--set``), converting each value to the field's type and naming
the key and the allowed values in every error.
"""

import contextlib
import dataclasses
import time as _time
from dataclasses import dataclass, field
from typing import ClassVar

from ..errors import ParameterError, require

OUTPUTS = {"vtk", "figures"}


@contextlib.contextmanager
def timed(timings, phase):
    """Add the wall time of the block to ``timings[phase]``."""
    start = _time.perf_counter()
    try:
        yield
    finally:
        timings[phase] = timings.get(phase, 0.0) + _time.perf_counter() - start


def param(default, help, unit=""):
    """A scene parameter with its documentation."""
    return field(default=default, metadata={"help": help, "unit": unit})


@dataclass(frozen=True)
class Scene:
    """Base of all scenes: discretisation parameters common to every scene."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    units: ClassVar[dict] = {"length": "mm", "stress": "MPa", "energy": "N mm"}

    order: int = param(4, "polynomial order of the displacement")
    maxh: float = param(0.25, "mesh size", "length")
    steps: int = param(1, "initial number of load steps (adaptive: cut on failure)")
    g_order: int = param(6, "order of the H1 space that Fg is projected into for Curl Fg")
    outputs: str = param("vtk,figures", "files besides results.json: comma list of "
                                        "vtk, figures; or none")
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
        unknown = self.output_set() - OUTPUTS
        require(not unknown, "outputs", self.outputs,
                f"a comma list of {', '.join(sorted(OUTPUTS))}, or none")

    def output_set(self):
        """The optional files this run writes, as a set of names."""
        if self.outputs.strip() in ("", "none"):
            return set()
        return {item.strip() for item in self.outputs.split(",")}

    @classmethod
    def parameters(cls):
        """name -> (default, help, unit) of every parameter."""
        return {f.name: (f.default, f.metadata.get("help", ""), f.metadata.get("unit", ""))
                for f in dataclasses.fields(cls)}

    @classmethod
    def from_settings(cls, settings):
        """Build the scene from a mapping of parameter names to strings or values."""
        fields = {f.name: f for f in dataclasses.fields(cls)}
        kwargs = {}
        for key, raw in settings.items():
            if key not in fields:
                raise ParameterError(
                    f"unknown parameter {key!r} for scene {cls.name!r}: allowed "
                    f"{', '.join(sorted(fields))}")
            kwargs[key] = _convert(key, raw, type(fields[key].default))
        return cls(**kwargs)

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
