"""The study of section 3.6 under the choices the paper leaves open
(``ngincompat.studies.skin_sensitivity``): each choice is the scene's defaults changed in one
reading, the rows are judged by the report's own rules, and an unknown choice is refused."""

import math

import pytest
from studies.findings.test_skin import skin

from geometries import FOOTPRINTS, footprint_size
from ngincompat.errors import ParameterError
from ngincompat.scenes.skin import SkinExpansionScene
from ngincompat.studies import findings, skin_sensitivity
from ngincompat.studies.findings import AGREES, DIFFERS, NOT_RUN


def _by_footprint(labelled):
    return {label.removeprefix("skin-"): r for label, r in labelled.items()}


def test_a_row_is_judged_by_the_reports_own_rules():
    """The paper's order and 40 kPa give "agrees" twice and the stresses in kPa; the
    preview's order (crescent least, square most but within 0.1 % of the circle) "differs";
    without a contact zone (the pressure expander) the stress is "not run"."""
    row = skin_sensitivity.judge(_by_footprint(skin()))
    assert (row["order_verdict"], row["stress_verdict"]) == (AGREES, AGREES)
    assert row["order"] == "circle 1.36 < crescent 1.4 < rectangle 1.45 < square 1.5"
    assert (row["tension_released"], row["compression_contact"]) == (40.0, 41.0)
    row = skin_sensitivity.judge(_by_footprint(skin(mean=(1.357, 1.403, 1.404, 1.323),
                                                    tension=0.6, compression=-0.4)))
    assert (row["order_verdict"], row["stress_verdict"]) == (DIFFERS, DIFFERS)
    row = skin_sensitivity.judge(_by_footprint(skin(compression=None)))
    assert row["stress_verdict"] == NOT_RUN and row["compression_contact"] is None


def test_each_choice_is_the_defaults_changed_in_one_reading():
    """Every choice makes valid scenes of the four footprints (writing results.json only);
    "defaults" changes nothing;
    the others each change what they name, and "equal-size" makes every footprint 7 cm
    wide (its base area computed back to that width)."""
    names = [c.name for c in skin_sensitivity.CHOICES]
    assert names[0] == "defaults" and len(set(names)) == len(names)
    default = SkinExpansionScene()
    for choice in skin_sensitivity.CHOICES:
        scenes = {f: choice.scene(f, {}) for f in FOOTPRINTS}
        assert all(s.outputs == () or s.output_set() == set() for s in scenes.values())
        changed = {k for s in scenes.values() for k, v in s.settings().items()
                   if k not in ("footprint", "outputs") and v != default.settings()[k]}
        expected = set(choice.settings) | {k for e in choice.each.values() for k in e}
        assert changed == expected, choice.name
    size = next(c for c in skin_sensitivity.CHOICES if c.name == "equal-size")
    for f in FOOTPRINTS:
        area = size.scene(f, {}).footprint_area
        assert math.isclose(footprint_size(f, area), skin_sensitivity.WIDTH, rel_tol=1e-6)


def test_an_unknown_choice_is_refused_with_the_list_before_anything_runs():
    with pytest.raises(ParameterError, match="unknown choice 'dome'.*equal-size"):
        skin_sensitivity.table(["defaults", "dome"])


def test_the_rules_it_applies_are_the_reports():
    keys = {f.key for f in findings.FINDINGS if f.section == "3.6"}
    assert set(skin_sensitivity.JUDGED) <= keys
