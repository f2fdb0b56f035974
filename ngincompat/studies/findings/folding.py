"""The findings of section 3.7, cortical folding (Fig. 7): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat import names
from ngincompat.mechanics.fields import FOCUS_DEPTH
from ngincompat.studies.findings.rule import (
    AGREES,
    DIFFERS,
    NOT_RUN,
    PARTLY,
    SOME,
    Finding,
    Threshold,
    for_each,
    number,
    otherwise,
    percent,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results

AXONS = names.AXONS
FOLDING = tuple(f"folding-{a}" for a in AXONS)
#: The axon fields the paper calls normal to the cortex. Its caption orders Fig. 7a's columns
#: "curved outward, concentric, normal to the interface", and the gradient at the interface
#: is greater "when the axons are normal to the cortex (second and third columns in Fig.
#: 7a), as opposed to the case in which axons approach the interface tangentially (first
#: column in Fig. 7a)": the concentric and straight fields.
NORMAL = ("concentric", "straight")
#: The axon field the paper calls tangential to the interface: the first column, curved.
TANGENTIAL = "curved"
#: The normal fields of a second reading, reported beside the paper's: the straight axons
#: normal, the concentric ones (arcs parallel to the interface above their focus) tangential
#: (:data:`SECOND_TANGENTIAL`).
SECOND_NORMAL = ("straight",)
#: The tangential field of the second reading (:data:`SECOND_NORMAL`).
SECOND_TANGENTIAL = "concentric"


def _fold_onset(f: Finding, *runs: Results) -> tuple[str, str, str]:
    onset = [r.metrics.get("onset_growth", math.nan) for r in runs]
    amp = [r.metrics.get("fold_amplitude", math.nan) for r in runs]
    return ("onset at theta_c = " + ", ".join(number(o) for o in onset) + "; fold amplitude "
            + ", ".join(number(a) for a in amp) + " cm (curved, concentric, straight)",
            *for_each({axons: bool(np.isfinite(o)) and not (np.isfinite(a) and a <= 0)
                    for axons, o, a in zip(AXONS, onset, amp, strict=True)}))


def _fold_interface(f: Finding, *runs: Results) -> tuple[str, str, str]:
    depth = [r.metrics["burgers_max_depth"] for r in runs]
    t, h = runs[0].params["cortex_thickness"], runs[0].params["cortex_maxh"]
    return ("max |b| at depth " + ", ".join(number(d) for d in depth)
            + f" cm (curved, concentric, straight); the interface is {number(t)} cm deep",
            *for_each({a: abs(d - t) <= f.limit("at_interface") * h
                    for a, d in zip(AXONS, depth, strict=True)}))


#: Axon growth (theta_a - 1) below which an axon field has not acted on a run.
AXON_GROWTH_MIN = 1e-3


def _axons_idle(runs: Sequence[Results]) -> str:
    """The reason the axon fields cannot be compared, or "": with theta_a = 1 everywhere
    (the stretch never passed its critical value before the run ended, as on the preview's
    short march) the three fields give the same growth, so equal or shuffled |b| and stress
    say nothing about their orientation."""
    grown = [r.metrics.get("theta_a_max", np.nan) - 1 for r in runs]
    if all(np.isfinite(grown)) and max(grown) >= AXON_GROWTH_MIN:
        return ""
    return ("the axons did not grow by the end of the run (theta_a_max - 1 = "
            + ", ".join(number(g) for g in grown) + "): their orientation cannot act")


def _by_field(runs: Sequence[Results], metric: str) -> dict[str, float]:
    return dict(zip(AXONS, (r.metrics.get(metric, np.nan) for r in runs), strict=True))


def _readings(f: Finding, runs: Sequence[Results], values: Mapping[str, float],
              compare: Callable[[Finding, Mapping[str, float], str, str], tuple[bool, bool, str]],
              claim: str) -> tuple[str, str, str]:
    """The verdict of the paper's reading (normal: :data:`NORMAL`, tangential:
    :data:`TANGENTIAL`) and, in the measured text beside it, the second reading's
    (:data:`SECOND_NORMAL`, :data:`SECOND_TANGENTIAL`). ``compare(f, values, normal,
    tangential)`` gives (strict, weak, text) for one normal field: agrees if strict holds
    for every normal field, differs if weak holds for none, partly otherwise; the reason
    says so of the ``claim``."""
    def judge(normal: Sequence[str], tangential: str) -> tuple[str, str]:
        tests = [compare(f, values, a, tangential) for a in normal]
        text = ", ".join(t for _, _, t in tests)
        verdict = (AGREES if all(s for s, _, _ in tests) else
                   PARTLY if any(w for _, w, _ in tests) else DIFFERS)
        return verdict, text

    verdict, text = judge(NORMAL, TANGENTIAL)
    second, second_text = judge(SECOND_NORMAL, SECOND_TANGENTIAL)
    length = runs[0].params["length"]
    angle = math.degrees(math.atan(length / (2 * FOCUS_DEPTH)))
    measured = (", ".join(f"{a} {number(v)}" for a, v in values.items())
                + f". The paper's reading (normal to the cortex: concentric, straight; "
                f"tangential: curved): {text}: {verdict}. Second reading (normal: straight; "
                f"tangential: concentric): {second_text}: {second}, not the verdict. The "
                f"curved axons meet the interface at most {angle:.3g} degrees from its normal "
                "(ngincompat.mechanics.fields.axons), which the paper calls tangential")
    reason = {AGREES: "", PARTLY: f"{claim} against some normal field, not against every "
              f"one by the threshold ({text})",
              DIFFERS: f"{claim} against no normal field ({text})"}
    return measured, verdict, reason[verdict]


def _more(f: Finding, values: Mapping[str, float], normal: str,
          tangential: str) -> tuple[bool, bool, str]:
    """A normal field's interface |b| over the tangential one's: (strict, weak, text)."""
    change = values[normal] / values[tangential] - 1
    return (change > f.limit("unsettled"), change > 0,
            f"{normal} {percent(change)} over {tangential}")


def _fold_axons(f: Finding, *runs: Results) -> tuple[str, str, str]:
    """The interface |b| of the normal fields against the tangential one's."""
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    values = _by_field(runs, "burgers_interface_mean")
    measured, verdict, reason = _readings(f, runs, values, _more,
                                          "the tangential field's |b| the smaller")
    return "burgers_interface_mean [1/cm]: " + measured, verdict, reason


def _lower(f: Finding, values: Mapping[str, float], normal: str,
           tangential: str) -> tuple[bool, bool, str]:
    """The tangential field's released stress over a normal one's: (strict, weak, text)."""
    ratio = values[tangential] / values[normal]
    return (ratio <= f.limit("much_lower"), ratio < 1,
            f"{tangential} {percent(ratio - 1)} against {normal}")


def _fold_release(f: Finding, *runs: Results) -> tuple[str, str, str]:
    """The released stress of the tangential field against the normal fields'."""
    values = _by_field(runs, "max_principal_stress_released")
    if not all(np.isfinite(list(values.values()))):
        return "not released", NOT_RUN, "the runs end before the release"
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    measured, verdict, reason = _readings(f, runs, values, _lower,
                                          "the tangential field's stress much lower")
    return "max_principal_stress_released [kPa]: " + measured, verdict, reason



#: settle it.
B_UNSETTLED = Threshold(
    "unsettled", AGREES, "each normal field's interface |b| above the tangential one's by "
    "more than {value:g} (relative)",
    "the mesh: the interface |b| of the creasing bilayer changes by up to 5 % between two "
    "resolutions (docs/measurements/folding.md, 'The fold shape at two resolutions')", 0.05)

#: Released stress of the tangential axons at most this fraction of each normal field's:
#: the paper's "much lower".
MUCH_LOWER = Threshold(
    "much_lower", AGREES, "the tangential field's stress at most {value:g} of each normal "
    "field's",
    "the paper gives no number for 'much lower'; a conservative choice: at most half, so "
    "that a difference of a fifth or a third, which 'lower' describes, is not counted as "
    "agreement", 0.5)

#: The rules of section 3.7.
FINDINGS = (
    Finding(
        "folding-onset", "3.7", "7a",
        "The differential growth between the two layers and the constraints at the ends of "
        "the domain lead to the characteristic patterns of folding seen in the brain (Fig. "
        "7a).",
        "the growing cortex on its subcortex folds", FOLDING,
        "each axon field: the onset theta_c (onset_growth: finite where the bilayer "
        "buckled) and the fold amplitude (positive where measured)",
        (Threshold("all", AGREES, "every field folds", "the caption: 'Folding patterns "
                   "emerge for three different axon orientations'"),
         replace(SOME, when="some fields fold"), otherwise("none folds")),
        _fold_onset),
    Finding(
        "folding-interface", "3.7", "7b",
        "The Burgers vector density has its greatest magnitude precisely at the interface "
        "between the cortex and subcortex, where the gradient of growth is sharpest.",
        "|b| is largest at the cortex-subcortex interface", FOLDING,
        "each axon field: the depth below the top of the largest |b| (burgers_max_depth) "
        "against the cortex's thickness",
        (Threshold("at_interface", AGREES, "for every field within {value:g} cortex mesh "
                   "sizes (cortex_maxh) of the interface",
                   "'precisely at the interface'; G is projected from a growth that jumps "
                   "there, which spreads the jump over the elements next to it: two mesh "
                   "sizes is a choice", 2.0),
         replace(SOME, when="for some fields but not all"), otherwise("for none")),
        _fold_interface),
    Finding(
        "folding-axons", "3.7", "7a-b",
        "The direction of the axons does affect the pattern and magnitude of |b|, as the "
        "gradient between cortex and subcortex is greater when the axons are normal to the "
        "cortex (second and third columns in Fig. 7a), as opposed to the case in which "
        "axons approach the interface tangentially (first column in Fig. 7a).",
        "axons normal to the interface give larger |b| there than tangential ones", FOLDING,
        "the mean |b| along the interface (burgers_interface_mean) of the fields the paper "
        "calls normal to the cortex, concentric and straight (Fig. 7a's second and third "
        "columns), against the one it calls tangential, curved (the first column); a second "
        "reading (straight normal, concentric tangential) reported beside it; not run where "
        f"the axons did not grow (theta_a_max - 1 < {AXON_GROWTH_MIN:g})",
        (B_UNSETTLED,
         Threshold("some", PARTLY, "a normal field above the tangential one, but not both "
                   "by more than it", "the mesh does not settle a smaller difference; the "
                   "paper states it for both normal fields"),
         otherwise("neither normal field above the tangential one")),
        _fold_axons),
    Finding(
        "folding-release", "3.7", "7c",
        "For the case in which the axon orientation is tangential to the interface, the "
        "incompatibility is less pronounced and the residual stress is also much lower.",
        "released, the residual stress is much lower for tangential axons", FOLDING,
        "the largest max principal stress after the release (max_principal_stress_released) "
        "of the tangential field (curved, Fig. 7a's first column) against each normal one "
        "(concentric, straight); a second reading (concentric tangential, straight normal) "
        "reported beside it; not run without a release or where the axons did not grow",
        (MUCH_LOWER,
         Threshold("lower", PARTLY, "lower than a normal field's, but not at most that "
                   "fraction of both", "'lower' without 'much', or for one normal field"),
         otherwise("not lower than either normal field's")),
        _fold_release),
)
