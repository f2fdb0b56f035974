"""The findings of section 3.3, the disc (Fig. 3): the paper's words, the rules that
judge them and their measurements."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ngincompat.studies.findings.rule import (
    AGREES,
    DIFFERS,
    FAILS,
    ROUND_OFF,
    SOME,
    TRACTION_FREE,
    Finding,
    Threshold,
    at_most,
    finite,
    for_each,
    number,
    otherwise,
    profile,
)

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results


def _disc_b(f: Finding, r: Results) -> tuple[str, str, str]:
    e = r.metrics["b_eq22_error"]
    return (f"|b - b(eq. 22)| relative = {number(e)}", *at_most(f, "round_off", e, "error"))


def _disc_fibers(f: Finding, r: Results) -> tuple[str, str, str]:
    sr, st = np.nanmax(profile(r, "sigma_r")), np.nanmax(profile(r, "sigma_theta"))
    holds = sr > st
    return (f"radial fibers: max sigma_r = {number(sr)}, max sigma_theta = {number(st)} MPa",
            AGREES if holds else DIFFERS, "" if holds else "sigma_r is not the higher")


def _disc_radial(f: Finding, r: Results) -> tuple[str, str, str]:
    _, s = finite(r, "sigma_r", "R")
    rim = r.metrics["sigma_r_rim_rel"]
    tol = f.limit("traction_free")
    largest = np.max(np.abs(s))
    fails = [what for what, ok in (
        ("tension", s.min() >= -tol * largest),
        ("higher at the centre than at the rim", s[0] > 0 and s[0] > s[-1]),
        (f"vanishing at the rim ({number(rim)} of its largest)", rim <= tol)) if not ok]
    return (f"sigma_r {number(s[0])} MPa at the centre, {number(s.min())} at least, "
            f"{number(rim)} of its largest at the rim", DIFFERS if fails else AGREES,
            "not " + ", ".join(fails) if fails else "")


def _disc_theta(f: Finding, r: Results) -> tuple[str, str, str]:
    _, s = finite(r, "sigma_theta", "R")
    holds = s[0] > 0 > s[-1]
    return (f"sigma_theta {number(s[0])} MPa at the centre, {number(s[-1])} MPa at the rim",
            AGREES if holds else DIFFERS, "" if holds else "not tension to compression")


def _largest_stress(r: Results) -> float:
    return max(float(np.nanmax(np.abs(profile(r, k)))) for k in ("sigma_r", "sigma_theta"))


def _disc_energy(f: Finding, radial: Results, circumferential: Results) -> tuple[str, str, str]:
    ea, eb = radial.metrics["strain_energy"], circumferential.metrics["strain_energy"]
    sa, sb = _largest_stress(radial), _largest_stress(circumferential)
    return (f"strain energy radial {number(ea)}, circumferential {number(eb)} N mm; largest "
            f"|sigma_r|,"
            f" |sigma_theta| radial {number(sa)}, circumferential {number(sb)} MPa",
            *for_each({"the strain energy": eb < ea, "the stresses": sb < sa}, FAILS))



#: The rules of section 3.3.
FINDINGS = (
    Finding(
        "disc-b", "3.3", "3b",
        "For our example, we compute the local Burgers vector density and observe that it is "
        "circumferentially aligned on the plane (Fig. 3b).",
        "b is circumferential on the plane (eq. 22)", ("disc-radial",),
        "disc-radial: the largest |b - b(eq. 22)| over the largest |b| (b_eq22_error)",
        (ROUND_OFF, otherwise("the ratio above it")), _disc_b),
    Finding(
        "disc-fibers", "3.3", "3c",
        "When the fiber is radially distributed, stress along fiber direction is higher "
        "than the stress in the circumferential direction (Fig. 3c).",
        "radial fibers: the stress along the fibers is higher than the circumferential one",
        ("disc-radial",), "disc-radial: the largest sigma_r and sigma_theta along the radius",
        (Threshold("higher", AGREES, "max sigma_r above max sigma_theta", "'higher'"),
         otherwise("max sigma_r not above")),
        _disc_fibers),
    Finding(
        "disc-radial", "3.3", "3c, 3e",
        "The radial component of the stress is in tension and the stress is higher at the "
        "center compared to the periphery of the disk, where it vanishes because of the "
        "boundary condition.",
        "sigma_r is tension, highest at the centre, vanishing at the rim", ("disc-radial",),
        "disc-radial: sigma_r along the radius: its sign, its values at the centre and at "
        "the rim, and at the rim over its largest (sigma_r_rim_rel)",
        (Threshold("tension", AGREES, "sigma_r positive at the centre and above its value "
                   "at the rim, and nowhere below minus the rim's tolerance",
                   "'in tension', 'higher at the center compared to the periphery'"),
         replace(TRACTION_FREE, when="sigma_r at the rim " + TRACTION_FREE.when),
         otherwise("any of these fails")),
        _disc_radial),
    Finding(
        "disc-theta", "3.3", "3c, 3e",
        "The circumferential direction follows a more similar pattern compared to the "
        "previous cases, with tension at the center and gradually transitioning to "
        "compression at the outer layers just as in the simple tumor example.",
        "sigma_theta goes from tension at the centre to compression at the rim",
        ("disc-radial",), "disc-radial: sigma_theta at the centre and at the rim",
        (Threshold("sign", AGREES, "positive at the centre, negative at the rim",
                   "'tension at the center', 'compression at the outer layers'"),
         otherwise("not both")),
        _disc_theta),
    Finding(
        "disc-energy", "3.3", "3d",
        "If the fiber orientation is circumferential, the trends in the stress are similar "
        "but overall the stresses and strain energy are lower, particularly due to the lack "
        "of fibers in tension in the radial direction (Fig. 3d).",
        "circumferential fibers: lower stresses and strain energy",
        ("disc-radial", "disc-circumferential"),
        "disc-radial against disc-circumferential: the strain energy, and the largest "
        "|sigma_r|, |sigma_theta| along the radius",
        (Threshold("both", AGREES, "both lower for circumferential fibers",
                   "'the stresses and strain energy are lower'"),
         replace(SOME, when="one of the two"),
         otherwise("neither")),
        _disc_energy),
)
