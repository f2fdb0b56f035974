"""ngincompat.studies.findings.rule: the rules' data, verdicts and shared measurements."""

# The section modules' tests (test_cube.py ... test_folding.py) judge every rule on results
# built there, through the helpers here: :func:`run` makes a finished run's results as the
# report reads them back (metrics, parameters, warnings and the profile "line"), and
# :func:`assert_gives_every_verdict` checks that a rule reaches each verdict it lists.

import numpy as np
import pytest

from ngincompat.studies import findings
from ngincompat.studies.findings import AGREES, DIFFERS, IMPOSED, NOT_RUN, PARTLY
from ngincompat.studies.findings.rule import (
    ABOUT,
    FALLS,
    ROUND_OFF,
    VERDICTS,
    Finding,
    Threshold,
    at_most,
    ends,
    falls,
    finite,
    for_each,
    otherwise,
    percent,
    within_about,
)
from ngincompat.workflow.results import MeshInfo, Results

SECTIONS = ("cube", "hemisphere", "disc", "cylinder", "atrophy", "skin", "folding")


def run(metrics=None, profile=None, params=None, warnings=(), status="done"):
    """A finished run's results as the report reads them."""
    return Results(scene="fake", params=params or {}, units={"length": "mm", "stress": "MPa"},
                   mesh=MeshInfo(ne=1, nv=1, order=1, maxh=1.0), status=status,
                   metrics=metrics or {}, metric_units={"max_principal_stress_released": "MPa"},
                   profiles={"line": profile or {}}, warnings=list(warnings))


def assert_gives_every_verdict(finding, cases):
    """A rule reaches each verdict it lists on the results made for it (``cases``: verdict ->
    results): "differs" where the paper's statement is contradicted, "agrees" or "imposed"
    where it is supported; only "agrees" comes without a reason."""
    assert set(cases) - {NOT_RUN} == set(finding.verdicts)
    assert DIFFERS in cases and {AGREES, IMPOSED} & set(cases)
    for verdict, results in cases.items():
        measured, given, reason = finding.judge(results)
        assert given == verdict, (verdict, measured, reason)
        assert (reason == "") == (given == AGREES), reason
        assert measured or given == NOT_RUN


def assert_unfinished_not_judged(finding, cases):
    """A rule whose last case did not finish gives "not run" and names that case."""
    results = dict(cases[DIFFERS])
    label = finding.needs[-1]
    results[label] = run(status="not converged")
    assert finding.judge(results) == ("", NOT_RUN, f"not finished: {label}")


def section_tests(section_findings, cases):
    """The two tests every section's rules pass, parametrised over its findings: each gives
    every verdict it lists on ``cases`` (key -> verdict -> results, see
    :func:`assert_gives_every_verdict`), and none judges a case that did not finish
    (:func:`assert_unfinished_not_judged`). A section's test module binds them to test names."""

    @pytest.mark.parametrize("finding", section_findings, ids=lambda f: f.key)
    def gives_every_verdict(finding):
        assert_gives_every_verdict(finding, cases[finding.key])

    @pytest.mark.parametrize("finding", section_findings, ids=lambda f: f.key)
    def does_not_judge_the_unfinished(finding):
        assert_unfinished_not_judged(finding, cases[finding.key])

    return gives_every_verdict, does_not_judge_the_unfinished


def rule_of(section_findings, key):
    """The finding of ``section_findings`` with this key."""
    (finding,) = [f for f in section_findings if f.key == key]
    return finding


def all_cases():
    """Every section's cases, rule key -> verdict -> results."""
    from studies.findings import (
        test_atrophy,
        test_cube,
        test_cylinder,
        test_disc,
        test_folding,
        test_hemisphere,
        test_skin,
    )
    modules = (test_cube, test_hemisphere, test_disc, test_cylinder, test_atrophy, test_skin,
               test_folding)
    return {k: v for m in modules for k, v in m.CASES.items()}


def test_every_rule_quotes_the_paper_and_names_a_source_for_each_threshold():
    keys = [f.key for f in findings.FINDINGS]
    assert len(set(keys)) == len(keys) == len(all_cases())
    assert set(keys) == set(all_cases())
    assert [f.key for f in findings.FINDINGS if not f.quote] == ["hemisphere-check"]
    for f in findings.FINDINGS:
        assert f.claim and f.states
        assert f.measure and f.needs and f.section in {f"3.{n}" for n in range(1, 8)}
        names = [t.name for t in f.thresholds]
        assert len(set(names)) == len(names), f.key
        assert NOT_RUN not in f.verdicts and DIFFERS in f.verdicts
        for t in f.thresholds:
            assert t.verdict in findings.VERDICTS and t.source and t.text(), (f.key, t)
            assert "{" not in t.text(), (f.key, t)


def test_the_rules_table_has_one_row_per_rule_with_its_words_and_sources():
    """The validation page's table (docs/_ext/finding_rules.py renders these rows)."""
    rows = findings.rules()
    assert len(rows) == len(findings.FINDINGS)
    for row, f in zip(rows, findings.FINDINGS, strict=True):
        assert len(row) == len(findings.RULE_COLUMNS)
        assert row[:2] == (f.section, f.figure)
        assert row[2] == f.states and (f.quote or f.claim) in row[2]
        assert len(row[4]) == len(f.thresholds)
        assert all("(source: " in t for t in row[4])
    (skin,) = [row for row in rows if "the square expander results" in row[2].lower()]
    assert skin[5] == "agrees, partly, differs"


def test_every_sections_rules_are_in_the_list_once_in_section_order():
    from ngincompat.studies.findings import (
        atrophy,
        cube,
        cylinder,
        disc,
        folding,
        hemisphere,
        skin,
    )
    parts = (cube, hemisphere, disc, cylinder, atrophy, skin, folding)
    assert findings.FINDINGS == tuple(f for m in parts for f in m.FINDINGS)
    sections = [f.section for f in findings.FINDINGS]
    assert sections == sorted(sections)
    for n, m in enumerate(parts, start=1):
        assert {f.section for f in m.FINDINGS} == {f"3.{n}"}, m.__name__


# --- the rule as data -----------------------------------------------------------------------

def _finding(decide, *thresholds, needs=("a",)):
    return Finding("k", "3.1", "1a", "q", "c", needs, "m", thresholds, decide)


def test_a_thresholds_text_carries_its_value_and_a_rule_reads_it_by_name():
    t = Threshold("tol", AGREES, "at most {value:g} apart", "a choice", 0.25)
    assert t.text() == "at most 0.25 apart"
    f = _finding(None, t, otherwise("more apart"))
    assert f.limit("tol") == 0.25 and f.limit("otherwise") is None
    with pytest.raises(KeyError):
        f.limit("missing")


def test_a_rules_verdicts_are_its_thresholds_in_order_without_repeats():
    f = _finding(None, Threshold("a", PARTLY, "", "s"), Threshold("b", AGREES, "", "s"),
                 Threshold("c", PARTLY, "", "s"), otherwise("no"))
    assert f.verdicts == (PARTLY, AGREES, DIFFERS)
    assert VERDICTS == (AGREES, PARTLY, DIFFERS, IMPOSED, NOT_RUN)


def test_states_quotes_the_paper_or_marks_a_check_as_ours():
    assert _finding(None).states == "\u201cq\u201d"
    ours = Finding("k", "3.1", "1a", "", "c", ("a",), "m", (), None)
    assert ours.states == "a check of ours, not the paper's: c"


def test_judge_gives_the_cases_in_the_order_of_needs_and_not_run_for_any_missing():
    seen = []

    def decide(f, *results):
        seen.append(results)
        return "m", AGREES, ""

    f = _finding(decide, needs=("a", "b"))
    a, b = run({"x": 1.0}), run({"x": 2.0})
    assert f.judge({"b": b, "a": a, "c": run()}) == ("m", AGREES, "")
    assert seen == [(a, b)]
    assert f.judge({"a": a}) == ("", NOT_RUN, "not finished: b")
    assert f.judge({"a": run(status="interrupted"), "b": b}) == (
        "", NOT_RUN, "not finished: a")
    assert f.judge({}) == ("", NOT_RUN, "not finished: a, b")
    assert len(seen) == 1


# --- the shared measurements ----------------------------------------------------------------

def test_for_each_agrees_for_all_differs_for_none_and_names_the_failing():
    assert for_each({"x": True, "y": True}) == (AGREES, "")
    assert for_each({"x": True, "y": False}) == (PARTLY, "not for y")
    assert for_each({"x": False, "y": False}, "fails: ") == (DIFFERS, "fails: x, y")


def test_falls_needs_the_first_above_the_second_by_the_margin():
    f = _finding(None, FALLS, otherwise("no"))
    margin = FALLS.value
    assert falls(f, 1.0 + 2 * margin, 1.0, "q") == (AGREES, "")
    assert falls(f, 1.0 + margin / 2, 1.0, "q") == (DIFFERS, "q does not fall")
    assert falls(f, 1.0, 2.0, "q")[0] == DIFFERS


def test_at_most_compares_with_the_named_threshold():
    f = _finding(None, ROUND_OFF, otherwise("no"))
    assert at_most(f, "round_off", 1e-16, "e") == (AGREES, "")
    assert at_most(f, "round_off", ROUND_OFF.value, "e") == (AGREES, "")
    assert at_most(f, "round_off", 0.5, "e") == (DIFFERS, "e = 0.5 > 1e-08")


def test_within_about_is_half_a_unit_of_the_papers_last_digit():
    f = _finding(None, ABOUT, otherwise("no"))
    assert within_about(f, 34.9, 30) and within_about(f, 25.0, 30)
    assert not within_about(f, 35.1, 30) and not within_about(f, 24.9, 30)


def test_ends_and_finite_read_a_profile_where_it_is_finite():
    x = np.linspace(0.0, 2.0, 5)
    y = np.array([np.nan, 1.0, 2.0, 3.0, np.nan])
    r = run(profile={"x": x, "y": y})
    xs, ys = finite(r, "y", "x")
    assert xs.tolist() == [0.5, 1.0, 1.5] and ys.tolist() == [1.0, 2.0, 3.0]
    assert ends(r, "y", "x") == (1.0, 3.0)
    # a quarter of the length in from each end, by linear interpolation: y = 2x
    assert ends(run(profile={"x": x, "y": 2 * x}), "y", "x", inner=0.25) == (1.0, 3.0)


def test_percent_is_signed():
    assert percent(0.125) == "+12.5 %" and percent(-0.5) == "-50 %"
