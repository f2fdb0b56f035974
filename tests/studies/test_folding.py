"""ngincompat.studies.folding: ``ngincompat folding``, one row per axon field and Fig. 7."""

from types import SimpleNamespace

import pytest

from ngincompat.errors import ParameterError
from ngincompat.scenes.folding import FoldingScene
from ngincompat.studies import folding


def test_the_release_columns_are_in_the_summary_only_when_a_row_has_them():
    held = [{"axons": "curved", "status": "done"}, {"axons": "straight", "status": "failed"}]
    assert folding.columns(held) == [c for c in folding.COLUMNS if c not in folding.RELEASED]
    released = [*held, {"axons": "concentric", "max_principal_stress_released": 4.1,
                        "top_curvature_released": 0.2}]
    assert folding.columns(released) == list(folding.COLUMNS)
    # each on its own: a run that measured the stress but not the curvature
    one = [*held, {"axons": "concentric", "max_principal_stress_released": 4.1}]
    assert folding.columns(one) == list(folding.COLUMNS[:-1])
    assert folding.columns([{"top_curvature_released": None}]) == folding.columns(held)


def test_the_summary_has_the_scenes_units_and_one_line_per_axon_field():
    rows = [{"axons": "curved", "status": "done", "onset_growth": 1.2345678,
             "burgers_interface_mean": 3.0}, {"axons": "straight", "status": "failed"}]
    lines = folding.summary_markdown(rows).splitlines()
    assert len(lines) == 4
    header = lines[0]
    assert "| axons | status |" in header and "seconds [s]" in header
    assert f"burgers_interface_mean [{FoldingScene.metric_unit('burgers_interface_mean')}]" \
        in header
    assert "max_principal_stress_released" not in header
    assert lines[2].startswith("| curved | done |") and "| 1.235 |" in lines[2]
    assert lines[3].startswith("| straight | failed |")


def test_every_metric_has_the_scenes_unit():
    for metric in folding.METRICS:
        assert folding.UNITS[metric] == FoldingScene.metric_unit(metric), metric
    assert folding.AXON_FIELDS == ("curved", "concentric", "straight")      # Fig. 7a's order


def test_no_fields_figure_without_sampled_fields():
    results = {"curved": SimpleNamespace(profiles={"line": {}})}
    assert folding.fields_figure(results, FoldingScene()) is None
    assert folding.fields_figure({}, FoldingScene()) is None


@pytest.mark.parametrize("settings, axons, name", [
    ({"cortex_thickness": "-1"}, folding.AXON_FIELDS, "cortex_thickness"),
    ({}, ("curved", "sideways"), "axons"),
])
def test_settings_are_checked_for_every_axon_field_before_anything_runs(tmp_path, settings,
                                                                        axons, name):
    out = tmp_path / "folding"
    with pytest.raises(ParameterError, match=f"^{name} = "):
        folding.run_all(out, axons=axons, **settings)
    assert not out.exists()
