"""ngincompat.studies.sections: the paper's result sections and the runs each needs."""

import pytest

from ngincompat import names
from ngincompat.studies import findings
from ngincompat.studies.sections import NUMBERS, SECTIONS

LABELS = {label: (section, cls, settings) for section in SECTIONS
          for label, cls, settings in section.cases}


def test_the_sections_are_3_1_to_3_7_in_order_with_titles():
    assert NUMBERS == tuple(f"3.{n}" for n in range(1, 8))
    assert all(s.title and s.cases for s in SECTIONS)


def test_every_case_has_its_own_label_starting_with_its_scenes_name():
    """The figures and views find a case's scene by the label's first word."""
    labels = [label for s in SECTIONS for label, _, _ in s.cases]
    assert len(set(labels)) == len(labels) == 16
    for label, (_, cls, _) in LABELS.items():
        assert label.split("-")[0] == cls.name, label


@pytest.mark.parametrize("label", list(LABELS))
def test_every_case_is_a_valid_variant_of_its_scene(label):
    _, cls, settings = LABELS[label]
    scene = cls.from_settings(settings)
    for key, value in settings.items():
        assert getattr(scene, key) == value, (label, key)


def test_the_variants_of_a_section_differ_and_cover_the_papers_figures():
    for section in SECTIONS:
        variants = [tuple(sorted(s.items())) for _, _, s in section.cases]
        assert len(set(variants)) == len(variants), section.number
    by_number = {s.number: s for s in SECTIONS}
    assert {s["footprint"] for _, _, s in by_number["3.6"].cases} == set(names.FOOTPRINTS)
    assert {s["axons"] for _, _, s in by_number["3.7"].cases} == set(names.AXONS)


def test_every_finding_reads_cases_of_its_own_section():
    for finding in findings.FINDINGS:
        for label in finding.needs:
            assert LABELS[label][0].number == finding.section, (finding.key, label)
