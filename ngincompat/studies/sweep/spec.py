"""The sweep file: a TOML file naming a scene, the parameters that stay fixed, those that vary
and the metrics to collect, read and validated into a :class:`Sweep` and expanded into its
:class:`Case` s::

    scene = "cube"
    metrics = ["strain_energy", "G_error_L2_rel"]   # optional; default: every metric

    [fixed]                                         # scene parameters of every case
    maxh = 0.5
    outputs = "none"

    [vary]                                          # full product across the keys
    order = {start = 1, stop = 3, step = 1}         # ints, stop included: 1, 2, 3
    nu = [0.3, 0.4, 0.45]

    [zip]                                           # varied together (equal lengths),
    a = [0.1, 0.25]                                 # then producted with [vary]
    side = [1.0, 2.0]

A value of ``[vary]`` or ``[zip]`` is a list or a range: ``{start, stop, num}`` is
``numpy.linspace(start, stop, num)``, ``{start, stop, step}`` the integers from ``start`` to
``stop`` (included when a step lands on it) by ``step``. A tuple parameter takes a list
or its string form, ``semi_axes = [3.0, 2.5, 2.0]`` or ``"3,2.5,2"`` in ``[fixed]``, and a
list of them in ``[vary]``. The cases are the product of the rows
of ``[zip]`` (outermost) with the values of ``[vary]`` in the file's order, the last key
varying fastest.

:meth:`Sweep.with_settings` sets parameters for every case on top of the file (``sweep run
--set``, e.g. coarse settings for a smoke test); a parameter the sweep varies cannot be set.

The file is checked when it is read: unknown keys, unknown parameter names, empty lists,
unequal ``[zip]`` lengths, an unknown scene, and metrics the scene cannot report (its class's
``metrics``) are errors naming the key. The parameter *values* are checked by the scene, case
by case (:meth:`Case.build`), so that a bad value makes only its case fail.
"""

import dataclasses
import hashlib
import itertools
import json
import os
import tomllib
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, NoReturn, Self

import numpy as np

from ngincompat.errors import ParameterError
from ngincompat.parameters import Parameter
from ngincompat.scenes import SCENES, get_scene
from ngincompat.scenes.base import Scene

SWEEP_KEYS = ("scene", "fixed", "vary", "zip", "metrics")
RANGE_KEYS = ("start", "stop", "num", "step")
#: The most cases a sweep may have, counted from the file before any list is made (a huge
#: range or product would exhaust the memory before the first case ran): each case is a run of
#: its scene, so 10,000 of them are days of computing already.
MAX_CASES = 10_000


@dataclasses.dataclass(frozen=True)
class Case:
    """One run of a sweep.

    Attributes
    ----------
    index : int
        Position in the sweep (row order of the table).
    scene : str
        Name of the scene.
    params : dict
        Every parameter handed to the scene's ``from_settings`` (fixed and varied).
    varied : dict
        The varied parameters alone (the table's parameter columns).
    """

    index: int
    scene: str
    params: dict
    varied: dict

    @property
    def key(self) -> str:
        """Short hash of the scene and the parameters."""
        text = json.dumps({"scene": self.scene, "params": self.params}, sort_keys=True)
        return hashlib.sha1(text.encode()).hexdigest()[:8]

    @property
    def name(self) -> str:
        """Folder name of the case, ``case_<index>_<hash>``."""
        return f"case_{self.index:03d}_{self.key}"

    def build(self) -> Scene:
        """The case's scene.

        Raises
        ------
        ParameterError
            The scene rejects a value of the case.
        """
        return get_scene(self.scene).from_settings(self.params)


@dataclasses.dataclass(frozen=True)
class Sweep:
    """A validated sweep file.

    Attributes
    ----------
    scene : str
        Name of the scene.
    fixed : dict
        Parameters shared by every case.
    vary : dict
        Parameter -> list of values; the cases take the full product across the keys.
    zipped : dict
        Parameter -> list of values, all of the same length, varied together.
    metrics : tuple of str or None
        Metrics to collect (None: every metric of the results).
    """

    scene: str
    fixed: dict
    vary: dict
    zipped: dict
    metrics: tuple | None = None

    @property
    def varied(self) -> list[str]:
        """Names of the varied parameters, in the table's order."""
        return [*self.zipped, *self.vary]

    @property
    def scene_class(self) -> type[Scene]:
        """The class of the sweep's scene (its parameters, metrics and units)."""
        return SCENES[self.scene]

    def with_settings(self, settings: Mapping[str, Any]) -> Self:
        """The sweep with ``settings`` (parameter -> string or value, as ``run --set`` gives
        them) added to its fixed parameters, replacing those of the file: every case runs
        with them, and they are part of the sweep's cases (their folder names and the record
        beside the table), so a sweep folder never mixes cases with and without them.

        Raises
        ------
        ParameterError
            A parameter the sweep varies ([vary] or [zip]), an unknown parameter, or a value
            that is not of its parameter's type or outside its range.
        """
        for key in settings:
            for section, table in (("zip", self.zipped), ("vary", self.vary)):
                if key in table:
                    raise ParameterError(
                        f"{key} cannot be set for every case: the sweep varies it "
                        f"([{section}] {key} = {table[key]!r}); change it in the sweep file")
        typed = self.scene_class.typed_settings(settings)
        return dataclasses.replace(self, fixed={**self.fixed, **typed})

    def record(self) -> dict[str, Any]:
        """The sweep and its cases as a JSON-ready dict (recorded beside the table)."""
        return {"scene": self.scene, "fixed": self.fixed, "vary": self.vary,
                "zip": self.zipped, "metrics": list(self.metrics) if self.metrics else None,
                "varied": self.varied,
                "cases": [{"case": c.index, "folder": c.name, "params": c.params}
                          for c in self.cases()]}

    def cases(self) -> list[Case]:
        """The cases: rows of ``zipped`` (outer) times the product of ``vary``.

        Returns
        -------
        list of Case
        """
        zip_rows = [dict(zip(self.zipped, values, strict=True))
                    for values in zip(*self.zipped.values(), strict=True)]
        vary_rows = [dict(zip(self.vary, values, strict=True))
                     for values in itertools.product(*self.vary.values())]
        cases = []
        for index, (z, v) in enumerate(itertools.product(zip_rows or [{}], vary_rows)):
            varied = {**z, **v}
            cases.append(Case(index, self.scene, {**self.fixed, **varied}, varied))
        return cases


def load_sweep(path: str | os.PathLike) -> Sweep:
    """Read and validate a sweep file.

    Parameters
    ----------
    path : path-like
        The TOML file.

    Returns
    -------
    Sweep

    Raises
    ------
    ParameterError
        The file cannot be read, is not TOML, or breaks a rule of the format; the message
        names the key.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise ParameterError(f"sweep file {path} cannot be read: {err}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ParameterError(f"sweep file {path} is not valid TOML: {err}") from None
    return parse_sweep(data, source=str(path))


def parse_sweep(data: Mapping[str, Any], source: str = "sweep") -> Sweep:
    """Validate the contents of a sweep file (a dict as ``tomllib`` returns it).

    Parameters
    ----------
    data : dict
        Keys ``scene``, ``fixed``, ``vary``, ``zip``, ``metrics``.
    source : str
        Name of the file, for the error messages.

    Returns
    -------
    Sweep
    """
    def fail(message: str) -> NoReturn:
        raise ParameterError(f"{source}: {message}")

    for key in data:
        if key not in SWEEP_KEYS:
            fail(f"unknown key {key!r}: allowed {', '.join(SWEEP_KEYS)}")
    if "scene" not in data:
        fail("missing key 'scene' (the name of the scene, e.g. scene = \"cube\")")
    scene = data["scene"]
    if not isinstance(scene, str) or scene not in SCENES:
        fail(f"scene = {scene!r} is unknown: allowed {', '.join(sorted(SCENES))}")
    allowed = SCENES[scene].declarations()

    tables: dict[str, dict] = {}
    for section in ("fixed", "vary", "zip"):
        table = data.get(section, {})
        if not isinstance(table, dict):
            fail(f"{section} must be a table ([{section}]), not {table!r}")
        for key in table:
            if key not in allowed:
                fail(f"{section}.{key}: unknown parameter of scene {scene!r}: allowed "
                     f"{', '.join(sorted(allowed))}")
            for other, seen in tables.items():
                if key in seen:
                    fail(f"{section}.{key}: {key!r} is also set in [{other}]")
        tables[section] = table

    fixed = {}
    for key, value in tables["fixed"].items():
        if not _is_value(value, allowed[key]):
            fail(f"fixed.{key} = {value!r} must be a single value (vary it in [vary])")
        fixed[key] = value
    vary = {key: _values(f"vary.{key}", raw, fail, allowed[key])
            for key, raw in tables["vary"].items()}
    zipped = {key: _values(f"zip.{key}", raw, fail, allowed[key])
              for key, raw in tables["zip"].items()}
    lengths = {key: len(values) for key, values in zipped.items()}
    if len(set(lengths.values())) > 1:
        fail("the lists of [zip] must have equal lengths: "
             + ", ".join(f"zip.{key} has {n}" for key, n in lengths.items()))
    count = max(lengths.values(), default=1)
    for values in vary.values():
        count *= len(values)
    if count > MAX_CASES:
        fail(f"the sweep has {count:.3g} cases ([zip] rows times the product of [vary]): "
             f"allowed at most {MAX_CASES}")

    metrics = data.get("metrics")
    if metrics is not None:
        if not isinstance(metrics, list) or not metrics:
            fail(f"metrics = {metrics!r} must be a non-empty list of metric names")
        known = SCENES[scene].metrics
        for name in metrics:
            if name not in known:
                fail(f"metrics: {name!r} is not a metric of scene {scene!r}: allowed "
                     f"{', '.join(known)}")
        if len(set(metrics)) < len(metrics):
            fail(f"metrics = {metrics!r} names a metric twice")
        metrics = tuple(metrics)
    return Sweep(scene, fixed, vary, zipped, metrics)


def _is_scalar(value: object) -> bool:
    return isinstance(value, (str, int, float, bool))


def _is_value(value: object, parameter: Parameter) -> bool:
    """Whether ``value`` is one value of ``parameter`` (a list of numbers for a tuple)."""
    if parameter.takes_list and isinstance(value, list):
        return all(_is_number(v) for v in value)
    return _is_scalar(value)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _values(name: str, raw: object, fail: Callable[[str], NoReturn],
            parameter: Parameter) -> list:
    """The list of values of one varied parameter: a list or a range table."""
    if isinstance(raw, dict):
        values = _range(name, raw, fail)
    elif isinstance(raw, list):
        values = raw
        for i, value in enumerate(values):
            if not _is_value(value, parameter):
                fail(f"{name}[{i}] = {value!r} must be a single value")
    else:
        fail(f"{name} = {raw!r} must be a list of values or a range {{start=, stop=, num=}} "
             "or {start=, stop=, step=}")
    if not values:
        fail(f"{name} is an empty list")
    return list(values)


def _range(name: str, spec: Mapping[str, Any], fail: Callable[[str], NoReturn]) -> list:
    for key in spec:
        if key not in RANGE_KEYS:
            fail(f"{name}.{key}: unknown key of a range: allowed start, stop and num or step")
    for key in ("start", "stop"):
        if key not in spec:
            fail(f"{name}: a range needs {key}")
    if ("num" in spec) == ("step" in spec):
        fail(f"{name}: a range needs either num (evenly spaced numbers) or step (integers)")
    start, stop = spec["start"], spec["stop"]
    if "num" in spec:
        num = spec["num"]
        if not (isinstance(num, int) and not isinstance(num, bool) and 1 <= num <= MAX_CASES):
            fail(f"{name}.num = {num!r} must be an integer in [1, {MAX_CASES}] (the most cases "
                 "of a sweep)")
        for key in ("start", "stop"):
            if not _is_number(spec[key]):
                fail(f"{name}.{key} = {spec[key]!r} must be a number")
        return [float(v) for v in np.linspace(start, stop, num)]
    step = spec["step"]
    for key in ("start", "stop", "step"):
        value = spec[key]
        if not (isinstance(value, int) and not isinstance(value, bool)):
            fail(f"{name}.{key} = {value!r} must be an integer (use num for evenly spaced "
                 "numbers)")
    if step == 0:
        fail(f"{name}.step = 0 must not be zero")
    count = max(0, (stop - start) // step + 1)
    if count > MAX_CASES:
        fail(f"{name}: the range from {start} to {stop} by {step} has {count} values: allowed "
             f"at most {MAX_CASES} (the most cases of a sweep)")
    values = list(range(start, stop + (1 if step > 0 else -1), step))
    if not values:
        fail(f"{name}: the range from {start} to {stop} by {step} is empty")
    return values
