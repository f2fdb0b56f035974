"""ngincompat.scenes.folding.figures: the panels of Fig. 7 in the scene's units, drawn where the
run has their fields, and figures that read what the case records and the scene declares."""

import dataclasses

from ngincompat.scenes import FoldingScene
from ngincompat.scenes.folding.case import FoldingCase
from ngincompat.scenes.folding.figures import DEPTH_FIELDS, PANELS, fields_figure, figures, panels

#: Profiles of a run that grew on its supports and was not released.
GROWN = {"section": {"X1": None, "X2": None, "theta_a": None, "u": None, "|b|": None,
                     "sigma_max": None},
         "depth": {"depth": None, "theta_a": None, "|b|": None, "sigma_max": None}}


def test_the_panels_are_labelled_in_the_scenes_units():
    labels = list(panels(FoldingScene()))
    assert labels == ["axon growth theta_a [-]", "|b| on the plane normal to e3 [1/cm]",
                      "max principal Cauchy stress [kPa]",
                      "after release: max principal Cauchy stress [kPa]"]
    assert list(panels(FoldingScene()).values()) == list(PANELS.values())


def test_a_panel_is_drawn_only_where_its_field_and_its_displacement_were_sampled():
    """Not released: no panel after the release; a released stress without u_released (its
    displacement) is not drawn either."""
    scene = FoldingScene()
    grown = fields_figure(scene, GROWN["section"])
    assert list(grown.curves.values()) == ["theta_a", "|b|", "sigma_max"]
    assert set(grown.deform.values()) == {"u"}
    assert (grown.file, grown.profile, grown.x, grown.y) == ("fields.png", "section", "X1", "X2")
    assert grown.floor == 1e-3 * scene.mu_white
    orphan = fields_figure(scene, {**GROWN["section"], "sigma_max_released": None})
    assert "sigma_max_released" not in orphan.curves.values()
    released = fields_figure(scene, {**GROWN["section"], "sigma_max_released": None,
                                     "u_released": None})
    key = "after release: max principal Cauchy stress [kPa]"
    assert released.curves[key] == "sigma_max_released"
    assert released.deform[key] == "u_released"


def test_the_stress_through_the_middle_has_a_curve_per_state_the_run_reached():
    scene = FoldingScene(mu_white=2.0)
    grown = {f.file: f for f in figures(scene, GROWN)}
    assert grown["stress_depth.png"].curves == {"grown": "sigma_max"}
    assert grown["stress_depth.png"].floor == 1e-3 * 2.0
    released = {"section": GROWN["section"],
                "depth": {**GROWN["depth"], "sigma_max_released": None}}
    both = {f.file: f for f in figures(scene, released)}
    assert both["stress_depth.png"].curves == {"grown": "sigma_max",
                                               "released": "sigma_max_released"}


def test_the_figures_read_what_the_case_records_and_the_scene_declares():
    """The branch figures plot keys of the case's series; their marks are declared metrics;
    the depth figures plot fields of DEPTH_FIELDS, which are those of the panels and the
    incompatibility's."""
    scene = FoldingScene()
    series = dataclasses.fields(FoldingCase)
    recorded = set(next(f for f in series if f.name == "series").default_factory()["perfect"])
    by_file = {f.file: f for f in figures(scene, GROWN)}
    assert list(by_file) == ["fields.png", "depth.png", "stress_depth.png", "eigenvalue.png",
                             "folds.png", "mode.png"]
    for name in ("eigenvalue.png", "folds.png"):
        fig = by_file[name]
        assert fig.profile in ("perfect", "buckling") and fig.x == "theta_c"
        assert {*fig.curves.values(), *fig.right.values()} <= recorded
        assert set(fig.marks.values()) <= set(FoldingScene.metrics)
    assert set(by_file["eigenvalue.png"].marks.values()) == {"onset_growth"}
    depth = by_file["depth.png"]
    assert {*depth.curves.values(), *depth.right.values()} <= set(DEPTH_FIELDS)
    panel_fields = {field for field, _ in PANELS.values()}
    assert set(DEPTH_FIELDS) - panel_fields == {"curlFg_sq"}
    assert by_file["mode.png"].profile == "mode" and by_file["mode.png"].curves == {
        "u2 on top": "u2"}
    assert all(f.title.startswith("folding (axons=curved): ") for f in by_file.values())
