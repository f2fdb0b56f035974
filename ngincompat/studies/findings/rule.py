"""A finding's rule as data (:class:`Finding`, :class:`Threshold`), the verdicts, and the
measurements and thresholds that the rules of several sections share."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results

AGREES, PARTLY, DIFFERS, IMPOSED, NOT_RUN = "agrees", "partly", "differs", "imposed", "not run"
#: Every verdict, in the order the report counts them.
VERDICTS = (AGREES, PARTLY, DIFFERS, IMPOSED, NOT_RUN)


@dataclass(frozen=True)
class Threshold:
    """When a rule gives ``verdict``: the condition in words (``when``; ``{value}`` in it
    stands for ``value``) and where it comes from (``source``). A rule's measurement reads
    ``value`` by ``name`` (:meth:`Finding.limit`)."""

    name: str
    verdict: str
    when: str
    source: str
    value: float | None = None

    def text(self) -> str:
        """The condition in words, with its value."""
        return self.when.format(value=self.value)


@dataclass(frozen=True)
class Finding:
    """A statement of the paper and the rule that judges it.

    Attributes
    ----------
    key : str
        A short name ("skin-order").
    section, figure : str
        Where the paper states it ("3.6", "6a").
    quote : str
        The paper's sentence, verbatim (its mathematics in plain text); "" for a check of
        ours that the paper does not state.
    claim : str
        The statement in short.
    needs : tuple of str
        The cases (labels of ``ngincompat paper``) whose results it reads.
    measure : str
        What is computed, from which case's metrics or profiles.
    thresholds : tuple of Threshold
        When each verdict is given, each with its source.
    decide : callable
        ``decide(finding, *results)`` -> (measured, verdict, reason), on the results of
        ``needs``, with the thresholds' values (:meth:`limit`).
    """

    key: str
    section: str
    figure: str
    quote: str
    claim: str
    needs: tuple
    measure: str
    thresholds: tuple
    decide: Callable

    @property
    def verdicts(self) -> tuple[str, ...]:
        """The verdicts the rule gives (besides "not run"), in the order of its thresholds."""
        return tuple(dict.fromkeys(t.verdict for t in self.thresholds))

    @property
    def states(self) -> str:
        """What the paper states, as the report and the rules' table show it: the quote, or
        for a check of ours its claim, marked as ours."""
        return (f"\u201c{self.quote}\u201d" if self.quote else
                f"a check of ours, not the paper's: {self.claim}")

    def limit(self, name: str) -> float:
        """The value of the rule's threshold ``name``."""
        return {t.name: t.value for t in self.thresholds}[name]

    def judge(self, results: Mapping[str, Results]) -> tuple[str, str, str]:
        """(measured, verdict, reason) on ``results`` (label -> Results)."""
        missing = [k for k in self.needs if k not in results or not results[k].converged]
        if missing:
            return "", NOT_RUN, "not finished: " + ", ".join(missing)
        return self.decide(self, *(results[k] for k in self.needs))


def number(v: float) -> str:
    return f"{v:.3g}"


def percent(v: float) -> str:
    return f"{100 * v:+.3g} %"


def profile(r: Results, key: str, name: str = "line") -> np.ndarray:
    return np.asarray(r.profile(name)[key], float)


def finite(r: Results, key: str, coord: str) -> tuple[np.ndarray, np.ndarray]:
    """A profile and its coordinate where the profile is finite."""
    x, y = profile(r, coord), profile(r, key)
    ok = np.isfinite(y)
    return x[ok], y[ok]


def ends(r: Results, key: str, coord: str, inner: float = 0.0) -> tuple[float, float]:
    """Values of a profile near its two ends (``inner`` of its length in from each)."""
    x, y = finite(r, key, coord)
    span = x[-1] - x[0]
    return (float(np.interp(x[0] + inner * span, x, y)),
            float(np.interp(x[-1] - inner * span, x, y)))


def for_each(holds: Mapping[str, bool], fails: str = "not for ") -> tuple[str, str]:
    """The verdict of a statement about each of ``holds`` (a case or a part of the statement
    -> whether it holds): agrees if it holds for all, differs if for none, partly otherwise;
    the reason names those for which it does not, after ``fails``."""
    failing = [what for what, ok in holds.items() if not ok]
    verdict = AGREES if not failing else DIFFERS if len(failing) == len(holds) else PARTLY
    return verdict, "" if verdict == AGREES else fails + ", ".join(failing)


#: The reason's words before the parts of a statement that fail (:func:`for_each`).
FAILS = "does not hold: "


def falls(f: Finding, first: float, second: float, what: str) -> tuple[str, str]:
    """Verdict of "``what`` falls from ``first`` to ``second``" (threshold ``falls``)."""
    if first > second * (1 + f.limit("falls")):
        return AGREES, ""
    return DIFFERS, f"{what} does not fall"


def at_most(f: Finding, name: str, value: float, what: str) -> tuple[str, str]:
    """Verdict of "``what`` = ``value`` is at most the threshold ``name``"."""
    limit = f.limit(name)
    return (AGREES, "") if value <= limit else (DIFFERS, f"{what} = {number(value)} > {limit:g}")


# --- thresholds that several rules share --------------------------------------------------

#: A quantity that a closed form makes vanish, relative to its scale.
ROUND_OFF = Threshold(
    "round_off", AGREES, "the ratio at most {value:g}",
    "the closed form: G of prescribed growth comes from the exact gradient of Fg, so the "
    "closed forms hold to round-off on any mesh (about 1e-16 on the validation page); "
    "1e-8 is a bound far above round-off and far below any real deviation", 1e-8)

#: "Decreases", "greater": a trend along a line, between its two ends.
FALLS = Threshold(
    "falls", AGREES, "the first value above the second by more than {value:g} of it",
    "the paper's word for the trend; the margin is a choice that keeps a constant sampled to "
    "round-off from counting as a trend, far below the closed forms' changes (eq. 16: 35 % "
    "along the cube, eq. 27: 25 % across the cylinder)", 1e-3)

#: A stress that a traction-free boundary makes vanish, over the largest stress.
TRACTION_FREE = Threshold(
    "traction_free", AGREES, "at most {value:g} of the largest stress",
    "the boundary condition makes it 0, what remains is the discretisation's: S11 on the "
    "cube's faces is 0.0599 of the largest at the preview and 0.0039 at the paper's "
    "resolution, sigma_r at the disc's rim 1.8e-3 and 2.5e-5 (docs/measurements/"
    "paper-job.md, 'Sections 3.1-3.4: preview against the paper's resolution'); 0.05 is a "
    "choice between the cube's two", 0.05)

#: A number the paper gives to one significant figure ("about 30 %", "up to 50 %",
#: "about 40 kPa").
ABOUT = Threshold(
    "about", AGREES, "within {value:g} of the paper's number, in its unit",
    "the paper gives the number to one significant figure: a value rounds to it within half "
    "a unit of its last digit", 5.0)

#: A value that the model's cap or input carries (the rule replaces ``when`` and ``source``
#: by the cap's).
AT_CAP = Threshold("at_cap", IMPOSED, "", "")

#: A verdict "agrees" on a run that warns.
WARNED = Threshold(
    "warned", PARTLY, "it would agree, but the run warns",
    "the run's own accuracy indicators (ngincompat/scenes/trust.py): a warned value is not "
    "trusted")

#: A statement about each of several cases that holds for some of them only.
SOME = Threshold(
    "some", PARTLY, "for some of the cases but not all",
    "the paper states it for each case or part ('in all cases', 'in either case', 'and'): "
    "some hold")

#: The gray-white interface within this fraction of the cortex's thickness of a peak: "near
#: the interface" (atrophy).
NEAR = Threshold(
    "near", AGREES, "the peak within {value:g} of the cortex's thickness of the interface",
    "'near the interface' read as nearer to it than to the brain's surface: within half "
    "the cortex's thickness", 0.5)


def within_about(f: Finding, value: float, paper: float) -> bool:
    """Is ``value`` (in the paper's unit) the paper's number ``paper`` to its precision
    (the threshold ``about``)?"""
    return abs(value - paper) <= f.limit("about")


def otherwise(when: str) -> Threshold:
    """The rule's "differs": the statement's negation, ``when``."""
    return Threshold("otherwise", DIFFERS, when, "the paper's statement, negated")

