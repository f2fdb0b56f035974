"""Typed parameters, declared once: type, allowed range, unit and help.

A set of parameters (a scene's) is a frozen dataclass. Each field's annotation is its type and
:class:`Param` adds the rest::

    MU = Param("shear modulus", "stress", range="> 0")

    @dataclass(frozen=True)
    class Cube:
        mu: float = MU(0.55)                                      # shared declaration
        model: Literal["full", "quarter"] = param("full", "full cube, or a quarter")
        semi_axes: tuple[float, float, float] = param((8.5, 7.0, 6.0), "semi-axes",
                                                      "length", range="> 0")
        outputs: Outputs = param(Outputs("vtk,figures"), "optional files")

        def __post_init__(self):
            convert_fields(self)          # every field to its type, in its range

The types understood are ``float`` (finite, and of magnitude at most :data:`FLOAT_LIMIT`
on a side its range leaves open), ``int``, ``bool``, ``str``, ``Literal[...]``
(or ``str`` with ``choices=`` a live registry such as a dict of builders), tuples of floats
(``tuple[float, float, float]`` of fixed length, ``tuple[float, ...]`` of any), a union of
words and such a tuple (``Literal["uniform"] | tuple[float, float, float]``) and
:class:`Outputs`. ``range`` is one of ``"> a"``, ``">= a"``, ``"< b"``, ``"<= b"`` or an
interval ``"(a, b]"`` (bounds may be fractions: ``"[0, 1/3]"``); for a tuple it bounds each
component.

:meth:`Parameter.convert` is the one converter: a ``--set key=value`` string, a TOML value
of a sweep file and a Python keyword argument become the same typed value, or a
:class:`~ngincompat.errors.ParameterError` in the package's one-line form that names the
parameter and its allowed range (``nu = 0.5 is out of range: allowed in (-1, 0.5)``,
``order = 'two' is not a valid int: allowed an integer in [1, 10]``). Checks that relate
several parameters stay in the dataclass's ``__post_init__``.

Why not pydantic: its dataclasses would validate the fields, but the messages (several lines,
its own wording) would have to be rewritten into the form above, the string forms of the
command line ("8.5,7.0,6.0", "vtk,figures", "yes") would still need their own parsers, and
it would be a dependency of the main job for what is about 270 lines of code here.
"""

import abc
import dataclasses
import math
import numbers
import os
import types
import typing
from collections.abc import Collection, Iterable
from fractions import Fraction
from typing import Any, Literal, Self

from ngincompat.errors import ParameterError, require, shown

#: Optional outputs of a run, as named in a scene's ``outputs`` parameter: files, and
#: ``curvature`` (the curvature of the growth metric in the metrics, fields and figures).
OUTPUTS = ("vtk", "figures", "growth", "curvature")

_TRUE = ("1", "true", "yes", "on")
_FALSE = ("0", "false", "no", "off")
_NUMBER_WORDS = {2: "two", 3: "three", 4: "four"}


#: The named settings of every scene, from the cheapest to the finest: ``preview`` for a first
#: look in seconds to a minute, ``default`` (the declared defaults: the cheapest settings within
#: the scene's stated tolerance) and ``paper`` (the resolution and settings of the paper's
#: figures). A scene lists the settings of its ``preview`` and ``paper`` in
#: :attr:`ngincompat.scenes.base.Scene.presets`.
PRESETS = ("preview", "default", "paper")


class Outputs(frozenset):
    """The optional outputs of a run (:data:`OUTPUTS`): a set of names, spelled as a comma
    list ("vtk,figures") or "none" (also "").

    ``Outputs("vtk,figures")``, ``Outputs(["vtk"])`` and ``Outputs("none")`` are the ways to
    make one; any other name is a :class:`~ngincompat.errors.ParameterError` naming
    ``outputs``. ``str()`` gives the comma list in the order of :data:`OUTPUTS`, the form
    results.json records.
    """

    ALLOWED = f"a comma list of {', '.join(sorted(OUTPUTS))}, or none"

    def __new__(cls, value: str | Iterable[str] = ()) -> Self:
        if isinstance(value, str):
            text = value.strip()
            names: list[str | None] = ([] if text in ("", "none")
                                       else [item.strip() for item in text.split(",")])
        elif isinstance(value, (list, tuple, set, frozenset)):
            names = list(value)
        else:
            names = [None]
        require(all(name in OUTPUTS for name in names), "outputs", value, cls.ALLOWED)
        return super().__new__(cls, names)

    def __str__(self) -> str:
        return ",".join(name for name in OUTPUTS if name in self) or "none"

    def __repr__(self) -> str:
        return f"Outputs({str(self)!r})"


class Range:
    """An allowed range of numbers, from its text: ``"> 0"``, ``">= 1"``, ``"< 0.5"``,
    ``"<= 1"``, or an interval ``"(-1, 0.5)"``, ``"[0, 1/3]"``, ``"(0, 1]"``."""

    def __init__(self, text: str) -> None:
        self.text = text.strip()
        self.low: float | None = None
        self.high: float | None = None
        self.low_open = self.high_open = False
        try:
            if self.text[:1] in "([" and self.text[-1:] in ")]":
                low, high = self.text[1:-1].split(",")
                self.low, self.high = _number(low), _number(high)
                self.low_open, self.high_open = self.text[0] == "(", self.text[-1] == ")"
            else:
                op, _, bound = self.text.partition(" ")
                value = _number(bound)
                if op in (">", ">="):
                    self.low, self.low_open = value, op == ">"
                elif op in ("<", "<="):
                    self.high, self.high_open = value, op == "<"
                else:
                    raise ValueError(op)
        except ValueError:
            raise ValueError(f"range {text!r}: expected '> a', '>= a', '< b', '<= b' or an "
                             "interval such as '(a, b]'") from None

    def __contains__(self, x: float) -> bool:
        if self.low is not None and not (x > self.low if self.low_open else x >= self.low):
            return False
        return self.high is None or (x < self.high if self.high_open else x <= self.high)

    @property
    def bounded(self) -> bool:
        """Whether the range has both bounds (then its numbers are finite)."""
        return self.low is not None and self.high is not None

    def words(self) -> str:
        """The range as the messages spell it: "> 0", "in (-1, 0.5)"."""
        return f"in {self.text}" if self.text[0] in "([" else self.text

    def __repr__(self) -> str:
        return f"Range({self.text!r})"


def _number(text: str) -> float:
    return float(Fraction(text.strip()))


@dataclasses.dataclass(frozen=True)
class Param:
    """The declaration of a parameter but its type (the field's annotation) and default.

    Calling it gives a dataclass field with a default: ``mu: float = MU(0.55)``; several
    dataclasses that call the same declaration share its help, unit and range (each with
    its own default; ``help=`` replaces the help text of one use).

    Attributes
    ----------
    help : str
        What the parameter is, one line.
    unit : str
        Its quantity in the scene's units ("length", "stress", "1/time"), "" if none.
    range : str, optional
        The allowed numbers (see :class:`Range`); for a tuple, of each component.
    choices : collection of str, optional
        The allowed strings of a ``str`` parameter, looked up when a value is converted
        (a registry that grows stays current); fixed choices are a ``Literal`` annotation.
    """

    help: str
    unit: str = ""
    range: str | None = None
    choices: typing.Collection[str] | None = None

    def __post_init__(self) -> None:
        if self.range is not None:
            Range(self.range)             # a malformed range fails where it is declared

    def __call__(self, default: Any, *, help: str | None = None) -> Any:
        decl = self if help is None else dataclasses.replace(self, help=help)
        return dataclasses.field(default=default, metadata={"param": decl})


def param(default: Any, help: str, unit: str = "", *, range: str | None = None,
          choices: Collection[str] | None = None) -> Any:
    """A parameter declared in one place: ``Param(help, unit, range, choices)(default)``."""
    return Param(help, unit, range, choices)(default)


# --------------------------------------------------------------------------- types

class _Kind(abc.ABC):
    """How the values of one type are read, checked, described and recorded."""

    #: How a parse error names the type: "x = 'a' is not a valid <name>".
    name = ""

    def __init__(self, range: str | None = None) -> None:
        self.range = Range(range) if range else None

    @abc.abstractmethod
    def parse(self, raw: Any) -> Any:
        """The typed value of ``raw`` (ValueError if ``raw`` is not of the type)."""

    def valid(self, value: Any) -> bool:
        return True

    def allowed(self) -> str:
        return self.range.words() if self.range else f"a {self.name}"

    def to_json(self, value: Any) -> Any:
        return value


#: The largest magnitude of a float parameter whose declared range leaves that side open:
#: no quantity of the models comes near it in its scene's units, and its squares and cubes
#: (energies, volumes) stay far from overflow, where 1e308 made inf, nan and crashes
#: downstream. A parameter that needs more declares a bounded range.
FLOAT_LIMIT = 1e12
#: Nonzero numbers of smaller magnitude are refused whatever the range: they are no quantity
#: distinct from 0, and the arithmetic underflows on them (their products are 0, quotients by
#: them overflow: a subnormal 1e-320 passed every "(0, x]" and broke deep in the solvers).
TINY = 1e-300


class _Float(_Kind):
    name = "float"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str):
            return float(raw)
        if isinstance(raw, bool) or not isinstance(raw, numbers.Real):
            raise ValueError(raw)
        return float(raw)

    def valid(self, value: Any) -> bool:
        return (math.isfinite(value) and (self.range is None or value in self.range)
                and (self.range is not None and self.range.high is not None
                     or value <= FLOAT_LIMIT)
                and (self.range is not None and self.range.low is not None
                     or value >= -FLOAT_LIMIT))

    def allowed(self) -> str:
        if self.range is None:
            return f"in [-{FLOAT_LIMIT:g}, {FLOAT_LIMIT:g}]"
        if self.range.bounded:
            return self.range.words()
        r = self.range
        if r.low is None:
            return f"in [-{FLOAT_LIMIT:g}, {r.high:g}{')' if r.high_open else ']'}"
        return f"in {'(' if r.low_open else '['}{r.low:g}, {FLOAT_LIMIT:g}]"


class _Int(_Kind):
    name = "int"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str):
            return int(raw)
        if isinstance(raw, numbers.Integral) and not isinstance(raw, bool):
            return int(raw)
        if isinstance(raw, numbers.Real) and not isinstance(raw, bool) and float(raw).is_integer():
            return int(raw)  # type: ignore[call-overload]  # int() takes any Real
        raise ValueError(raw)

    def valid(self, value: Any) -> bool:
        return self.range is None or value in self.range

    def allowed(self) -> str:
        return f"an integer {self.range.words()}" if self.range else "an integer"


class _Bool(_Kind):
    name = "bool"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str) and raw.strip().lower() in _TRUE + _FALSE:
            return raw.strip().lower() in _TRUE
        if isinstance(raw, bool) or getattr(getattr(raw, "dtype", None), "kind", "") == "b":
            return bool(raw)                                        # numpy's bool too
        raise ValueError(raw)

    def allowed(self) -> str:
        return "true or false"


class _Str(_Kind):
    name = "str"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str):
            return raw
        if isinstance(raw, os.PathLike):
            return os.fspath(raw)
        if isinstance(raw, numbers.Real) and not isinstance(raw, bool):
            return str(raw)              # theta = 1 in a sweep file is the expression "1"
        raise ValueError(raw)

    def allowed(self) -> str:
        return "a string"


class _Choice(_Kind):
    name = "choice"

    def __init__(self, choices: Collection[str]) -> None:
        super().__init__()
        self.choices = choices

    def parse(self, raw: Any) -> Any:
        return raw                        # anything else is out of range, not malformed

    def valid(self, value: Any) -> bool:
        return isinstance(value, str) and value in self.choices

    def allowed(self) -> str:
        names = list(self.choices)
        return " or ".join(names) if len(names) == 2 else ", ".join(names)


class _Floats(_Kind):
    """A tuple of floats: ``length`` of them, or any number (``None``)."""

    def __init__(self, length: int | None = None, range: str | None = None) -> None:
        super().__init__(range)
        self.length = length
        self.item = _Float(range)
        self.name = f"tuple of {length} floats" if length else "list of floats"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str):
            items = [] if not raw.strip() else raw.split(",")
        elif isinstance(raw, (list, tuple)) or hasattr(raw, "tolist"):      # numpy arrays
            items = list(raw.tolist() if hasattr(raw, "tolist") else raw)
        else:
            raise ValueError(raw)
        return tuple(self.item.parse(item) for item in items)

    def valid(self, value: Any) -> bool:
        return ((self.length is None or len(value) == self.length)
                and all(self.item.valid(v) for v in value))

    def allowed(self) -> str:
        what = (f"{_NUMBER_WORDS.get(self.length, self.length)} numbers" if self.length
                else "a comma list of numbers")
        return f"{what} {self.item.allowed()}"

    def to_json(self, value: Any) -> Any:
        return list(value)


class _WordsOrFloats(_Kind):
    """One of some words, or a tuple of floats (``"uniform"`` or ``0,0,-5``)."""

    def __init__(self, words: Iterable[str], floats: _Kind) -> None:
        super().__init__()
        self.words, self.floats = tuple(words), floats
        self.name = f"{' or '.join(self.words)} or {floats.name}"

    def parse(self, raw: Any) -> Any:
        if isinstance(raw, str) and raw.strip() in self.words:
            return raw.strip()
        return self.floats.parse(raw)

    def valid(self, value: Any) -> bool:
        return value in self.words if isinstance(value, str) else self.floats.valid(value)

    def allowed(self) -> str:
        return f"{' or '.join(self.words)}, or {self.floats.allowed()}"

    def to_json(self, value: Any) -> Any:
        return value if isinstance(value, str) else self.floats.to_json(value)


class _Outputs(_Kind):
    name = "outputs"

    def parse(self, raw: Any) -> Any:
        return raw if isinstance(raw, Outputs) else Outputs(raw)

    def allowed(self) -> str:
        return Outputs.ALLOWED

    def to_json(self, value: Any) -> Any:
        return str(value)


_SCALARS: dict[type, type[_Kind]] = {float: _Float, int: _Int, bool: _Bool, str: _Str}


def _kind(annotation: Any, decl: Param) -> _Kind:
    """The :class:`_Kind` of a field from its annotation and declaration."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if decl.choices is not None:
        if annotation is not str:
            raise TypeError(f"choices= needs a str parameter, not {annotation}")
        return _Choice(decl.choices)
    if annotation in _SCALARS:
        if decl.range and annotation not in (float, int):
            raise TypeError(f"range= needs a number, not {annotation.__name__}")
        return _SCALARS[annotation](decl.range)
    if annotation is Outputs:
        return _Outputs()
    if origin is Literal:
        return _Choice(args)
    if origin is tuple and args and all(a is float for a in args if a is not Ellipsis):
        length = None if args[-1] is Ellipsis else len(args)
        return _Floats(length, decl.range)
    if origin in (typing.Union, types.UnionType):
        words = [a for a in args if typing.get_origin(a) is Literal]
        rest = [a for a in args if typing.get_origin(a) is not Literal]
        if len(rest) == 1 and typing.get_origin(rest[0]) is tuple:
            floats = _kind(rest[0], decl)
            return _WordsOrFloats([w for a in words for w in typing.get_args(a)], floats)
    raise TypeError(f"no converter for parameters of type {annotation}")


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One parameter of a dataclass: its name, default, declaration and type."""

    name: str
    default: object
    decl: Param
    kind: _Kind

    @property
    def help(self) -> str:
        return self.decl.help

    @property
    def unit(self) -> str:
        return self.decl.unit

    def allowed(self) -> str:
        """The allowed values in words, as the error messages give them."""
        return self.kind.allowed()

    @property
    def takes_list(self) -> bool:
        """Whether a value is a list (a tuple parameter: ``semi_axes = [8.5, 7.0, 6.0]`` in
        a sweep file, the same as ``"8.5,7.0,6.0"``)."""
        return isinstance(self.kind, (_Floats, _WordsOrFloats))

    def convert(self, raw: Any) -> Any:
        """The typed value of ``raw`` (a string, a TOML value or a Python value), checked.

        Raises
        ------
        ParameterError
            ``raw`` is not of the type ("x = 'a' is not a valid float: allowed ...") or its
            value is outside the range ("x = -1.0 is out of range: allowed > 0").
        """
        try:
            value = self.kind.parse(raw)
        except ParameterError as err:       # Outputs names itself with the value given
            raise ParameterError(str(err).replace("outputs = ", f"{self.name} = ", 1)) from None
        except (ValueError, TypeError, OverflowError):
            raise ParameterError(f"{self.name} = {shown(raw)} is not a valid "
                                 f"{self.kind.name}: allowed {self.allowed()}") from None
        numbers_given = value if isinstance(value, tuple) else (value,)
        if any(isinstance(v, float) and v != 0 and abs(v) < TINY for v in numbers_given):
            raise ParameterError(f"{self.name} = {shown(raw)} is below {TINY:g} in magnitude, "
                                 f"where the arithmetic underflows: allowed {self.allowed()}, "
                                 f"of magnitude 0 or at least {TINY:g}")
        require(self.kind.valid(value), self.name, value, self.allowed())
        return value

    def to_json(self, value: Any) -> Any:
        """``value`` as results.json records it: tuples as lists, outputs as "vtk,figures";
        :meth:`convert` reads that form back."""
        return self.kind.to_json(value)


_CACHE: dict[type, dict[str, Parameter]] = {}


def declarations(cls: type) -> dict[str, Parameter]:
    """name -> :class:`Parameter` of every field of the dataclass ``cls`` that was declared
    with :class:`Param`, in the fields' order."""
    if cls not in _CACHE:
        hints = typing.get_type_hints(cls)
        _CACHE[cls] = {
            f.name: Parameter(f.name, f.default, f.metadata["param"],
                              _kind(hints[f.name], f.metadata["param"]))
            for f in dataclasses.fields(cls) if "param" in f.metadata}
    return _CACHE[cls]


def convert_fields(obj: object) -> None:
    """Convert every declared field of the frozen dataclass instance ``obj`` in place (see
    :meth:`Parameter.convert`), in the fields' order: the first bad value raises."""
    for name, parameter in declarations(type(obj)).items():
        object.__setattr__(obj, name, parameter.convert(getattr(obj, name)))


def to_json(obj: object) -> dict[str, Any]:
    """The declared fields of ``obj`` as a JSON-ready dict (:meth:`Parameter.to_json`)."""
    return {name: p.to_json(getattr(obj, name)) for name, p in declarations(type(obj)).items()}
