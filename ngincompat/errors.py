"""Exceptions raised by ngincompat.

Every error a user can cause by their input is a :class:`ParameterError` whose message names
the parameter and the allowed range, so that the command line can print it as one line.
"""

from typing import Any


class NgincompatError(Exception):
    """Base class of every error raised on purpose by ngincompat."""


class ParameterError(NgincompatError, ValueError):
    """A parameter is missing, unknown, malformed or outside its allowed range."""


class ExpressionError(ParameterError):
    """A growth expression could not be parsed or uses something outside the whitelist."""


class ConvergenceError(NgincompatError):
    """The nonlinear solver could not reach the requested load.

    The problem's displacement still holds the last converged state; ``history`` holds the
    per-step record up to the failure and ``t_converged`` the last load that converged.
    """

    def __init__(self, message: object, history: Any = None, t_converged: Any = None) -> None:
        super().__init__(message)
        self.history = history
        self.t_converged = t_converged
        #: The :class:`~ngincompat.workflow.results.Results` of the last converged state, once a
        #: pipeline has measured (and written) them.
        self.results: Any = None


class Interrupted(NgincompatError):
    """The user interrupted a solve (Ctrl-C); the state was reset to the last converged step.

    ``history`` holds the per-step record up to the interruption."""

    def __init__(self, message: object, history: Any = None, t_converged: Any = None) -> None:
        super().__init__(message)
        self.history = history
        self.t_converged = t_converged
        self.results: Any = None


class InterruptedBeforeComputing(Interrupted):
    """The user interrupted a run while it built its case (meshing): nothing was computed and
    nothing written."""


def require(condition: object, name: str, value: object, allowed: str) -> None:
    """Raise :class:`ParameterError` unless ``condition`` holds.

    Parameters
    ----------
    condition : bool
        The check that must pass.
    name : str
        Name of the parameter, as the user spells it.
    value : object
        The offending value.
    allowed : str
        The allowed range in words, e.g. ``"> 0"`` or ``"in [0, 1/3]"``.
    """
    if not condition:
        raise ParameterError(f"{name} = {shown(value)} is out of range: allowed {allowed}")


#: The most characters of a value that an error message quotes.
QUOTE = 70


def shown(value: object) -> str:
    """``value`` as an error message quotes it: its repr, cut to about :data:`QUOTE`
    characters with the length of the whole (a 5,000-character value is not echoed)."""
    text = repr(value)
    if len(text) <= QUOTE:
        return text
    if isinstance(value, str):
        return f"{value[:QUOTE - 3]!r}... ({len(value)} characters)"
    return f"{text[:QUOTE - 3]}..."
