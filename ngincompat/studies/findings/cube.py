"""The findings of section 3.1, the cube (Fig. 1): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat.studies.findings.rule import (
    AGREES,
    AT_CAP,
    DIFFERS,
    FALLS,
    IMPOSED,
    ROUND_OFF,
    TRACTION_FREE,
    Finding,
    Threshold,
    at_most,
    ends,
    falls,
    number,
    otherwise,
    profile,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results


def _cube_growth(f: Finding, r: Results) -> tuple[str, str, str]:
    """theta = 1 + X1 t / 4 (eq. 50) is 1.25 at X1 = 1, t = 1: given, not found."""
    theta = profile(r, "theta")
    off = abs(theta.max() - 1.25)
    measured = f"theta from {number(theta.min())} to {number(theta.max())}"
    if off <= f.limit("at_cap"):
        return measured, IMPOSED, "theta is the prescribed growth of eq. (50), an input"
    return (measured, DIFFERS,
            f"|theta_max - 1.25| = {number(off)}: the growth did not reach eq. (50)'s")


def _cube_curl(f: Finding, r: Results) -> tuple[str, str, str]:
    a, b = ends(r, "curlFg_sq", "X1")
    return (f"Curl Fg : Curl Fg {number(a)} at X1 = 0, {number(b)} at X1 = 1 (1/mm^2)",
            *falls(f, a, b, "Curl Fg : Curl Fg"))


def _cube_b_n1(f: Finding, r: Results) -> tuple[str, str, str]:
    b1 = np.nanmax(profile(r, "|b_n1|"))
    b2 = np.nanmax(profile(r, "|b_n2|"))
    return (f"max |b| on n1 = {number(b1)}, on n2 = {number(b2)} 1/mm",
            *at_most(f, "round_off", b1 / b2, "|b_n1| / |b_n2|"))


def _cube_b_trend(f: Finding, r: Results) -> tuple[str, str, str]:
    a, b = ends(r, "|b_n2|", "X1")
    closed = r.metrics.get("G_error_L2_rel", np.nan)
    return (f"|b| on n2: {number(a)} at X1 = 0, {number(b)} at X1 = 1 (1/mm); G against eq. (16): "
            f"relative L2 error {number(closed)}", *falls(f, a, b, "|b|"))


def _cube_stress(f: Finding, r: Results) -> tuple[str, str, str]:
    peaks = {k: float(np.nanmax(np.abs(profile(r, k)))) for k in ("S11", "S22", "S33")}
    scale = max(peaks.values())
    s11 = profile(r, "S11")
    faces = max(abs(s11[0]), abs(s11[-1])) / scale
    absent = [k for k, v in peaks.items() if v < f.limit("present") * scale]
    measured = ("max |S11|, |S22|, |S33| on the centre line "
                + ", ".join(number(v) for v in peaks.values())
                + f" MPa; S11 on the faces X1 = 0, 1: {number(faces)} of the largest")
    if absent:
        return measured, DIFFERS, "no residual stress in " + ", ".join(absent)
    return measured, *at_most(f, "traction_free", faces, "|S11| on the faces / max |S|")



#: The rules of section 3.1.
FINDINGS = (
    Finding(
        "cube-growth", "3.1", "1a",
        "This function leads to a 25% volume increase across the domain (Fig. 1a).",
        "theta = 1 + X1 t / 4 gives a 25 % volume increase across the cube", ("cube",),
        "cube: theta along the centre line, its largest value against 1.25",
        (replace(AT_CAP, value=1e-3, when="|theta_max - 1.25| at most {value:g}",
                 source="theta is the prescribed growth of eq. (50), an input: at t = 1 it "
                 "is 1.25 at X1 = 1 whatever the solution; 1e-3 is a choice far below the "
                 "25 % and far above round-off"),
         otherwise("|theta_max - 1.25| above it (the growth stopped short)")),
        _cube_growth),
    Finding(
        "cube-curl", "3.1", "1b, 1g",
        "Note, however, that even though the gradient of the volume change is constant, the "
        "incompatibility metric is not. [Fig. 1g:] ... while incompatibility decreases "
        "along X1 ...",
        "Curl Fg : Curl Fg is not constant although the growth gradient is; it falls where "
        "growth is larger", ("cube",),
        "cube: Curl Fg : Curl Fg on the centre line at X1 = 0 (first) and X1 = 1 (second)",
        (FALLS, otherwise("it does not fall")), _cube_curl),
    Finding(
        "cube-b-n1", "3.1", "1d",
        "For the plane corresponding to the growth gradient, n = Fg e1 / |Fg e1|, the "
        "Burgers vector vanishes.",
        "b vanishes on the plane normal to the growth gradient (n1)", ("cube",),
        "cube: the largest |b| on the plane n1 over the largest on n2, on the centre line",
        (ROUND_OFF, otherwise("the ratio above it")), _cube_b_n1),
    Finding(
        "cube-b-trend", "3.1", "1e",
        "Instead, maybe albeit surprisingly, the magnitude is greater in the region with "
        "least growth, and decreases as growth increases.",
        "|b| is largest where growth is least and decreases as growth increases (eq. 16)",
        ("cube",), "cube: |b| on n2 at X1 = 0 (least growth, first) and X1 = 1 (second)",
        (FALLS, otherwise("it does not fall")), _cube_b_trend),
    Finding(
        "cube-stress", "3.1", "1f",
        "There are residual stresses in all three directions. ... The stress on the faces "
        "with normal e1 or -e1 have zero stress, as required.",
        "residual stresses in all three directions; S11 vanishes on the faces normal to e1",
        ("cube",),
        "cube: the largest |S11|, |S22|, |S33| on the centre line against the largest of "
        "them; |S11| on the faces X1 = 0, 1 against it",
        (Threshold("present", AGREES, "each component's largest at least {value:g} of the "
                   "largest", "'in all three directions': the paper gives no size; a "
                   "choice far above round-off", 0.01),
         replace(TRACTION_FREE, when="|S11| on the faces " + TRACTION_FREE.when),
         otherwise("a component below it, or S11 on the faces above it")),
        _cube_stress),
)
