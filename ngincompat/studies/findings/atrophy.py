"""The findings of section 3.5, brain atrophy (Fig. 5): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from ngincompat.studies.findings.rule import (
    ABOUT,
    AGREES,
    AT_CAP,
    DIFFERS,
    FAILS,
    IMPOSED,
    NEAR,
    PARTLY,
    SOME,
    WARNED,
    Finding,
    Threshold,
    for_each,
    number,
    otherwise,
    within_about,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results


def _warned(r: Results, verdict: str, reason: str) -> tuple[str, str]:
    """"partly" for "agrees" on a run with warnings (threshold :data:`WARNED`)."""
    if verdict == AGREES and r.warnings:
        return PARTLY, "the run warns: " + "; ".join(w.split(":")[0] for w in r.warnings)
    return verdict, reason


def _atrophy_loss(f: Finding, r: Results) -> tuple[str, str, str]:
    loss = 100 * (1 - r.metrics["theta_min_reached"])
    cap = 100 * (1 - r.params["theta_min"])
    measured = f"largest volume loss {number(loss)} %; the cap 1 - theta_min = {number(cap)} %"
    if not within_about(f, loss, 30):
        return measured, DIFFERS, "not about 30 %"
    if within_about(f, cap, 30):
        return measured, IMPOSED, "the cap theta_min of the atrophy law gives the loss"
    return measured, *_warned(r, AGREES, "")


def _atrophy_gray(f: Finding, r: Results) -> tuple[str, str, str]:
    g, w = r.metrics["gray_volume_loss"], r.metrics["white_volume_loss"]
    gray, white = r.params["rate_gray"], r.params["rate_white"]
    measured = (f"volume loss gray {number(100 * g)} %, white {number(100 * w)} % (rates given: "
                f"gray {number(gray)}, white {number(white)})")
    if g <= w:
        return measured, DIFFERS, "gray matter does not lose more"
    if gray > white:
        return measured, IMPOSED, "the input rates order the losses"
    return measured, *_warned(r, AGREES, "")


def _near(f: Finding, r: Results, key: str) -> bool:
    """Is the peak ``key`` (its depth below the surface) near the gray-white interface?"""
    gray = r.params["gray_thickness"]
    return abs(r.metrics[key] - gray) <= f.limit("near") * gray


def _atrophy_burgers(f: Finding, r: Results) -> tuple[str, str, str]:
    share = r.metrics.get("burgers_interface_fraction", math.nan)
    volume = r.metrics.get("interface_band_volume_fraction", math.nan)
    verdict, reason = for_each({"the peak near the interface": _near(f, r, "burgers_peak_depth"),
                             "more of |b| than of the volume near it": share > volume}, FAILS)
    return (f"|b| peaks {number(r.metrics['burgers_peak_depth'])} cm below the surface, the "
            f"interface at {number(r.params['gray_thickness'])} cm; within a cortex's thickness "
            f"of it: {number(share)} of int |b| dV, {number(volume)} of the volume",
            *_warned(r, verdict, reason))


def _atrophy_stress(f: Finding, r: Results) -> tuple[str, str, str]:
    ratio = r.metrics.get("stress_interface_over_surface", math.nan)
    verdict, reason = for_each({"the peak near the interface": _near(f, r, "stress_peak_depth"),
                             "falling toward the surface": ratio > 1}, FAILS)
    return (f"the max principal stress peaks {number(r.metrics['stress_peak_depth'])} cm below "
            f"the surface, the interface at {number(r.params['gray_thickness'])} cm; mean at the "
            f"interface / at the surface = {number(ratio)}", *_warned(r, verdict, reason))



#: The rules of section 3.5.
FINDINGS = (
    Finding(
        "atrophy-loss", "3.5", "5a",
        "The maximum volume loss is about 30%.",
        "the largest volume loss is about 30 %", ("atrophy",),
        "atrophy: the largest local volume loss 1 - min theta (theta_min_reached), against "
        "30 % and against the cap 1 - theta_min of the atrophy law",
        (replace(ABOUT, when="the loss within {value:g} points of 30 %"),
         replace(AT_CAP, when="the loss and the cap 1 - theta_min both within the band above",
                 source="theta never passes theta_min (the exact update of "
                 "ngincompat.mechanics.atrophy), and theta_min = 0.7 is chosen from this "
                 "sentence (ngincompat.scenes.atrophy): a loss there is the cap's"),
         WARNED, otherwise("the loss outside it")),
        _atrophy_loss),
    Finding(
        "atrophy-gray", "3.5", "5c",
        "It can be observed from the different cross sections that atrophy takes place "
        "mostly on the outer gray matter while the inner white matter has almost no volume "
        "loss (Fig. 5c).",
        "atrophy takes place mostly in gray matter, white matter almost keeps its volume",
        ("atrophy",),
        "atrophy: the volume loss of gray and of white matter, against the order of the "
        "input rates rate_gray, rate_white (how small the white loss is: reported, not "
        "judged)",
        (Threshold("gray", AGREES, "gray matter loses more, with rate_gray <= rate_white",
                   "'mostly on the outer gray matter'; with the rates not ordered so, the "
                   "transport decides it"),
         replace(AT_CAP, when="gray matter loses more, with rate_gray > rate_white",
                 source="the input rates are chosen from this sentence, rate_white = 1/30 "
                 "of rate_gray (ngincompat.scenes.atrophy): the order is the inputs'"),
         WARNED, otherwise("white matter loses as much or more")),
        _atrophy_gray),
    Finding(
        "atrophy-burgers", "3.5", "5d",
        "Indeed, after computing the geometric incompatibility tensor G and the "
        "corresponding local Burgers vector density b for each of the planes of interest, "
        "we can observe that the degree of incompatibility characterized by the magnitude "
        "|b| is concentrated near the interface (Fig. 5d).",
        "|b| concentrates near the gray-white interface", ("atrophy",),
        "atrophy: the depth of the largest |b| along X1 from the centre (burgers_peak_depth) "
        "against the cortex's thickness gray_thickness; the share of int |b| dV within a "
        "cortex's thickness of the interface (burgers_interface_fraction) against that "
        "band's share of the volume",
        (NEAR, Threshold("concentrated", AGREES, "and the share of |b| above the share of "
                         "the volume", "'concentrated'"),
         replace(SOME, when="one of the two"), WARNED, otherwise("neither")),
        _atrophy_burgers),
    Finding(
        "atrophy-stress", "3.5", "5e",
        "Similar to |b|, stress sigma localizes at the interface between gray and white "
        "matter and decreases towards the outer brain surface.",
        "the largest principal stress localises at the interface, falling toward the surface",
        ("atrophy",),
        "atrophy: the depth of the largest max principal stress along X1 from the centre "
        "(stress_peak_depth) against gray_thickness; its mean in the band of the cortex at "
        "the interface over that at the surface (stress_interface_over_surface)",
        (NEAR, Threshold("falling", AGREES, "and the mean at the interface above that at the "
                         "surface", "'decreases towards the outer brain surface'"),
         replace(SOME, when="one of the two (a ratio not measured counts as failing)"),
         WARNED, otherwise("neither")),
        _atrophy_stress),
)
