"""ngincompat.studies.findings.cylinder: the rules of section 3.4 on synthetic results."""

# |b| = 1 / (4 theta) (eq. 27), Fe a rotation about e3 (eq. 56)

import numpy as np
from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies.findings import AGREES, DIFFERS, PARTLY, cylinder

X = np.linspace(0.0, 1.0, 11)
THETA = 1 + X / 4


def results(b=1 / (4 * THETA), error=0.0, rate=-0.25, stretch=2.6e-4):
    return {"cylinder": run({"b_eq27_error": error, "rotation_rate": rate,
                             "rotation_rate_expected": -0.25, "Fe_rotation_deviation": stretch,
                             "max_principal_stress": 1e-4}, {"X2": X, "|b_e3|": b},
                            params={"mu": 0.55})}


#: Per rule: verdict -> results that must give it.
CASES = {
    "cylinder-b": {AGREES: results(), DIFFERS: results(error=0.2)},
    "cylinder-trend": {AGREES: results(), DIFFERS: results(b=1 / (4 * THETA[::-1]))},
    "cylinder-rotation": {AGREES: results(), PARTLY: results(stretch=0.02),
                          DIFFERS: results(rate=-0.2)},
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(cylinder.FINDINGS, CASES)


def _rule(key):
    return rule_of(cylinder.FINDINGS, key)


def test_the_rotation_rate_is_judged_relative_to_eq_56():
    """-a = -0.25 within 1e-3 relative: a slope off by 2e-4 agrees, by 2e-3 differs, and
    the stress is reported in units of mu."""
    rotation = _rule("cylinder-rotation")
    measured, verdict, _ = rotation.judge(results(rate=-0.25 * (1 + 2e-4)))
    assert verdict == AGREES and "principal stress 0.000182 mu" in measured
    assert rotation.judge(results(rate=-0.25 * (1 + 2e-3)))[1] == DIFFERS


def test_a_constant_b_does_not_fall():
    _, verdict, reason = _rule("cylinder-trend").judge(results(b=0 * X + 0.25))
    assert verdict == DIFFERS and reason == "|b| does not fall"
