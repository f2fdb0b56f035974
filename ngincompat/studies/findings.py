"""The paper's findings, section by section: each one a rule fixed from the paper's own words,
judged on the runs of ``ngincompat paper``.

A :class:`Finding` is its rule as data:

- ``quote``: the paper's sentence, verbatim (Lee et al. 2021, section ``section``, Fig.
  ``figure``; its mathematics in plain text: Fg, |b|, theta^g, X1), or "" for a check of
  ours that the paper does not state;
- ``measure``: what is computed, from which case's metrics or profiles;
- ``thresholds``: the thresholds (:class:`Threshold`) that give each verdict, each with its
  source: the paper's words, a mesh study, or, where neither gives a number, the reason for
  the choice;
- ``decide``: the measurement, ``decide(finding, *results)`` on the results
  (:class:`~ngincompat.workflow.results.Results`) of the cases ``needs``. It reads its
  numbers from the thresholds (:meth:`Finding.limit`), not from numbers of its own, and
  returns the measured value in words and numbers, the verdict and the reason.

The verdicts:

- ``agrees``: the rule's thresholds for agreement hold;
- ``partly``: a part of the statement holds (one of its cases, one of its trends), or the
  trend holds but the mesh does not settle it, or the run warns;
- ``differs``: the statement fails, with the reason measured;
- ``imposed``: the measured value is one the model is given (an input, or a cap that the
  model's growth cannot pass): that it is the paper's is no result, and the report counts it
  apart;
- ``not run``: a case it needs did not finish, or what it compares did not act.

Every rule can return every verdict it lists (``tests/test_findings.py`` gives each rule data
for each); the documentation's validation page shows the rules as a table
(``docs/_ext/finding_rules.py``).

Why one module: a rule's measurement reads its thresholds by name, and its thresholds' words
describe what the measurement computes; in one file the paper's sentence, the thresholds with
their sources and the code that applies them are read together, and cannot be changed apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ngincompat import names
from ngincompat.mechanics.fields import FOCUS_DEPTH

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

    def text(self):
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
    def verdicts(self):
        """The verdicts the rule gives (besides "not run"), in the order of its thresholds."""
        return tuple(dict.fromkeys(t.verdict for t in self.thresholds))

    @property
    def states(self):
        """What the paper states, as the report and the rules' table show it: the quote, or
        for a check of ours its claim, marked as ours."""
        return (f"\u201c{self.quote}\u201d" if self.quote else
                f"a check of ours, not the paper's: {self.claim}")

    def limit(self, name):
        """The value of the rule's threshold ``name``."""
        return {t.name: t.value for t in self.thresholds}[name]

    def judge(self, results):
        """(measured, verdict, reason) on ``results`` (label -> Results)."""
        missing = [k for k in self.needs if k not in results or not results[k].converged]
        if missing:
            return "", NOT_RUN, "not finished: " + ", ".join(missing)
        return self.decide(self, *(results[k] for k in self.needs))


def _g(v):
    return f"{v:.3g}"


def _percent(v):
    return f"{100 * v:+.3g} %"


def _profile(r, key, name="line"):
    return np.asarray(r.profile(name)[key], float)


def _finite(r, key, coord):
    """A profile and its coordinate where the profile is finite."""
    x, y = _profile(r, coord), _profile(r, key)
    ok = np.isfinite(y)
    return x[ok], y[ok]


def _ends(r, key, coord, inner=0.0):
    """Values of a profile near its two ends (``inner`` of its length in from each)."""
    x, y = _finite(r, key, coord)
    span = x[-1] - x[0]
    return (float(np.interp(x[0] + inner * span, x, y)),
            float(np.interp(x[-1] - inner * span, x, y)))


def _each(holds, fails="not for "):
    """The verdict of a statement about each of ``holds`` (a case or a part of the statement
    -> whether it holds): agrees if it holds for all, differs if for none, partly otherwise;
    the reason names those for which it does not, after ``fails``."""
    failing = [what for what, ok in holds.items() if not ok]
    verdict = AGREES if not failing else DIFFERS if len(failing) == len(holds) else PARTLY
    return verdict, "" if verdict == AGREES else fails + ", ".join(failing)


#: The reason's words before the parts of a statement that fail (:func:`_each`).
FAILS = "does not hold: "


def _falls(f, first, second, what):
    """Verdict of "``what`` falls from ``first`` to ``second``" (threshold ``falls``)."""
    if first > second * (1 + f.limit("falls")):
        return AGREES, ""
    return DIFFERS, f"{what} does not fall"


def _at_most(f, name, value, what):
    """Verdict of "``what`` = ``value`` is at most the threshold ``name``"."""
    limit = f.limit(name)
    return (AGREES, "") if value <= limit else (DIFFERS, f"{what} = {_g(value)} > {limit:g}")


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


def _otherwise(when):
    """The rule's "differs": the statement's negation, ``when``."""
    return Threshold("otherwise", DIFFERS, when, "the paper's statement, negated")


# --- 3.1 cube ------------------------------------------------------------------------------

def _cube_growth(f, r):
    """theta = 1 + X1 t / 4 (eq. 50) is 1.25 at X1 = 1, t = 1: given, not found."""
    theta = _profile(r, "theta")
    off = abs(theta.max() - 1.25)
    measured = f"theta from {_g(theta.min())} to {_g(theta.max())}"
    if off <= f.limit("at_cap"):
        return measured, IMPOSED, "theta is the prescribed growth of eq. (50), an input"
    return (measured, DIFFERS,
            f"|theta_max - 1.25| = {_g(off)}: the growth did not reach eq. (50)'s")


def _cube_curl(f, r):
    a, b = _ends(r, "curlFg_sq", "X1")
    return (f"Curl Fg : Curl Fg {_g(a)} at X1 = 0, {_g(b)} at X1 = 1 (1/mm^2)",
            *_falls(f, a, b, "Curl Fg : Curl Fg"))


def _cube_b_n1(f, r):
    b1 = np.nanmax(_profile(r, "|b_n1|"))
    b2 = np.nanmax(_profile(r, "|b_n2|"))
    return (f"max |b| on n1 = {_g(b1)}, on n2 = {_g(b2)} 1/mm",
            *_at_most(f, "round_off", b1 / b2, "|b_n1| / |b_n2|"))


def _cube_b_trend(f, r):
    a, b = _ends(r, "|b_n2|", "X1")
    closed = r.metrics.get("G_error_L2_rel", np.nan)
    return (f"|b| on n2: {_g(a)} at X1 = 0, {_g(b)} at X1 = 1 (1/mm); G against eq. (16): "
            f"relative L2 error {_g(closed)}", *_falls(f, a, b, "|b|"))


def _cube_stress(f, r):
    peaks = {k: float(np.nanmax(np.abs(_profile(r, k)))) for k in ("S11", "S22", "S33")}
    scale = max(peaks.values())
    s11 = _profile(r, "S11")
    faces = max(abs(s11[0]), abs(s11[-1])) / scale
    absent = [k for k, v in peaks.items() if v < f.limit("present") * scale]
    measured = ("max |S11|, |S22|, |S33| on the centre line "
                + ", ".join(_g(v) for v in peaks.values())
                + f" MPa; S11 on the faces X1 = 0, 1: {_g(faces)} of the largest")
    if absent:
        return measured, DIFFERS, "no residual stress in " + ", ".join(absent)
    return measured, *_at_most(f, "traction_free", faces, "|S11| on the faces / max |S|")


# --- 3.2 hemisphere ------------------------------------------------------------------------

HEMISPHERES = ("hemisphere-linear", "hemisphere-concave", "hemisphere-convex")
#: The |b| profiles are read this fraction of the radius in from the centre, a cone point of
#: the linear and concave profiles (grad theta jumps there), and from the surface.
INNER = 0.15


def _hemi_radial(f, *runs):
    v = max(r.metrics["b_radial_rel"] for r in runs)
    return (f"max |b| on radial planes / max |b|, largest of the three profiles = {_g(v)}",
            *_at_most(f, "round_off", v, "the ratio"))


def _meridional(r):
    """|b| on the meridional planes at R = INNER and 1 - INNER of the radius, and its
    relative change between them."""
    a, b = _ends(r, "|b_meridional|", "R", inner=INNER)
    return a, b, abs(a - b) / max(a, b)


def _hemi_profiles(f, concave, convex):
    c0, c1, _ = _meridional(concave)
    v0, v1, _ = _meridional(convex)
    return (f"|b| meridional at R = {INNER:g} and {1 - INNER:g} mm: concave {_g(c0)} -> "
            f"{_g(c1)}, convex {_g(v0)} -> {_g(v1)} (1/mm)",
            *_each({"the concave profile (falling)": c0 > c1,
                    "the convex profile (rising)": v0 < v1}, FAILS))


def _hemi_linear(f, linear, concave, convex):
    a, b, change = _meridional(linear)
    nonlinear = min(_meridional(concave)[2], _meridional(convex)[2])
    return (f"|b| meridional {_g(a)} -> {_g(b)} 1/mm from R = {INNER:g} to {1 - INNER:g} "
            f"mm ({_g(100 * change)} % change; concave and convex: at least "
            f"{_g(100 * nonlinear)} %)",
            *_each({"falling with R (more growth, less |b|)": a > b,
                    "a change smaller than the nonlinear profiles'": change < nonlinear}, FAILS))


def _tension_to_compression(r, key, coord):
    """Does the profile ``key`` go from tension to compression along ``coord``: positive
    somewhere, negative somewhere, its largest tension before its largest compression?"""
    _, s = _finite(r, key, coord)
    return bool(s.max() > 0 > s.min() and np.argmax(s) < np.argmin(s))


def _hemi_sign(f, concave, convex):
    ranges = ", ".join(f"{name} {_g(np.nanmax(_profile(r, 'sigma_thetatheta')))} to "
                       f"{_g(np.nanmin(_profile(r, 'sigma_thetatheta')))}"
                       for name, r in (("concave", concave), ("convex", convex)))
    return (f"sigma_thetatheta along R: {ranges} MPa",
            *_each({name: _tension_to_compression(r, "sigma_thetatheta", "R")
                    for name, r in (("concave", concave), ("convex", convex))}))


def _hemi_check(f, r):
    e = max(r.metrics["radial_sigma_rr_error"], r.metrics["radial_sigma_thetatheta_error"])
    return (f"largest deviation from the 1-D radial solution / max stress = {_g(e)}",
            *_at_most(f, "resolved", e, "deviation"))


# --- 3.3 disc -----------------------------------------------------------------------------

def _disc_b(f, r):
    e = r.metrics["b_eq22_error"]
    return (f"|b - b(eq. 22)| relative = {_g(e)}", *_at_most(f, "round_off", e, "error"))


def _disc_fibers(f, r):
    sr, st = np.nanmax(_profile(r, "sigma_r")), np.nanmax(_profile(r, "sigma_theta"))
    holds = sr > st
    return (f"radial fibers: max sigma_r = {_g(sr)}, max sigma_theta = {_g(st)} MPa",
            AGREES if holds else DIFFERS, "" if holds else "sigma_r is not the higher")


def _disc_radial(f, r):
    _, s = _finite(r, "sigma_r", "R")
    rim = r.metrics["sigma_r_rim_rel"]
    tol = f.limit("traction_free")
    largest = np.max(np.abs(s))
    fails = [what for what, ok in (
        ("tension", s.min() >= -tol * largest),
        ("higher at the centre than at the rim", s[0] > 0 and s[0] > s[-1]),
        (f"vanishing at the rim ({_g(rim)} of its largest)", rim <= tol)) if not ok]
    return (f"sigma_r {_g(s[0])} MPa at the centre, {_g(s.min())} at least, "
            f"{_g(rim)} of its largest at the rim", DIFFERS if fails else AGREES,
            "not " + ", ".join(fails) if fails else "")


def _disc_theta(f, r):
    _, s = _finite(r, "sigma_theta", "R")
    holds = s[0] > 0 > s[-1]
    return (f"sigma_theta {_g(s[0])} MPa at the centre, {_g(s[-1])} MPa at the rim",
            AGREES if holds else DIFFERS, "" if holds else "not tension to compression")


def _largest_stress(r):
    return max(float(np.nanmax(np.abs(_profile(r, k)))) for k in ("sigma_r", "sigma_theta"))


def _disc_energy(f, radial, circumferential):
    ea, eb = radial.metrics["strain_energy"], circumferential.metrics["strain_energy"]
    sa, sb = _largest_stress(radial), _largest_stress(circumferential)
    return (f"strain energy radial {_g(ea)}, circumferential {_g(eb)} N mm; largest |sigma_r|,"
            f" |sigma_theta| radial {_g(sa)}, circumferential {_g(sb)} MPa",
            *_each({"the strain energy": eb < ea, "the stresses": sb < sa}, FAILS))


# --- 3.4 cylinder -------------------------------------------------------------------------

def _cyl_b(f, r):
    e = r.metrics["b_eq27_error"]
    return f"|b - b(eq. 27)| relative = {_g(e)}", *_at_most(f, "round_off", e, "error")


def _cyl_trend(f, r):
    a, b = _ends(r, "|b_e3|", "X2")
    return (f"|b| on e3: {_g(a)} at the bottom, {_g(b)} at the top (1/mm; eq. 27: 1/4 and "
            "1/5)", *_falls(f, a, b, "|b|"))


def _cyl_rotation(f, r):
    """Fe is the rotation of eq. (56): about e3 at the rate -a along X1, and no stretch."""
    rate, expected = r.metrics["rotation_rate"], r.metrics["rotation_rate_expected"]
    d = r.metrics["Fe_rotation_deviation"]
    s = r.metrics["max_principal_stress"] / r.params["mu"]
    turns = abs(rate - expected) <= f.limit("rate") * abs(expected)
    rotation = d < f.limit("stretch")
    verdict = AGREES if turns and rotation else PARTLY if turns else DIFFERS
    reason = {AGREES: "", PARTLY: f"|Fe^T Fe - I| = {_g(d)} >= {f.limit('stretch'):g}",
              DIFFERS: "the rotation rate is not eq. (56)'s"}[verdict]
    return (f"Fe turns about e3 at {_g(rate)} rad/mm along X1 (eq. 56: {_g(expected)}); "
            f"largest |Fe^T Fe - I| = {_g(d)}, principal stress {_g(s)} mu", verdict, reason)


# --- 3.5 atrophy --------------------------------------------------------------------------

def _warned(r, verdict, reason):
    """"partly" for "agrees" on a run with warnings (threshold :data:`WARNED`)."""
    if verdict == AGREES and r.warnings:
        return PARTLY, "the run warns: " + "; ".join(w.split(":")[0] for w in r.warnings)
    return verdict, reason


def _within_about(f, value, paper):
    """Is ``value`` (in the paper's unit) the paper's number ``paper`` to its precision?"""
    return abs(value - paper) <= f.limit("about")


def _atrophy_loss(f, r):
    loss = 100 * (1 - r.metrics["theta_min_reached"])
    cap = 100 * (1 - r.params["theta_min"])
    measured = f"largest volume loss {_g(loss)} %; the cap 1 - theta_min = {_g(cap)} %"
    if not _within_about(f, loss, 30):
        return measured, DIFFERS, "not about 30 %"
    if _within_about(f, cap, 30):
        return measured, IMPOSED, "the cap theta_min of the atrophy law gives the loss"
    return measured, *_warned(r, AGREES, "")


def _atrophy_gray(f, r):
    g, w = r.metrics["gray_volume_loss"], r.metrics["white_volume_loss"]
    gray, white = r.params["rate_gray"], r.params["rate_white"]
    measured = (f"volume loss gray {_g(100 * g)} %, white {_g(100 * w)} % (rates given: "
                f"gray {_g(gray)}, white {_g(white)})")
    if g <= w:
        return measured, DIFFERS, "gray matter does not lose more"
    if gray > white:
        return measured, IMPOSED, "the input rates order the losses"
    return measured, *_warned(r, AGREES, "")


def _near(f, r, key):
    """Is the peak ``key`` (its depth below the surface) near the gray-white interface?"""
    gray = r.params["gray_thickness"]
    return abs(r.metrics[key] - gray) <= f.limit("near") * gray


def _atrophy_burgers(f, r):
    share = r.metrics.get("burgers_interface_fraction", math.nan)
    volume = r.metrics.get("interface_band_volume_fraction", math.nan)
    verdict, reason = _each({"the peak near the interface": _near(f, r, "burgers_peak_depth"),
                             "more of |b| than of the volume near it": share > volume}, FAILS)
    return (f"|b| peaks {_g(r.metrics['burgers_peak_depth'])} cm below the surface, the "
            f"interface at {_g(r.params['gray_thickness'])} cm; within a cortex's thickness "
            f"of it: {_g(share)} of int |b| dV, {_g(volume)} of the volume",
            *_warned(r, verdict, reason))


def _atrophy_stress(f, r):
    ratio = r.metrics.get("stress_interface_over_surface", math.nan)
    verdict, reason = _each({"the peak near the interface": _near(f, r, "stress_peak_depth"),
                             "falling toward the surface": ratio > 1}, FAILS)
    return (f"the max principal stress peaks {_g(r.metrics['stress_peak_depth'])} cm below "
            f"the surface, the interface at {_g(r.params['gray_thickness'])} cm; mean at the "
            f"interface / at the surface = {_g(ratio)}", *_warned(r, verdict, reason))


# --- 3.6 skin -----------------------------------------------------------------------------

FOOTPRINTS = names.FOOTPRINTS
SKIN = tuple(f"skin-{f}" for f in FOOTPRINTS)


def _skin_growth(f, *runs):
    theta = [r.metrics["theta_max"] for r in runs]
    top = 100 * (max(theta) - 1)
    cap = 100 * (min(r.params["theta_max"] for r in runs) - 1)
    measured = (f"largest area growth {_g(top)} % ("
                + ", ".join(f"{n} {_g(t)}" for n, t in zip(FOOTPRINTS, theta, strict=True))
                + f"); the Hill law's saturation {_g(cap)} %")
    if _within_about(f, top, 50):
        if _within_about(f, cap, 50):
            return measured, IMPOSED, "the saturation theta_max of the Hill law gives it"
        return measured, AGREES, ""
    if top / 50 <= f.limit("factor") and 50 / top <= f.limit("factor"):
        return measured, PARTLY, f"not about 50 %, within a factor {f.limit('factor'):g}"
    return measured, DIFFERS, "not about 50 %"


def _skin_order(f, *runs):
    """The expanders by mean growth over the footprint: the square most and the circle
    least; by less than the threshold ``unsettled`` apart from the next, not settled."""
    mean = dict(zip(FOOTPRINTS, (r.metrics["theta_mean_footprint"] for r in runs),
                    strict=True))
    order = sorted(mean, key=mean.get)
    measured = ("mean growth over the footprint, least to most: "
                + " < ".join(f"{n} {_g(mean[n])}" for n in order))
    close = [(a, b) for a, b in (order[:2], order[-2:])
             if mean[b] - mean[a] < f.limit("unsettled") * mean[a]]
    unsettled = "; ".join(f"{a} and {b} within {_g(100 * (mean[b] / mean[a] - 1))} %, "
                          "closer than the mesh settles" for a, b in close)
    if order[-1] != "square" or order[0] != "circle":
        return (measured, DIFFERS, "; ".join(filter(None, [
            f"the most is {order[-1]}, the least {order[0]}", unsettled])))
    return measured, PARTLY if close else AGREES, unsettled


def _skin_apex(f, *runs):
    """Per expander: the growth at the apex (the footprint's centre) near its largest, and
    |b| there a small part of its largest."""
    holds, parts = {}, []
    for name, r in zip(FOOTPRINTS, runs, strict=True):
        growth = (r.metrics["theta_apex"] - 1) / (r.metrics["theta_max"] - 1)
        b = r.metrics["burgers_apex"] / r.metrics["burgers_max"]
        holds[name] = growth >= f.limit("apex_growth") and b <= f.limit("apex_free")
        parts.append(f"{name} {_g(growth)} / {_g(b)}")
    return ("growth at the apex / largest growth, |b| at the apex / largest |b|: "
            + ", ".join(parts), *_each(holds))


def _skin_stress(f, *runs):
    contact = [r.metrics.get("min_principal_stress_contact_zone", math.nan) for r in runs]
    if not all(np.isfinite(contact)):
        return "", NOT_RUN, "no contact zone measured (the pressure expander)"
    unit = runs[0].metric_units.get("max_principal_stress_released", "MPa")
    scale = 1000 if unit == "MPa" else 1
    tension = scale * max(r.metrics["max_principal_stress_released"] for r in runs)
    compression = -scale * min(contact)
    measured = (f"released: the largest tension anywhere in the patch {_g(tension)} kPa "
                f"(where it lies is not measured), the largest compression in the former "
                f"contact zone {_g(compression)} kPa")
    if _within_about(f, tension, 40) and _within_about(f, compression, 40):
        return measured, AGREES, ""
    factor = f.limit("factor")
    if all(v > 0 and 40 / factor <= v <= 40 * factor for v in (tension, compression)):
        return measured, PARTLY, f"not about 40 kPa, within a factor {factor:g}"
    return measured, DIFFERS, f"not within a factor {factor:g} of 40 kPa"


# --- 3.7 folding --------------------------------------------------------------------------

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


def _fold_onset(f, *runs):
    onset = [r.metrics.get("onset_growth", math.nan) for r in runs]
    amp = [r.metrics.get("fold_amplitude", math.nan) for r in runs]
    return ("onset at theta_c = " + ", ".join(_g(o) for o in onset) + "; fold amplitude "
            + ", ".join(_g(a) for a in amp) + " cm (curved, concentric, straight)",
            *_each({axons: bool(np.isfinite(o)) and not (np.isfinite(a) and a <= 0)
                    for axons, o, a in zip(AXONS, onset, amp, strict=True)}))


def _fold_interface(f, *runs):
    depth = [r.metrics["burgers_max_depth"] for r in runs]
    t, h = runs[0].params["cortex_thickness"], runs[0].params["cortex_maxh"]
    return ("max |b| at depth " + ", ".join(_g(d) for d in depth)
            + f" cm (curved, concentric, straight); the interface is {_g(t)} cm deep",
            *_each({a: abs(d - t) <= f.limit("at_interface") * h
                    for a, d in zip(AXONS, depth, strict=True)}))


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


def _by_field(runs, metric):
    return dict(zip(AXONS, (r.metrics.get(metric, np.nan) for r in runs), strict=True))


def _readings(f, runs, values, compare, claim):
    """The verdict of the paper's reading (normal: :data:`NORMAL`, tangential:
    :data:`TANGENTIAL`) and, in the measured text beside it, the second reading's
    (:data:`SECOND_NORMAL`, :data:`SECOND_TANGENTIAL`). ``compare(f, values, normal,
    tangential)`` gives (strict, weak, text) for one normal field: agrees if strict holds
    for every normal field, differs if weak holds for none, partly otherwise; the reason
    says so of the ``claim``."""
    def judge(normal, tangential):
        tests = [compare(f, values, a, tangential) for a in normal]
        text = ", ".join(t for _, _, t in tests)
        verdict = (AGREES if all(s for s, _, _ in tests) else
                   PARTLY if any(w for _, w, _ in tests) else DIFFERS)
        return verdict, text

    verdict, text = judge(NORMAL, TANGENTIAL)
    second, second_text = judge(SECOND_NORMAL, SECOND_TANGENTIAL)
    length = runs[0].params["length"]
    angle = math.degrees(math.atan(length / (2 * FOCUS_DEPTH)))
    measured = (", ".join(f"{a} {_g(v)}" for a, v in values.items())
                + f". The paper's reading (normal to the cortex: concentric, straight; "
                f"tangential: curved): {text}: {verdict}. Second reading (normal: straight; "
                f"tangential: concentric): {second_text}: {second}, not the verdict. The "
                f"curved axons meet the interface at most {angle:.3g} degrees from its normal "
                "(ngincompat.mechanics.fields.axons), which the paper calls tangential")
    reason = {AGREES: "", PARTLY: f"{claim} against some normal field, not against every "
              f"one by the threshold ({text})",
              DIFFERS: f"{claim} against no normal field ({text})"}
    return measured, verdict, reason[verdict]


def _more(f, values, normal, tangential):
    """A normal field's interface |b| over the tangential one's: (strict, weak, text)."""
    change = values[normal] / values[tangential] - 1
    return (change > f.limit("unsettled"), change > 0,
            f"{normal} {_percent(change)} over {tangential}")


def _fold_axons(f, *runs):
    """The interface |b| of the normal fields against the tangential one's."""
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    values = _by_field(runs, "burgers_interface_mean")
    measured, verdict, reason = _readings(f, runs, values, _more,
                                          "the tangential field's |b| the smaller")
    return "burgers_interface_mean [1/cm]: " + measured, verdict, reason


def _lower(f, values, normal, tangential):
    """The tangential field's released stress over a normal one's: (strict, weak, text)."""
    ratio = values[tangential] / values[normal]
    return (ratio <= f.limit("much_lower"), ratio < 1,
            f"{tangential} {_percent(ratio - 1)} against {normal}")


def _fold_release(f, *runs):
    """The released stress of the tangential field against the normal fields'."""
    values = _by_field(runs, "max_principal_stress_released")
    if not all(np.isfinite(list(values.values()))):
        return "not released", NOT_RUN, "the runs end before the release"
    if idle := _axons_idle(runs):
        return "", NOT_RUN, idle
    measured, verdict, reason = _readings(f, runs, values, _lower,
                                          "the tangential field's stress much lower")
    return "max_principal_stress_released [kPa]: " + measured, verdict, reason


# --- the rules ----------------------------------------------------------------------------

#: Relative difference of two expanders' mean growth below which their order is not settled.
UNSETTLED = Threshold(
    "unsettled", PARTLY, "the order holds, but the square or the circle lies within "
    "{value:g} of the next expander (relative)",
    "the mesh: between the preview and the paper's resolution the circle-square difference "
    "moved by 0.9 % of the mean growth, from +0.07 % to -0.85 % (docs/measurements/"
    "paper-job.md, 'Section 3.6: preview against the paper's resolution'); 2 % is about "
    "twice that", 0.02)

#: Relative difference of the interface |b| of two axon fields below which the mesh does not
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
         _otherwise("|theta_max - 1.25| above it (the growth stopped short)")),
        _cube_growth),
    Finding(
        "cube-curl", "3.1", "1b, 1g",
        "Note, however, that even though the gradient of the volume change is constant, the "
        "incompatibility metric is not. [Fig. 1g:] ... while incompatibility decreases "
        "along X1 ...",
        "Curl Fg : Curl Fg is not constant although the growth gradient is; it falls where "
        "growth is larger", ("cube",),
        "cube: Curl Fg : Curl Fg on the centre line at X1 = 0 (first) and X1 = 1 (second)",
        (FALLS, _otherwise("it does not fall")), _cube_curl),
    Finding(
        "cube-b-n1", "3.1", "1d",
        "For the plane corresponding to the growth gradient, n = Fg e1 / |Fg e1|, the "
        "Burgers vector vanishes.",
        "b vanishes on the plane normal to the growth gradient (n1)", ("cube",),
        "cube: the largest |b| on the plane n1 over the largest on n2, on the centre line",
        (ROUND_OFF, _otherwise("the ratio above it")), _cube_b_n1),
    Finding(
        "cube-b-trend", "3.1", "1e",
        "Instead, maybe albeit surprisingly, the magnitude is greater in the region with "
        "least growth, and decreases as growth increases.",
        "|b| is largest where growth is least and decreases as growth increases (eq. 16)",
        ("cube",), "cube: |b| on n2 at X1 = 0 (least growth, first) and X1 = 1 (second)",
        (FALLS, _otherwise("it does not fall")), _cube_b_trend),
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
         _otherwise("a component below it, or S11 on the faces above it")),
        _cube_stress),
    Finding(
        "hemisphere-radial", "3.2", "2b-c",
        "As can be expected based on the previous example and the derivation for Curl Fg "
        "in eq. (15), the local Burgers vector density vanishes for the planes defined by "
        "the growth gradient n_r.",
        "b vanishes on the radial planes", HEMISPHERES,
        "the three profiles (hemisphere-linear, -concave, -convex): the largest |b| on the "
        "radial planes over the largest |b| (b_radial_rel, away from the e3 axis), the "
        "largest of the three",
        (ROUND_OFF, _otherwise("the ratio above it")), _hemi_radial),
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
         _otherwise("neither trend")),
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
         _otherwise("rising, by a change no smaller than the nonlinear profiles'")),
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
         _otherwise("in neither")),
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
         _otherwise("above it")),
        _hemi_check),
    Finding(
        "disc-b", "3.3", "3b",
        "For our example, we compute the local Burgers vector density and observe that it is "
        "circumferentially aligned on the plane (Fig. 3b).",
        "b is circumferential on the plane (eq. 22)", ("disc-radial",),
        "disc-radial: the largest |b - b(eq. 22)| over the largest |b| (b_eq22_error)",
        (ROUND_OFF, _otherwise("the ratio above it")), _disc_b),
    Finding(
        "disc-fibers", "3.3", "3c",
        "When the fiber is radially distributed, stress along fiber direction is higher "
        "than the stress in the circumferential direction (Fig. 3c).",
        "radial fibers: the stress along the fibers is higher than the circumferential one",
        ("disc-radial",), "disc-radial: the largest sigma_r and sigma_theta along the radius",
        (Threshold("higher", AGREES, "max sigma_r above max sigma_theta", "'higher'"),
         _otherwise("max sigma_r not above")),
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
         _otherwise("any of these fails")),
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
         _otherwise("not both")),
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
         _otherwise("neither")),
        _disc_energy),
    Finding(
        "cylinder-b", "3.4", "4b",
        "The Burgers vector is aligned with the fiber direction as expected based on eq. "
        "(27).",
        "b is along the fiber direction (eq. 27)", ("cylinder",),
        "cylinder: the largest |b - b(eq. 27)| over the largest |b| (b_eq27_error)",
        (ROUND_OFF, _otherwise("the ratio above it")), _cyl_b),
    Finding(
        "cylinder-trend", "3.4", "4b",
        "The local Burgers vector density b shows a small variation from greater values at "
        "the bottom of the fiber to smaller values at the top.",
        "|b| falls slightly from the bottom (no growth) to the top", ("cylinder",),
        "cylinder: |b| on e3 at the bottom (X2 = 0, no growth, first) and at the top "
        "(second); the size of the change is reported, not judged (eq. 27: a fifth)",
        (FALLS, _otherwise("it does not fall")), _cyl_trend),
    Finding(
        "cylinder-rotation", "3.4", "4c-d",
        "Numerically, Fig. 4c shows that the elastic deformation Fe from our finite element "
        "solution is actually a pure rotation around e3 that varies along X1 as expected.",
        "no residual stress: Fe is a pure rotation (eq. 55-56)", ("cylinder",),
        "cylinder: the angle of Fe about e3 along X1, its slope fitted (rotation_rate) "
        "against eq. (56)'s -a; the largest |Fe^T Fe - I| (Fe_rotation_deviation)",
        (Threshold("rate", AGREES, "the slope within {value:g} of -a (relative)",
                   "the closed form eq. (56); the fit is 1.5e-5 from it at the preview, "
                   "2.8e-6 at the paper's resolution (docs/_generated/scenes); 1e-3 is a "
                   "choice above both", 1e-3),
         Threshold("stretch", AGREES, "and |Fe^T Fe - I| below {value:g}",
                   "the mesh: 9.5e-3 at the preview, 2.6e-4 at the paper's resolution (docs/"
                   "measurements/paper-job.md); a stretch below 1 % is read as none", 0.01),
         Threshold("stretched", PARTLY, "the slope as eq. (56), the stretch not below it",
                   "the rotation holds, its purity is not resolved by the mesh"),
         _otherwise("the slope is not eq. (56)'s")),
        _cyl_rotation),
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
         WARNED, _otherwise("the loss outside it")),
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
         WARNED, _otherwise("white matter loses as much or more")),
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
         replace(SOME, when="one of the two"), WARNED, _otherwise("neither")),
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
         WARNED, _otherwise("neither")),
        _atrophy_stress),
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
         _otherwise("beyond that factor")),
        _skin_growth),
    Finding(
        "skin-order", "3.6", "6a",
        "The square expander results in the largest area growth and the circular expander "
        "yields the smallest growth.",
        "the square expander grows the most area, the circle the least", SKIN,
        "the four expanders: the mean area growth over the footprint (theta_mean_footprint)",
        (Threshold("order", AGREES, "the square most and the circle least, each apart from "
                   "the next by at least the mesh's margin below", "the paper's ranking"),
         UNSETTLED, _otherwise("the square not the most, or the circle not the least")),
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
         _otherwise("for none")),
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
         _otherwise("a sign wrong, or a magnitude beyond that factor")),
        _skin_stress),
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
         replace(SOME, when="some fields fold"), _otherwise("none folds")),
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
         replace(SOME, when="for some fields but not all"), _otherwise("for none")),
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
         _otherwise("neither normal field above the tangential one")),
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
         _otherwise("not lower than either normal field's")),
        _fold_release),
)


def judged(section, results):
    """(finding, measured, verdict, reason) of every finding of ``section``."""
    return [(f, *f.judge(results)) for f in FINDINGS if f.section == section]


#: The columns of the rules' table (:func:`rules`).
RULE_COLUMNS = ("section", "Fig.", "the paper's words", "measure",
                "thresholds and their sources", "verdicts")


def rules():
    """The rules as a table, one row per finding in the columns :data:`RULE_COLUMNS`: the
    thresholds as a list of "verdict: condition (source: ...)", the rest as text."""
    return [(f.section, f.figure, f.states, f.measure,
             [f"{t.verdict}: {t.text()} (source: {t.source})" for t in f.thresholds],
             ", ".join(f.verdicts))
            for f in FINDINGS]
