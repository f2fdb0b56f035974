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

Every rule can return every verdict it lists (``tests/studies/findings/`` gives each
rule data for each); the documentation's validation page shows the rules as a table
(``docs/_ext/finding_rules.py``).

The rules live with their section's measurements (:mod:`~ngincompat.studies.findings.cube`
for 3.1, ... :mod:`~ngincompat.studies.findings.folding` for 3.7), the rule's data and the
shared measurements in :mod:`~ngincompat.studies.findings.rule`.
"""

from collections.abc import Mapping
from typing import TYPE_CHECKING

from ngincompat.studies.findings import atrophy, cube, cylinder, disc, folding, hemisphere, skin
from ngincompat.studies.findings.folding import FOLDING
from ngincompat.studies.findings.rule import (
    AGREES,
    DIFFERS,
    IMPOSED,
    NOT_RUN,
    PARTLY,
    VERDICTS,
    Finding,
    Threshold,
)
from ngincompat.studies.findings.skin import SKIN

if TYPE_CHECKING:     # the rules read the runs' records (their module imports NGSolve)
    from ngincompat.workflow.results import Results

#: Every rule, section by section.
FINDINGS = (*cube.FINDINGS, *hemisphere.FINDINGS, *disc.FINDINGS, *cylinder.FINDINGS,
            *atrophy.FINDINGS, *skin.FINDINGS, *folding.FINDINGS)

def judged(section: str,
           results: "Mapping[str, Results]") -> list[tuple[Finding, str, str, str]]:
    """(finding, measured, verdict, reason) of every finding of ``section``."""
    return [(f, *f.judge(results)) for f in FINDINGS if f.section == section]


#: The columns of the rules' table (:func:`rules`).
RULE_COLUMNS = ("section", "Fig.", "the paper's words", "measure",
                "thresholds and their sources", "verdicts")


def rules() -> list[tuple[str, str, str, str, list[str], str]]:
    """The rules as a table, one row per finding in the columns :data:`RULE_COLUMNS`: the
    thresholds as a list of "verdict: condition (source: ...)", the rest as text."""
    return [(f.section, f.figure, f.states, f.measure,
             [f"{t.verdict}: {t.text()} (source: {t.source})" for t in f.thresholds],
             ", ".join(f.verdicts))
            for f in FINDINGS]


__all__ = ["AGREES", "DIFFERS", "FINDINGS", "FOLDING", "IMPOSED", "NOT_RUN", "PARTLY",
           "RULE_COLUMNS", "SKIN", "VERDICTS", "Finding", "Threshold", "judged", "rules"]
