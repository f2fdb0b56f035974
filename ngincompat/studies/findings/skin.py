"""The findings of section 3.6, skin expansion (Fig. 6): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat import names
from ngincompat.studies.findings.rule import (
    ABOUT,
    AGREES,
    AT_CAP,
    DIFFERS,
    IMPOSED,
    NOT_RUN,
    PARTLY,
    SOME,
    Finding,
    Threshold,
    for_each,
    number,
    otherwise,
    within_about,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results

FOOTPRINTS = names.FOOTPRINTS
SKIN = tuple(f"skin-{f}" for f in FOOTPRINTS)


def _skin_growth(f: Finding, *runs: Results) -> tuple[str, str, str]:
    theta = [r.metrics["theta_max"] for r in runs]
    top = 100 * (max(theta) - 1)
    cap = 100 * (min(r.params["theta_max"] for r in runs) - 1)
    measured = (f"largest area growth {number(top)} % ("
                + ", ".join(f"{n} {number(t)}" for n, t in zip(FOOTPRINTS, theta, strict=True))
                + f"); the Hill law's saturation {number(cap)} %")
    if within_about(f, top, 50):
        if within_about(f, cap, 50):
            return measured, IMPOSED, "the saturation theta_max of the Hill law gives it"
        return measured, AGREES, ""
    if top / 50 <= f.limit("factor") and 50 / top <= f.limit("factor"):
        return measured, PARTLY, f"not about 50 %, within a factor {f.limit('factor'):g}"
    return measured, DIFFERS, "not about 50 %"


def _skin_order(f: Finding, *runs: Results) -> tuple[str, str, str]:
    """The expanders by mean growth over the footprint: the square most and the circle
    least; by less than the threshold ``unsettled`` apart from the next, not settled."""
    mean = dict(zip(FOOTPRINTS, (r.metrics["theta_mean_footprint"] for r in runs),
                    strict=True))
    order = sorted(mean, key=mean.get)  # type: ignore[arg-type]  # its own keys: no None
    measured = ("mean growth over the footprint, least to most: "
                + " < ".join(f"{n} {number(mean[n])}" for n in order))
    close = [(a, b) for a, b in (order[:2], order[-2:])
             if mean[b] - mean[a] < f.limit("unsettled") * mean[a]]
    unsettled = "; ".join(f"{a} and {b} within {number(100 * (mean[b] / mean[a] - 1))} %, "
                          "closer than the mesh settles" for a, b in close)
    if order[-1] != "square" or order[0] != "circle":
        return (measured, DIFFERS, "; ".join(filter(None, [
            f"the most is {order[-1]}, the least {order[0]}", unsettled])))
    return measured, PARTLY if close else AGREES, unsettled


def _skin_apex(f: Finding, *runs: Results) -> tuple[str, str, str]:
    """Per expander: the growth at the apex (the footprint's centre) near its largest, and
    |b| there a small part of its largest."""
    holds, parts = {}, []
    for name, r in zip(FOOTPRINTS, runs, strict=True):
        growth = (r.metrics["theta_apex"] - 1) / (r.metrics["theta_max"] - 1)
        b = r.metrics["burgers_apex"] / r.metrics["burgers_max"]
        holds[name] = growth >= f.limit("apex_growth") and b <= f.limit("apex_free")
        parts.append(f"{name} {number(growth)} / {number(b)}")
    return ("growth at the apex / largest growth, |b| at the apex / largest |b|: "
            + ", ".join(parts), *for_each(holds))


def _skin_stress(f: Finding, *runs: Results) -> tuple[str, str, str]:
    contact = [r.metrics.get("min_principal_stress_contact_zone", math.nan) for r in runs]
    if not all(np.isfinite(contact)):
        return "", NOT_RUN, "no contact zone measured (the pressure expander)"
    unit = runs[0].metric_units.get("max_principal_stress_released", "MPa")
    scale = 1000 if unit == "MPa" else 1
    tension = scale * max(r.metrics["max_principal_stress_released"] for r in runs)
    compression = -scale * min(contact)
    measured = (f"released: the largest tension anywhere in the patch {number(tension)} kPa "
                f"(where it lies is not measured), the largest compression in the former "
                f"contact zone {number(compression)} kPa")
    if within_about(f, tension, 40) and within_about(f, compression, 40):
        return measured, AGREES, ""
    factor = f.limit("factor")
    if all(v > 0 and 40 / factor <= v <= 40 * factor for v in (tension, compression)):
        return measured, PARTLY, f"not about 40 kPa, within a factor {factor:g}"
    return measured, DIFFERS, f"not within a factor {factor:g} of 40 kPa"



#: Relative difference of two expanders' mean growth below which their order is not settled.
UNSETTLED = Threshold(
    "unsettled", PARTLY, "the order holds, but the square or the circle lies within "
    "{value:g} of the next expander (relative)",
    "the mesh: between the preview and the paper's resolution the circle-square difference "
    "moved by 0.9 % of the mean growth, from +0.07 % to -0.85 % (docs/measurements/"
    "paper-job.md, 'Section 3.6: preview against the paper's resolution'); 2 % is about "
    "twice that", 0.02)


#: The rules of section 3.6.
FINDINGS = (
    Finding(
        "skin-growth", "3.6", "6a",
        "Inflating the expanders to 50 cc induces area growth up to 50% with respect to the "
        "original area (Fig. 6a).",
        "inflating to 50 cc gives area growth up to 50 %", SKIN,
        "the four expanders: the largest area growth theta_max - 1 of any, against 50 % and "
        "against the Hill law's saturation theta_max - 1 (an input)",
        (replace(ABOUT, when="the growth within {value:g} points of 50 %"),
         replace(AT_CAP, when="the growth and the saturation both within the band above",
                 source="theta never passes the Hill law's saturation (eq. 46): a growth "
                 "there is the input's"),
         Threshold("factor", PARTLY, "within a factor {value:g} of 50 %",
                   "the Hill law's constants are not given in the paper: halving its rate k "
                   "moves the largest growth from 57 % to 32 % (docs/measurements/skin.md, "
                   "'Sensitivity of the expanders' order')", 2.0),
         otherwise("beyond that factor")),
        _skin_growth),
    Finding(
        "skin-order", "3.6", "6a",
        "The square expander results in the largest area growth and the circular expander "
        "yields the smallest growth.",
        "the square expander grows the most area, the circle the least", SKIN,
        "the four expanders: the mean area growth over the footprint (theta_mean_footprint)",
        (Threshold("order", AGREES, "the square most and the circle least, each apart from "
                   "the next by at least the mesh's margin below", "the paper's ranking"),
         UNSETTLED, otherwise("the square not the most, or the circle not the least")),
        _skin_order),
    Finding(
        "skin-apex", "3.6", "6a-b",
        "In all cases, the growth field is characterized by greater area gains at the apex "
        "of the expander and gradually less toward the periphery of the expanded region. "
        "... The apex has the largest growth theta^g, but it is actually free of "
        "incompatibility.",
        "growth peaks at the apex, which is free of incompatibility", SKIN,
        "each expander: the area growth theta - 1 at the apex (the footprint's centre) over "
        "its largest, and |b| at the apex over its largest",
        (Threshold("apex_growth", AGREES, "for every expander the growth at the apex at "
                   "least {value:g} of the largest",
                   "'the apex has the largest growth'; the largest is sampled anywhere, the "
                   "apex at a point: at the defaults the apex's growth is 0.957 of the "
                   "largest on the crescent (theta 1.575 against 1.601), above 0.99 on the "
                   "other three (docs/measurements/skin.md, 'Against the paper'); 0.95 is a "
                   "choice just below", 0.95),
         Threshold("apex_free", AGREES, "and |b| at the apex at most {value:g} of the "
                   "largest",
                   "'free of incompatibility': |b| of the projected G at the apex is "
                   "0.1-0.4 % of the largest on three expanders at the defaults (docs/"
                   "measurements/skin.md, 'Against the paper'); 0.05 is ten times that", 0.05),
         replace(SOME, when="for some expanders but not all"),
         otherwise("for none")),
        _skin_apex),
    Finding(
        "skin-stress", "3.6", "6c",
        "Tension of about 40 kPa occurs at the base, with regions of 40 kPa compression at "
        "the zones of contact between expander and skin, which also have large "
        "incompatibility in terms of |b|.",
        "after deflation about 40 kPa tension and 40 kPa compression where the expander "
        "touched", SKIN,
        "the four expanders, released: the largest max principal stress anywhere in the "
        "patch (where it lies, at the base or not, is not measured) and the largest "
        "compression (smallest principal stress) over the former contact zone, in kPa",
        (replace(ABOUT, when="tension and compression both within {value:g} kPa of 40 kPa"),
         Threshold("factor", PARTLY, "tension and compression both within a factor "
                   "{value:g} of 40 kPa",
                   "the skin's shear modulus, not given in section 3.6: the two readings "
                   "(0.55 MPa of ref. [77], 0.1786 MPa of Buganza Tepole et al. 2011) move "
                   "every stress by 3.1 times, growth unchanged (the deviation table, "
                   "measured on the rectangle)", 3.1),
         otherwise("a sign wrong, or a magnitude beyond that factor")),
        _skin_stress),
)
