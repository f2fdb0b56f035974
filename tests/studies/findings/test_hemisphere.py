"""ngincompat.studies.findings.hemisphere: the rules of section 3.2 on synthetic results."""

# the three profiles, |b| ~ theta^(-4/3) |grad theta| along R (eq. 16)

import numpy as np
from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies.findings import AGREES, DIFFERS, PARTLY, hemisphere

R = np.linspace(0.0, 1.0, 21)
PROFILES = {"linear": (R, np.ones_like(R)), "concave": (2 * R - R * R, 2 - 2 * R),
            "convex": (R * R, 2 * R)}


def burgers(profile):
    f, slope = PROFILES[profile]
    return (1 + f / 4) ** (-4 / 3) * slope / 12


def hemispheres(linear=None, concave=None, convex=None, hoop=(None, None), radial=1e-16):
    """The three profiles (|b| meridional of eq. 16 unless given, the hoop stress going from
    tension to compression unless given) and the symmetric check."""
    given = {"linear": linear, "concave": concave, "convex": convex}
    hoops = {"linear": None, "concave": hoop[0], "convex": hoop[1]}
    out = {f"hemisphere-{p}": run(
        {"b_radial_rel": radial},
        {"R": R, "|b_meridional|": burgers(p) if given[p] is None else given[p],
         "sigma_thetatheta": 1e-2 * (1 - 2 * R) if hoops[p] is None else hoops[p]})
        for p in PROFILES}
    out["hemisphere-linear-symmetry"] = run({"radial_sigma_rr_error": 6.7e-4,
                                              "radial_sigma_thetatheta_error": 6.7e-4})
    return out


def symmetric(error):
    return {"hemisphere-linear-symmetry": run({"radial_sigma_rr_error": error,
                                               "radial_sigma_thetatheta_error": error})}


#: Per rule: verdict -> results that must give it.
CASES = {
    "hemisphere-radial": {AGREES: hemispheres(), DIFFERS: hemispheres(radial=0.1)},
    "hemisphere-profiles": {
        AGREES: hemispheres(), PARTLY: hemispheres(convex=burgers("convex")[::-1]),
        DIFFERS: hemispheres(concave=burgers("concave")[::-1],
                             convex=burgers("convex")[::-1])},
    "hemisphere-linear": {
        AGREES: hemispheres(),
        PARTLY: hemispheres(linear=burgers("linear")[::-1]),           # rising, small
        DIFFERS: hemispheres(linear=burgers("convex"))},           # rising, as the convex
    "hemisphere-sign": {
        AGREES: hemispheres(), PARTLY: hemispheres(hoop=(None, 1e-2 * (2 * R - 1))),
        DIFFERS: hemispheres(hoop=(1e-2 * (2 * R - 1), 1e-2 * (1 + R)))},
    "hemisphere-check": {AGREES: symmetric(6.7e-4), DIFFERS: symmetric(0.151)},
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(hemisphere.FINDINGS, CASES)


def _rule(key):
    return rule_of(hemisphere.FINDINGS, key)


def test_the_radial_planes_are_judged_on_the_largest_of_the_three_profiles():
    """b_radial_rel of round-off on two profiles and 1e-3 on the third: "differs"."""
    out = hemispheres()
    out["hemisphere-convex"].metrics["b_radial_rel"] = 1e-3
    measured, verdict, _ = _rule("hemisphere-radial").judge(out)
    assert verdict == DIFFERS and measured.endswith("= 0.001")


def test_the_check_reads_the_larger_of_the_two_stress_deviations():
    out = {"hemisphere-linear-symmetry": run({"radial_sigma_rr_error": 1e-4,
                                              "radial_sigma_thetatheta_error": 0.05})}
    _, verdict, reason = _rule("hemisphere-check").judge(out)
    assert verdict == DIFFERS and reason == "deviation = 0.05 > 0.02"


def test_a_hoop_stress_whose_compression_comes_first_is_no_transition():
    """Tension and compression both present, but compression at the centre: not "from
    tension to compression" along R."""
    _, verdict, reason = _rule("hemisphere-sign").judge(
        hemispheres(hoop=(1e-2 * (2 * R - 1), None)))
    assert verdict == PARTLY and reason == "not for concave"
