"""ngincompat.studies.deviations: the settings that differ from the paper's, as run."""

from ngincompat.scenes import AtrophyScene, CubeScene
from ngincompat.studies import deviations
from ngincompat.studies.sections import NUMBERS


def test_every_setting_a_verdict_rests_on_is_disclosed():
    """The settings the paper leaves open or states otherwise each have a row."""
    listed = {(row["section"], name) for row in deviations.rows()
              for name in row["parameter"].split(", ")}
    for key in [("3.2", "profile"), ("3.5", "theta_min"), ("3.5", "seed"), ("3.5", "t_end"),
                ("3.6", "footprint_area"), ("3.6", "(none)"), ("3.7", "axon_rate"),
                ("3.7", "stretch_crit"), ("3.7", "viscosity"), ("3.7", "axons")]:
        assert key in listed, key


def _entry(section, parameter):
    (entry,) = [d for d in deviations.DEVIATIONS
                if d.section == section and d.parameter == parameter]
    return entry


def test_every_entry_names_parameters_of_its_scene_in_a_section_of_the_paper():
    for d in deviations.DEVIATIONS:
        assert d.section in NUMBERS, d
        assert d.paper and d.reason and d.effect, d
        if d.choice:
            assert d.parameter == "(none)" and d.names == []
        else:
            assert set(d.names) <= set(d.scene.parameters()), (d.section, d.parameter)


def test_ours_is_the_scenes_default_with_its_unit():
    """Read from the scene class: the table cannot disagree with the code."""
    cube = _entry("3.1", "elements, order, maxh")
    defaults = CubeScene.parameters()
    assert cube.ours == (f"elements = {defaults['elements'][0]}, "
                         f"order = {defaults['order'][0]}, maxh = {defaults['maxh'][0]} mm")
    choice = _entry("3.6", "(none)")
    assert choice.ours == choice.choice and choice.as_run([{"mu": 1.0}]) == choice.choice


def test_as_run_notes_the_default_a_run_replaced_and_lists_variants():
    cube = _entry("3.1", "elements, order, maxh")
    order = CubeScene.parameters()["order"][0]
    assert cube.as_run([{"elements": "tet", "order": 3, "maxh": 0.5}]) == (
        f"elements = tet, order = 3 (default {order}), maxh = 0.5 mm")
    assert cube.as_run([{"order": 3}, {"order": 4}, {"order": 3}]) == (
        f"elements = tet, order = 3 / 4 (default {order}), maxh = 0.5 mm")
    # runs at the defaults, or none: the defaults without a note
    assert cube.as_run([{"order": order}]) == cube.as_run([]) == cube.ours
    assert "(default" not in cube.ours


def test_a_list_read_back_from_json_is_the_tuple_it_was():
    seed = _entry("3.5", "seed, seed_radius, c0, t_end")
    default = AtrophyScene.typed_settings({"seed": AtrophyScene.parameters()["seed"][0]})
    default_seed = tuple(default["seed"])
    assert seed.as_run([{"seed": list(default_seed)}]) == seed.as_run([])
    text = seed.as_run([{"seed": [0.0, 0.0, -1.5]}])
    assert text.startswith(f"seed = (0.0, 0.0, -1.5) cm (default {default_seed})")


def test_rows_give_the_defaults_or_the_values_of_the_runs_by_scene():
    rows = deviations.rows()
    assert len(rows) == len(deviations.DEVIATIONS)
    assert set(rows[0]) == {"section", "scene", "parameter", "paper", "ours", "reason",
                            "effect"}
    runs = {"cube": [{"order": 2}]}
    as_run = deviations.rows(runs)
    for row, before, d in zip(as_run, rows, deviations.DEVIATIONS, strict=True):
        assert row["scene"] == d.scene.name
        if d.scene is CubeScene and "order" in d.names:
            assert "order = 2 (default" in row["ours"]
        else:                       # no runs of the scene: its defaults
            assert row["ours"] == before["ours"]
