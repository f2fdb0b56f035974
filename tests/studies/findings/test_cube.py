"""ngincompat.studies.findings.cube: the rules of section 3.1 on synthetic cube results."""

# theta = 1 + X1 / 4 at t = 1 (eq. 50), |b| and Curl Fg : Curl Fg of eq. 16

import numpy as np
from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies.findings import AGREES, DIFFERS, IMPOSED, cube

X = np.linspace(0.0, 1.0, 11)
THETA = 1 + X / 4
B_EQ16 = THETA ** (-4 / 3) / 12


def results(**profile):
    line = {"X1": X, "theta": THETA, "curlFg_sq": 2 * B_EQ16 ** 2, "|b_n1|": 0 * X,
            "|b_n2|": B_EQ16, "S11": 1e-3 * np.sin(np.pi * X),
            "S22": 1e-3 * np.cos(2 * np.pi * X), "S33": 1e-3 * np.cos(2 * np.pi * X)}
    return {"cube": run({"G_error_L2_rel": 1e-16}, {**line, **profile})}


#: Per rule: verdict -> results that must give it.
CASES = {
    "cube-growth": {IMPOSED: results(), DIFFERS: results(theta=1 + X / 8)},
    "cube-curl": {AGREES: results(), DIFFERS: results(curlFg_sq=2 * B_EQ16[::-1] ** 2)},
    "cube-b-n1": {AGREES: results(), DIFFERS: results(**{"|b_n1|": 0.1 * B_EQ16})},
    "cube-b-trend": {AGREES: results(), DIFFERS: results(**{"|b_n2|": B_EQ16[::-1]})},
    "cube-stress": {AGREES: results(),
                    DIFFERS: results(S11=1e-3 * np.ones_like(X))},        # S11 on the faces
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(cube.FINDINGS, CASES)


def _rule(key):
    return rule_of(cube.FINDINGS, key)


def test_a_stress_component_that_is_absent_differs_and_is_named():
    """"Residual stresses in all three directions": S33 at 1e-3 of the largest fails."""
    measured, verdict, reason = _rule("cube-stress").judge(
        results(S33=1e-6 * np.cos(2 * np.pi * X)))
    assert verdict == DIFFERS and reason == "no residual stress in S33"
    assert "max |S11|, |S22|, |S33| on the centre line 0.001, 0.001, 1e-06 MPa" in measured


def test_the_growth_reports_its_range_and_the_distance_to_eq_50():
    measured, verdict, reason = _rule("cube-growth").judge(results(theta=1 + X / 5))
    assert verdict == DIFFERS and measured == "theta from 1 to 1.2"
    assert "|theta_max - 1.25| = 0.05" in reason
