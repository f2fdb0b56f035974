"""The paper's findings, section by section, each measured on the runs of ``ngincompat paper``
and given a verdict.

A :class:`Finding` quotes what the paper states (Lee et al. 2021, section 3.x) and measures it
on the results of the section's cases (label -> :class:`~ngincompat.workflow.results.Results`,
read back from their folders): the measured value in words and numbers, and a verdict:
``agrees``, ``partly`` (the trend holds but a value is off, or the run carries a warning),
``differs`` (with the reason measured), or ``not run`` (a case it needs did not finish).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

AGREES, PARTLY, DIFFERS, NOT_RUN = "agrees", "partly", "differs", "not run"


@dataclass(frozen=True)
class Finding:
    """A statement of the paper (``claim``, its figure) and how it is measured: ``measure``
    takes the section's results by case and returns (measured value, verdict, reason)."""

    section: str
    claim: str
    figure: str
    needs: tuple
    measure: Callable

    def judge(self, results):
        """(measured, verdict, reason) on ``results`` (label -> Results)."""
        if not all(k in results and results[k].converged for k in self.needs):
            missing = [k for k in self.needs if k not in results or not results[k].converged]
            return "", NOT_RUN, "not finished: " + ", ".join(missing)
        return self.measure(*(results[k] for k in self.needs))


def _g(v):
    return f"{v:.3g}"


def _profile(r, key, name="line"):
    return np.asarray(r.profile(name)[key], float)


def _ends(r, key, coord, inner=0.1):
    """Values of a profile near its two ends (``inner`` of its length in from each)."""
    x, y = _profile(r, coord), _profile(r, key)
    ok = np.isfinite(y)
    x, y = x[ok], y[ok]
    span = x[-1] - x[0]
    return (float(np.interp(x[0] + inner * span, x, y)),
            float(np.interp(x[-1] - inner * span, x, y)))


def _larger(a, b, what, tol=0.0):
    """Verdict of "a exceeds b" (by more than ``tol`` relative)."""
    holds = a > b * (1 + tol)
    return AGREES if holds else DIFFERS, "" if holds else f"{what} goes the other way"


def _below(value, limit, what):
    return (AGREES, "") if value <= limit else (DIFFERS, f"{what} = {_g(value)} > {limit}")


# --- 3.1 cube ------------------------------------------------------------------------------

def _cube_growth(r):
    theta = _profile(r, "theta")
    return (f"theta from {_g(theta.min())} to {_g(theta.max())}",
            *_below(abs(theta.max() - 1.25), 1e-3, "|theta_max - 1.25|"))


def _cube_curl(r):
    a, b = _ends(r, "curlFg_sq", "X1", inner=0.0)
    verdict, reason = _larger(a, b, "Curl Fg : Curl Fg", tol=1e-3)
    return f"Curl Fg : Curl Fg {_g(a)} at X1 = 0, {_g(b)} at X1 = 1 (1/mm^2)", verdict, reason


def _cube_b_n1(r):
    b1 = np.nanmax(_profile(r, "|b_n1|"))
    b2 = np.nanmax(_profile(r, "|b_n2|"))
    return (f"max |b| on n1 = {_g(b1)}, on n2 = {_g(b2)} 1/mm",
            *_below(b1 / b2, 1e-8, "|b_n1| / |b_n2|"))


def _cube_b_trend(r):
    a, b = _ends(r, "|b_n2|", "X1", inner=0.0)
    verdict, reason = _larger(a, b, "|b|")
    closed = r.metrics.get("G_error_L2_rel", np.nan)
    return (f"|b| on n2: {_g(a)} at X1 = 0, {_g(b)} at X1 = 1 (1/mm); G against eq. (16): "
            f"relative L2 error {_g(closed)}", verdict, reason)


def _cube_stress(r):
    s11 = _profile(r, "S11")
    scale = max(np.nanmax(np.abs(_profile(r, k))) for k in ("S11", "S22", "S33"))
    ends = max(abs(s11[0]), abs(s11[-1])) / scale
    verdict, reason = _below(ends, 0.05, "|S11| on the faces X1 = 0, 1 / max |S|")
    return (f"max |S| = {_g(scale)} MPa on the centre line; S11 on the faces X1 = 0, 1: "
            f"{_g(ends)} of it", verdict, reason)


# --- 3.2 hemisphere ------------------------------------------------------------------------

def _hemi_radial(r):
    v = r.metrics["b_radial_rel"]
    return f"max |b| on radial planes / max |b| = {_g(v)}", *_below(v, 1e-3, "ratio")


def _hemi_profile(concave, convex):
    c0, c1 = _ends(concave, "|b_meridional|", "R", inner=0.15)
    v0, v1 = _ends(convex, "|b_meridional|", "R", inner=0.15)
    down, up = c0 > c1, v0 < v1
    verdict = AGREES if down and up else (PARTLY if down or up else DIFFERS)
    return (f"|b| meridional at R = 0.15 and 0.85 mm: concave {_g(c0)} -> {_g(c1)}, convex "
            f"{_g(v0)} -> {_g(v1)} (1/mm)", verdict,
            "" if verdict == AGREES else "a profile's trend is the other way")


def _hemi_linear(r):
    a, b = _ends(r, "|b_meridional|", "R", inner=0.15)
    change = abs(a - b) / max(a, b)
    verdict = AGREES if a > b and change < 0.3 else DIFFERS
    return (f"|b| meridional {_g(a)} -> {_g(b)} 1/mm from R = 0.15 to 0.85 mm "
            f"({_g(100 * change)} % change)", verdict,
            "" if verdict == AGREES else "not a small decrease")


def _hemi_sign(r):
    s = _profile(r, "sigma_thetatheta")
    s = s[np.isfinite(s)]
    holds = s.min() < 0 < s.max()
    return (f"sigma_thetatheta from {_g(s.max())} to {_g(s.min())} MPa along R",
            AGREES if holds else DIFFERS, "" if holds else "no change of sign")


def _hemi_check(r):
    e = max(r.metrics["radial_sigma_rr_error"], r.metrics["radial_sigma_thetatheta_error"])
    return (f"largest deviation from the 1-D radial solution / max stress = {_g(e)}",
            *_below(e, 0.02, "deviation"))


# --- 3.3 disc -----------------------------------------------------------------------------

def _disc_b(r):
    return (f"|b - b(eq. 22)| relative = {_g(r.metrics['b_eq22_error'])}",
            *_below(r.metrics["b_eq22_error"], 1e-6, "error"))


def _disc_fibers(r):
    sr, st = np.nanmax(_profile(r, "sigma_r")), np.nanmax(_profile(r, "sigma_theta"))
    return (f"radial fibers: max sigma_r = {_g(sr)}, max sigma_theta = {_g(st)} MPa",
            *_larger(sr, st, "sigma_r against sigma_theta"))


def _disc_radial(r):
    s = _profile(r, "sigma_r")
    rim = r.metrics["sigma_r_rim_rel"]
    holds = s[0] > 0 and rim < 0.05 and s[0] >= np.nanmax(s) * 0.9
    return (f"sigma_r = {_g(s[0])} MPa at the centre, {_g(rim)} of its largest at the rim",
            AGREES if holds else DIFFERS, "" if holds else "not tension falling to zero")


def _disc_theta(r):
    s = _profile(r, "sigma_theta")
    holds = s[0] > 0 > s[-1]
    return (f"sigma_theta {_g(s[0])} MPa at the centre, {_g(s[-1])} MPa at the rim",
            AGREES if holds else DIFFERS, "" if holds else "no tension-compression")


def _disc_energy(radial, circumferential):
    a, b = radial.metrics["strain_energy"], circumferential.metrics["strain_energy"]
    return (f"strain energy radial {_g(a)}, circumferential {_g(b)} N mm",
            *_larger(a, b, "energy"))


# --- 3.4 cylinder -------------------------------------------------------------------------

def _cyl_b(r):
    e = r.metrics["b_eq27_error"]
    return f"|b - b(eq. 27)| relative = {_g(e)}", *_below(e, 1e-6, "error")


def _cyl_trend(r):
    a, b = _ends(r, "|b_e3|", "X2", inner=0.0)
    return (f"|b| on e3: {_g(a)} at the bottom, {_g(b)} at the top (1/mm)",
            *_larger(a, b, "|b|"))


def _cyl_rotation(r):
    """Fe is the rotation of eq. (56): about e3 at the rate -a along X1, and no stretch (its
    largest deviation, at element corners, falls with the mesh)."""
    rate, expected = r.metrics["rotation_rate"], r.metrics["rotation_rate_expected"]
    d = r.metrics["Fe_rotation_deviation"]
    s = r.metrics["max_principal_stress"] / r.params["mu"]
    turns = abs(rate - expected) <= 0.02 * abs(expected)
    verdict = AGREES if turns and d < 0.01 else PARTLY if turns else DIFFERS
    reason = {AGREES: "", PARTLY: f"|Fe^T Fe - I| = {_g(d)} >= 0.01 (the mesh)",
              DIFFERS: "the rotation rate is not eq. (56)'s"}[verdict]
    return (f"Fe turns about e3 at {_g(rate)} rad/mm along X1 (eq. 56: {_g(expected)}); "
            f"largest |Fe^T Fe - I| = {_g(d)}, principal stress {_g(s)} mu", verdict, reason)


# --- 3.5 atrophy --------------------------------------------------------------------------

def _warned(r, verdict, reason):
    if verdict == AGREES and r.warnings:
        return PARTLY, "the run warns: " + "; ".join(w.split(":")[0] for w in r.warnings)
    return verdict, reason


def _atrophy_loss(r):
    loss = 1 - r.metrics["theta_min_reached"]
    verdict, reason = ((AGREES, "") if 0.25 <= loss <= 0.35
                       else (DIFFERS, "largest loss outside 25-35 %"))
    return (f"largest volume loss {_g(100 * loss)} % (theta_min "
            f"{_g(r.params['theta_min'])})", *_warned(r, verdict, reason))


def _atrophy_gray(r):
    g, w = r.metrics["gray_volume_loss"], r.metrics["white_volume_loss"]
    verdict, reason = _larger(g, w, "loss")
    return (f"volume loss gray {_g(100 * g)} %, white {_g(100 * w)} %",
            *_warned(r, verdict, reason))


def _atrophy_depth(key, what):
    def measure(r):
        depth, gray = r.metrics[key], r.params["gray_thickness"]
        holds = abs(depth - gray) <= gray / 2
        reason = ("" if holds else f"its peak lies {_g(depth)} cm deep, not at the interface "
                  f"({_g(gray)} cm) within half the gray thickness")
        return (f"{what} peaks {_g(depth)} cm below the surface; interface at {_g(gray)} cm",
                *_warned(r, AGREES if holds else DIFFERS, reason))
    return measure


# --- 3.6 skin -----------------------------------------------------------------------------

FOOTPRINTS = ("rectangle", "circle", "square", "crescent")
SKIN = tuple(f"skin-{f}" for f in FOOTPRINTS)


def _skin_growth(*runs):
    theta = [r.metrics["theta_max"] for r in runs]
    top = max(theta) - 1
    verdict = AGREES if 0.4 <= top <= 0.6 else PARTLY if 0.25 <= top <= 0.8 else DIFFERS
    return (f"largest area growth {_g(100 * top)} % ("
            + ", ".join(f"{f} {_g(t)}" for f, t in zip(FOOTPRINTS, theta, strict=True)) + ")",
            verdict, "" if verdict == AGREES else "not about 50 %")


#: Relative difference of two expanders' mean growth below which their order is not
#: settled: the mean growth changes by a few per cent between the preview and the paper's
#: resolution, and the order of close expanders with it (docs/measurements/paper-job.md).
UNSETTLED = 0.02


def _skin_order(*runs):
    """The expanders by mean growth over the footprint; an order whose first or last two
    lie within :data:`UNSETTLED` of each other is not settled by the mesh: "partly" at best,
    and the reason says which."""
    mean = dict(zip(FOOTPRINTS, (r.metrics["theta_mean_footprint"] for r in runs),
                    strict=True))
    order = sorted(mean, key=mean.get)
    holds = order[-1] == "square" and order[0] == "circle"
    part = order[-1] == "square" or order[0] == "circle"
    close = [(a, b) for a, b in (order[:2], order[-2:])
             if mean[b] - mean[a] < UNSETTLED * mean[a]]
    verdict = AGREES if holds else PARTLY if part else DIFFERS
    why = "" if holds else "the order of the expanders differs"
    if close:
        verdict = PARTLY if verdict == AGREES else verdict
        why = "; ".join(filter(None, [why] + [
            f"{a} and {b} within {_g(100 * (mean[b] / mean[a] - 1))} %, closer than the mesh "
            "settles (docs/measurements/paper-job.md)" for a, b in close]))
    return ("mean growth over the footprint, least to most: "
            + " < ".join(f"{f} {_g(mean[f])}" for f in order), verdict, why)


def _skin_apex(*runs):
    """Per expander: growth at the apex (the footprint's centre) near its largest, and |b|
    there a small part of its largest."""
    holds = {}
    parts = []
    for f, r in zip(FOOTPRINTS, runs, strict=True):
        b = r.metrics["burgers_apex"] / r.metrics["burgers_max"]
        theta = r.metrics["theta_apex"] / r.metrics["theta_max"]
        holds[f] = b < 0.05 and theta > 0.95
        parts.append(f"{f} {_g(theta)} / {_g(b)}")
    count = sum(holds.values())
    verdict = AGREES if count == len(runs) else PARTLY if count >= 2 else DIFFERS
    return ("theta at the apex / max theta, |b| at the apex / max |b|: " + ", ".join(parts),
            verdict, "" if verdict == AGREES else "not for " + ", ".join(
                f for f, ok in holds.items() if not ok))


def _skin_stress(*runs):
    top = max(r.metrics["max_principal_stress_released"] for r in runs)
    low = min(r.metrics.get("min_principal_stress_contact_zone", np.nan) for r in runs)
    unit = runs[0].metric_units.get("max_principal_stress_released", "MPa")
    scale = 1000 if unit == "MPa" else 1
    within = 0.5 <= top * scale / 40 <= 2 and 0.5 <= -low * scale / 40 <= 2
    return (f"after deflation: tension up to {_g(top * scale)} kPa, compression in the "
            f"contact zone down to {_g(low * scale)} kPa", AGREES if within else PARTLY,
            "" if within else "the signs and places agree, the magnitudes are not within a "
            "factor 2 of 40 kPa (see the deviations: mu, the mesh)")


# --- 3.7 folding --------------------------------------------------------------------------

AXONS = ("curved", "concentric", "straight")
FOLDING = tuple(f"folding-{a}" for a in AXONS)


def _fold_onset(*runs):
    onset = [r.metrics.get("onset_growth", np.nan) for r in runs]
    amp = [r.metrics.get("fold_amplitude", np.nan) for r in runs]
    holds = all(np.isfinite(onset)) and all(a > 0 for a in amp if np.isfinite(a))
    return ("onset at theta_c = " + ", ".join(_g(o) for o in onset) + "; fold amplitude "
            + ", ".join(_g(a) for a in amp) + " cm (curved, concentric, straight)",
            AGREES if holds else DIFFERS, "" if holds else "no onset found")


def _fold_interface(*runs):
    depth = [r.metrics["burgers_max_depth"] for r in runs]
    t, h = runs[0].params["cortex_thickness"], runs[0].params["cortex_maxh"]
    holds = all(abs(d - t) <= 2 * h for d in depth)
    return ("max |b| at depth " + ", ".join(_g(d) for d in depth)
            + f" cm; the interface is {_g(t)} cm deep", AGREES if holds else DIFFERS,
            "" if holds else "a peak lies away from the interface")


#: Axon growth (theta_a - 1) below which an axon field has not acted on a run.
AXON_GROWTH_MIN = 1e-3


def _axons_idle(runs):
    """The reason the axon fields cannot be compared, or "": with theta_a = 1 everywhere
    (the stretch never passed its critical value before the run ended, as on the preview's
    short march) the three fields give the same growth, so equal or shuffled |b| and stress
    say nothing about their orientation."""
    grown = [r.metrics.get("theta_a_max", np.nan) - 1 for r in runs]
    if all(np.isfinite(grown)) and max(grown) >= AXON_GROWTH_MIN:
        return ""
    return ("the axons did not grow by the end of the run (theta_a_max - 1 = "
            + ", ".join(_g(g) for g in grown) + "): their orientation cannot act")


#: Released stress of the tangential axons at most this fraction of the normal ones': the
#: paper's "much lower".
MUCH_LOWER = 0.8


def _orientation(runs, metric, unit):
    """The three fields' ``metric`` by axon field, as the measured text: the normal
    (straight) and the tangential (concentric: arcs parallel to the interface) axons, and
    the curved ones, which fan out from a focus below and meet the interface within 27
    degrees of its normal (:func:`~ngincompat.mechanics.fields.axons`). The paper's text
    calls its first column, curved outward, the tangential one; its field is not given."""
    values = dict(zip(AXONS, (r.metrics.get(metric, np.nan) for r in runs), strict=True))
    text = (f"{metric}: straight (normal) {_g(values['straight'])}, concentric (tangential) "
            f"{_g(values['concentric'])}, curved (within 27 degrees of normal) "
            f"{_g(values['curved'])} {unit}")
    return values, text


#: Relative difference of the interface |b| of two axon fields below which it is not settled
#: by the mesh: the interface |b| of the creasing bilayer changes by up to 5 % between two
#: resolutions (docs/measurements/folding.md, "The fold shape at two resolutions").
B_UNSETTLED = 0.05


def _fold_axons(*runs):
    """Normal (straight) axons give the larger interface |b|; by less than
    :data:`B_UNSETTLED` it is "partly" at best (the mesh does not settle it)."""
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    b, text = _orientation(runs, "burgers_interface_mean", "1/cm")
    more = b["straight"] / b["concentric"] - 1
    if more <= 0:
        return text, DIFFERS, "the tangential (concentric) axons do not give the smaller |b|"
    if more < B_UNSETTLED:
        return (text, PARTLY, f"larger, but only by {_g(100 * more)} %, less than the "
                f"{_g(100 * B_UNSETTLED)} % the interface |b| changes under refinement")
    return text, AGREES, ""


def _fold_release(*runs):
    s, text = _orientation(runs, "max_principal_stress_released", "kPa")
    if not all(np.isfinite(list(s.values()))):
        return "not released", NOT_RUN, "the runs end before the release"
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    ratio = s["concentric"] / s["straight"]
    verdict = AGREES if ratio <= MUCH_LOWER else PARTLY if ratio < 1 else DIFFERS
    reason = {AGREES: "", PARTLY: f"lower, but only by {_g(100 * (1 - ratio))} %",
              DIFFERS: "the tangential (concentric) axons' stress is not the lower"}[verdict]
    return text, verdict, reason


FINDINGS = (
    Finding("3.1", "theta = 1 + X1 t / 4 gives a 25 % volume increase across the cube",
            "1a", ("cube",), _cube_growth),
    Finding("3.1", "Curl Fg : Curl Fg is not constant although the growth gradient is; it "
            "falls where growth is larger", "1b", ("cube",), _cube_curl),
    Finding("3.1", "b vanishes on the plane normal to the growth gradient (n1)", "1d",
            ("cube",), _cube_b_n1),
    Finding("3.1", "|b| is largest where growth is least and decreases as growth increases "
            "(eq. 16)", "1e", ("cube",), _cube_b_trend),
    Finding("3.1", "residual stresses in all three directions; S11 vanishes on the faces "
            "normal to e1", "1f", ("cube",), _cube_stress),
    Finding("3.2", "b vanishes on the radial planes", "2b-c", ("hemisphere-linear",),
            _hemi_radial),
    Finding("3.2", "growth fast at the core (concave): |b| highest at the core, falling "
            "outward; growth fast outside (convex): |b| rising with R", "2g",
            ("hemisphere-concave", "hemisphere-convex"), _hemi_profile),
    Finding("3.2", "constant growth rate (linear): |b| varies little with R, falling as "
            "growth grows", "2g", ("hemisphere-linear",), _hemi_linear),
    Finding("3.2", "the hoop stress goes from tension to compression along the radius",
            "2d-e", ("hemisphere-linear",), _hemi_sign),
    Finding("3.2", "(check) the 3-D stresses match the independent 1-D radial solution",
            "2d", ("hemisphere-linear-symmetry",), _hemi_check),
    Finding("3.3", "b is circumferential on the plane (eq. 22)", "3b", ("disc-radial",),
            _disc_b),
    Finding("3.3", "radial fibers: the stress along the fibers is higher than the "
            "circumferential one", "3c", ("disc-radial",), _disc_fibers),
    Finding("3.3", "sigma_r is tension, highest at the centre, vanishing at the rim", "3c, 3e",
            ("disc-radial",), _disc_radial),
    Finding("3.3", "sigma_theta goes from tension at the centre to compression at the rim",
            "3c, 3e", ("disc-radial",), _disc_theta),
    Finding("3.3", "circumferential fibers: lower stresses and strain energy", "3d",
            ("disc-radial", "disc-circumferential"), _disc_energy),
    Finding("3.4", "b is along the fiber direction (eq. 27)", "4b", ("cylinder",), _cyl_b),
    Finding("3.4", "|b| falls slightly from the bottom (no growth) to the top", "4b",
            ("cylinder",), _cyl_trend),
    Finding("3.4", "no residual stress: Fe is a pure rotation (eq. 55-56)", "4c-d",
            ("cylinder",), _cyl_rotation),
    Finding("3.5", "the largest volume loss is about 30 %", "5a", ("atrophy",),
            _atrophy_loss),
    Finding("3.5", "atrophy takes place mostly in gray matter, white matter almost keeps its "
            "volume", "5c", ("atrophy",), _atrophy_gray),
    Finding("3.5", "|b| concentrates near the gray-white interface", "5d", ("atrophy",),
            _atrophy_depth("burgers_peak_depth", "|b|")),
    Finding("3.5", "the largest principal stress localises at the interface", "5e",
            ("atrophy",), _atrophy_depth("stress_peak_depth", "the max principal stress")),
    Finding("3.6", "inflating to 50 cc gives area growth up to 50 %", "6a", SKIN,
            _skin_growth),
    Finding("3.6", "the square expander grows the most area, the circle the least", "6a",
            SKIN, _skin_order),
    Finding("3.6", "growth peaks at the apex, which is free of incompatibility", "6a-b", SKIN,
            _skin_apex),
    Finding("3.6", "after deflation about 40 kPa tension at the base and 40 kPa compression "
            "where the expander touched", "6c", SKIN, _skin_stress),
    Finding("3.7", "the growing cortex on its subcortex folds", "7a", FOLDING, _fold_onset),
    Finding("3.7", "|b| is largest at the cortex-subcortex interface", "7b", FOLDING,
            _fold_interface),
    Finding("3.7", "axons normal to the interface give larger |b| there than tangential ones",
            "7b", FOLDING, _fold_axons),
    Finding("3.7", "released, the residual stress is much lower for tangential axons",
            "7c", FOLDING, _fold_release),
)


def judged(section, results):
    """(finding, measured, verdict, reason) of every finding of ``section``."""
    return [(f, *f.judge(results)) for f in FINDINGS if f.section == section]
