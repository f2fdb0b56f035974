"""ngincompat.studies.findings.atrophy: the rules of section 3.5 on synthetic results."""

import math

import pytest
from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies.findings import AGREES, DIFFERS, IMPOSED, PARTLY, atrophy

NAN = float("nan")


def results(warnings=(), **settings):
    metrics = {"theta_min_reached": 0.7, "gray_volume_loss": 0.25, "white_volume_loss": 0.01,
               "burgers_peak_depth": 0.3, "stress_peak_depth": 0.3,
               "burgers_interface_fraction": 0.6, "interface_band_volume_fraction": 0.3,
               "stress_interface_over_surface": 1.4}
    params = {"theta_min": 0.7, "rate_gray": 0.03, "rate_white": 0.001, "gray_thickness": 0.3}
    for key, value in settings.items():
        (params if key in params else metrics)[key] = value
    return {"atrophy": run(metrics, params=params, warnings=warnings)}


WARNS = ("equilibrium_residual_rel: the equilibrium is not met",)

#: Per rule: verdict -> results that must give it.
CASES = {
    "atrophy-loss": {IMPOSED: results(), AGREES: results(theta_min=0.5),
                     PARTLY: results(WARNS, theta_min=0.5),
                     DIFFERS: results(theta_min_reached=0.9)},
    "atrophy-gray": {IMPOSED: results(), AGREES: results(rate_white=0.03),
                     PARTLY: results(WARNS, rate_white=0.03),
                     DIFFERS: results(gray_volume_loss=0.01, white_volume_loss=0.02)},
    "atrophy-burgers": {AGREES: results(), PARTLY: results(burgers_peak_depth=0.05),
                        DIFFERS: results(burgers_peak_depth=0.05,
                                         burgers_interface_fraction=0.1)},
    "atrophy-stress": {AGREES: results(), PARTLY: results(stress_interface_over_surface=NAN),
                       DIFFERS: results(stress_peak_depth=0.02,
                                        stress_interface_over_surface=0.7)},
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(atrophy.FINDINGS, CASES)


def _rule(key):
    return rule_of(atrophy.FINDINGS, key)


def test_the_cap_of_the_atrophy_law_is_imposed_not_agreement():
    """The largest volume loss at the cap 1 - theta_min = 30 % that the law cannot pass is
    the model's input; with a cap of 50 % a loss of 30 % is a result."""
    loss = _rule("atrophy-loss")
    measured, verdict, reason = loss.judge(results(theta_min_reached=0.7001))
    assert verdict == IMPOSED and "theta_min" in reason and "cap 1 - theta_min = 30 %" in measured
    assert loss.judge(results(theta_min=0.5))[1] == AGREES


def test_a_warned_run_names_its_warnings_but_a_differing_one_stays_differs():
    _, verdict, reason = _rule("atrophy-burgers").judge(results(WARNS))
    assert verdict == PARTLY and reason == "the run warns: equilibrium_residual_rel"
    _, verdict, _ = _rule("atrophy-loss").judge(results(WARNS, theta_min_reached=0.9))
    assert verdict == DIFFERS


@pytest.mark.parametrize("depth, near", [(0.3 + 0.149, True), (0.3 - 0.149, True),
                                         (0.3 + 0.151, False), (0.3 - 0.151, False)])
def test_near_the_interface_is_within_half_the_cortexs_thickness(depth, near):
    _, verdict, _ = _rule("atrophy-stress").judge(results(stress_peak_depth=depth))
    assert verdict == (AGREES if near else PARTLY)


def test_a_missing_interface_share_counts_as_failing():
    _, verdict, reason = _rule("atrophy-burgers").judge(
        results(burgers_interface_fraction=math.nan))
    assert verdict == PARTLY and "more of |b| than of the volume near it" in reason
