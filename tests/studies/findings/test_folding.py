"""ngincompat.studies.findings.folding: the rules of section 3.7 on synthetic results."""

# the three axon fields (curved, concentric, straight), judged under the paper's labels of
# Fig. 7a

from studies.findings.test_rule import rule_of, run, section_tests

from ngincompat.studies import findings
from ngincompat.studies.findings import AGREES, DIFFERS, NOT_RUN, PARTLY
from ngincompat.studies.findings import folding as rules

NAN = float("nan")


def folding(b=(3.0, 4.0, 4.2), released=(2.0, 4.1, 4.7), onset=(1.28, 1.28, 1.28),
            depth=(0.05, 0.05, 0.05), grown=1.01, amplitude=0.05):
    return {label: run({"onset_growth": o, "fold_amplitude": amplitude,
                        "burgers_max_depth": d, "theta_a_max": grown,
                        "burgers_interface_mean": bi, "max_principal_stress_released": s},
                       params={"cortex_thickness": 0.05, "cortex_maxh": 0.0125, "length": 3.0})
            for label, o, d, bi, s in zip(findings.FOLDING, onset, depth, b, released,
                                          strict=True)}


#: Per rule: verdict -> results that must give it.
CASES = {
    "folding-onset": {AGREES: folding(), PARTLY: folding(onset=(1.28, NAN, 1.28)),
                      DIFFERS: folding(onset=(NAN, NAN, NAN))},
    "folding-interface": {AGREES: folding(), PARTLY: folding(depth=(0.05, 0.3, 0.05)),
                          DIFFERS: folding(depth=(0.3, 0.3, 0.3))},
    "folding-axons": {AGREES: folding(), PARTLY: folding(b=(3.0, 3.05, 4.2)),
                      DIFFERS: folding(b=(4.2, 3.0, 4.1)), NOT_RUN: folding(grown=1.0)},
    "folding-release": {AGREES: folding(), PARTLY: folding(released=(3.9, 4.1, 4.7)),
                        DIFFERS: folding(released=(4.98, 3.15, 4.71)),
                        NOT_RUN: folding(released=(NAN, NAN, NAN))},
}


test_every_rule_gives_every_verdict_it_lists, test_a_case_that_did_not_finish_is_not_judged = \
    section_tests(rules.FINDINGS, CASES)


def _rule(key):
    return rule_of(rules.FINDINGS, key)


def test_axon_findings_take_the_papers_labels_of_fig_7a():
    """The paper calls the curved field (Fig. 7a's first column) tangential and the
    concentric and straight ones (second and third) normal to the cortex. Released stresses
    of curved 4.98, concentric 3.15, straight 4.71 kPa: the tangential field's is not the
    lower, "differs"; the second reading (concentric tangential against straight) is
    reported beside it, not as the verdict."""
    axons, release = _rule("folding-axons"), _rule("folding-release")
    measured, verdict, reason = release.judge(folding(released=(4.98, 3.15, 4.71)))
    assert verdict == DIFFERS
    paper, second = measured.split("Second reading")
    assert "curved +58.1 % against concentric, curved +5.73 % against straight: differs" in paper
    assert "concentric -33.1 % against straight: partly, not the verdict" in second
    assert "26.6 degrees from its normal" in measured
    # both normal fields' interface |b| above the curved one's by more than 5 %: agrees
    measured, verdict, _ = axons.judge(folding(b=(3.0, 4.0, 4.2)))
    assert verdict == AGREES and "concentric +33.3 % over curved" in measured
    # one normal field above, the other below: partly, and the reason says which
    _, verdict, reason = axons.judge(folding(b=(4.0, 3.0, 4.3)))
    assert verdict == PARTLY and "straight +7.5 % over curved" in reason


def test_axon_findings_are_not_judged_when_the_axons_did_not_grow():
    """Where theta_a stayed 1 (a march too short for the stretch to pass its critical value)
    the three fields are the same growth: "not run", and the reason says so."""
    for key in ("folding-axons", "folding-release"):
        measured, verdict, reason = _rule(key).judge(folding(b=(9.4,) * 3, released=(9.4,) * 3,
                                                             grown=1.0))
        assert verdict == NOT_RUN and "did not grow" in reason


def test_a_fold_of_no_amplitude_is_no_fold():
    """An onset found but a measured amplitude of 0: the bilayer did not fold."""
    _, verdict, reason = _rule("folding-onset").judge(folding(amplitude=0.0))
    assert verdict == DIFFERS and reason == "not for curved, concentric, straight"
    assert _rule("folding-onset").judge(folding(amplitude=NAN))[1] == AGREES


def test_the_interface_is_within_two_cortex_mesh_sizes():
    """The interface 0.05 cm deep, the cortex's mesh size 0.0125 cm: 0.075 is within two
    sizes, 0.076 is not."""
    interface = _rule("folding-interface")
    assert interface.judge(folding(depth=(0.075, 0.025, 0.05)))[1] == AGREES
    _, verdict, reason = interface.judge(folding(depth=(0.076, 0.05, 0.05)))
    assert verdict == PARTLY and reason == "not for curved"


def test_a_tangential_stress_half_the_normal_ones_is_much_lower():
    release = _rule("folding-release")
    assert release.judge(folding(released=(2.0, 4.0, 4.0)))[1] == AGREES
    assert release.judge(folding(released=(2.01, 4.0, 4.0)))[1] == PARTLY
