"""The findings of section 3.2, the hemisphere (Fig. 2): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat.studies.findings.rule import (
    AGREES,
    FAILS,
    ROUND_OFF,
    SOME,
    Finding,
    Threshold,
    at_most,
    ends,
    finite,
    for_each,
    number,
    otherwise,
    profile,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results

HEMISPHERES = ("hemisphere-linear", "hemisphere-concave", "hemisphere-convex")
#: The |b| profiles are read this fraction of the radius in from the centre, a cone point of
#: the linear and concave profiles (grad theta jumps there), and from the surface.
INNER = 0.15


def _hemi_radial(f: Finding, *runs: Results) -> tuple[str, str, str]:
    v = max(r.metrics["b_radial_rel"] for r in runs)
    return (f"max |b| on radial planes / max |b|, largest of the three profiles = {number(v)}",
            *at_most(f, "round_off", v, "the ratio"))


def _meridional(r: Results) -> tuple[float, float, float]:
    """|b| on the meridional planes at R = INNER and 1 - INNER of the radius, and its
    relative change between them."""
    a, b = ends(r, "|b_meridional|", "R", inner=INNER)
    return a, b, abs(a - b) / max(a, b)


def _hemi_profiles(f: Finding, concave: Results, convex: Results) -> tuple[str, str, str]:
    c0, c1, _ = _meridional(concave)
    v0, v1, _ = _meridional(convex)
    return (f"|b| meridional at R = {INNER:g} and {1 - INNER:g} mm: concave {number(c0)} -> "
            f"{number(c1)}, convex {number(v0)} -> {number(v1)} (1/mm)",
            *for_each({"the concave profile (falling)": c0 > c1,
                    "the convex profile (rising)": v0 < v1}, FAILS))


def _hemi_linear(f: Finding, linear: Results, concave: Results,
                 convex: Results) -> tuple[str, str, str]:
    a, b, change = _meridional(linear)
    nonlinear = min(_meridional(concave)[2], _meridional(convex)[2])
    return (f"|b| meridional {number(a)} -> {number(b)} 1/mm from R = {INNER:g} to {1 - INNER:g} "
            f"mm ({number(100 * change)} % change; concave and convex: at least "
            f"{number(100 * nonlinear)} %)",
            *for_each({"falling with R (more growth, less |b|)": a > b,
                    "a change smaller than the nonlinear profiles'": change < nonlinear}, FAILS))


def _tension_to_compression(r: Results, key: str, coord: str) -> bool:
    """Does the profile ``key`` go from tension to compression along ``coord``: positive
    somewhere, negative somewhere, its largest tension before its largest compression?"""
    _, s = finite(r, key, coord)
    return bool(s.max() > 0 > s.min() and np.argmax(s) < np.argmin(s))


def _hemi_sign(f: Finding, concave: Results, convex: Results) -> tuple[str, str, str]:
    ranges = ", ".join(f"{name} {number(np.nanmax(profile(r, 'sigma_thetatheta')))} to "
                       f"{number(np.nanmin(profile(r, 'sigma_thetatheta')))}"
                       for name, r in (("concave", concave), ("convex", convex)))
    return (f"sigma_thetatheta along R: {ranges} MPa",
            *for_each({name: _tension_to_compression(r, "sigma_thetatheta", "R")
                    for name, r in (("concave", concave), ("convex", convex))}))


def _hemi_check(f: Finding, r: Results) -> tuple[str, str, str]:
    e = max(r.metrics["radial_sigma_rr_error"], r.metrics["radial_sigma_thetatheta_error"])
    return (f"largest deviation from the 1-D radial solution / max stress = {number(e)}",
            *at_most(f, "resolved", e, "deviation"))



#: The rules of section 3.2.
FINDINGS = (
    Finding(
        "hemisphere-radial", "3.2", "2b-c",
        "As can be expected based on the previous example and the derivation for Curl Fg "
        "in eq. (15), the local Burgers vector density vanishes for the planes defined by "
        "the growth gradient n_r.",
        "b vanishes on the radial planes", HEMISPHERES,
        "the three profiles (hemisphere-linear, -concave, -convex): the largest |b| on the "
        "radial planes over the largest |b| (b_radial_rel, away from the e3 axis), the "
        "largest of the three",
        (ROUND_OFF, otherwise("the ratio above it")), _hemi_radial),
    Finding(
        "hemisphere-profiles", "3.2", "2g",
        "Note that if the growth increases rapidly at the core compared to the outer region, "
        "the magnitude of the local Burgers vector density is higher at the core and "
        "decreases toward the outer layers as the growth gradient decreases (red curve in "
        "Fig. 2g). In contrast, when the growth shows an increasing gradient with respect to "
        "R, |b| increases with respect to R as well.",
        "growth fast at the core (concave): |b| highest at the core, falling outward; growth "
        "fast outside (convex): |b| rising with R",
        ("hemisphere-concave", "hemisphere-convex"),
        f"|b| on the meridional planes along the ray at R = {INNER:g} and {1 - INNER:g} of "
        "the radius (the centre is a cone point): falling on hemisphere-concave, rising on "
        "hemisphere-convex",
        (Threshold("both", AGREES, "both trends as stated", "the paper's two sentences"),
         replace(SOME, when="one of the two trends"),
         otherwise("neither trend")),
        _hemi_profiles),
    Finding(
        "hemisphere-linear", "3.2", "2g",
        "In such case, there is still a small variation in b as a function of R because, as "
        "discussed before, the magnitude of growth also contributes to b and not just the "
        "magnitude of the growth gradient. However, the scaling of b by the growth amount "
        "is barely noticeable when compared to the effect of the nonlinear functions "
        "theta^g(R) with large gradients |grad theta^g| relative to the growth theta^g.",
        "constant growth rate (linear): |b| varies little with R, falling as growth grows",
        HEMISPHERES,
        f"|b| meridional at R = {INNER:g} and {1 - INNER:g} of the radius: its direction on "
        "hemisphere-linear, and its relative change there against the smaller of "
        "hemisphere-concave's and -convex's",
        (Threshold("both", AGREES, "falling with R, by a smaller change than the nonlinear "
                   "profiles'", "the paper: growth 'also contributes' (more growth, less |b|,"
                   " eq. 16), 'barely noticeable when compared to' the nonlinear profiles"),
         replace(SOME, when="one of the two"),
         otherwise("rising, by a change no smaller than the nonlinear profiles'")),
        _hemi_linear),
    Finding(
        "hemisphere-sign", "3.2", "2d-e",
        "In either case, there is a transition from tension to compression along the radial "
        "direction, which has also been shown in [52].",
        "the hoop stress goes from tension to compression along the radius",
        ("hemisphere-concave", "hemisphere-convex"),
        "the hoop stress sigma_thetatheta along the ray on hemisphere-concave and -convex "
        "(the two cases of Figs. 2d-e): positive and negative, its largest tension nearer "
        "the centre than its largest compression",
        (Threshold("both", AGREES, "in both cases", "'In either case'"),
         replace(SOME, when="in one of the two"),
         otherwise("in neither")),
        _hemi_sign),
    Finding(
        "hemisphere-check", "3.2", "2d", "",
        "the 3-D stresses match the independent 1-D radial solution",
        ("hemisphere-linear-symmetry",),
        "hemisphere-linear-symmetry: the largest deviation of sigma_rr and sigma_thetatheta "
        "along the ray from the 1-D radial solution (ngincompat.references.radial), over "
        "the largest stress",
        (Threshold("resolved", AGREES, "at most {value:g}",
                   "the mesh: 0.151 at the preview, 6.7e-4 at the paper's resolution (docs/"
                   "measurements/paper-job.md, 'Sections 3.1-3.4: preview against the "
                   "paper's resolution'); 0.02 is a choice between", 0.02),
         otherwise("above it")),
        _hemi_check),
)
