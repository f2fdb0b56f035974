"""ngincompat.scenes.curvature: the verdict on the curvature of the growth metric against its
error estimate, and the figure drawn beside the Burgers vectors in the scene's units."""

from types import SimpleNamespace

import pytest

from ngincompat.scenes import AtrophyScene, DiscScene
from ngincompat.scenes.curvature import FIGURE_FLOOR, figure, report, verdict


@pytest.mark.parametrize("value, error, compatible", [
    (5e-10, 1e-8, True), (1e-8, 1e-8, True), (0.0, 0.0, True),
    (0.77, 1e-3, False), (1.0000001e-8, 1e-8, False)])
def test_the_verdict_is_compatible_exactly_when_the_norm_is_within_its_error(value, error,
                                                                              compatible):
    line = verdict({"einstein_norm_L2": value, "einstein_norm_L2_error": error})
    if compatible:
        assert line.startswith("compatible: a stress-free state exists ")
        assert f"= {value:.3g} <= its error {error:.3g})" in line
    else:
        assert line.startswith("incompatible: no stress-free state ")
        assert f"= {value:.3g} > its error {error:.3g})" in line


def test_the_verdict_needs_both_numbers():
    with pytest.raises(KeyError):
        verdict({"einstein_norm_L2": 1.0})


@pytest.mark.parametrize("scene, length", [(DiscScene(), "mm"), (AtrophyScene(), "cm")])
def test_the_figure_is_in_the_scenes_units_with_its_variant_in_the_title(scene, length):
    burgers = {"|b| on e3": "|b_e3|"}
    fig = figure(scene, "R", burgers)
    assert (fig.file, fig.x, fig.profile) == ("curvature.png", "R", "line")
    assert fig.xlabel == f"R [{length}]"
    assert fig.curves == {"|Ein(Cg)|_g": "einstein_norm_g"}
    assert fig.ylabel == f"curvature [1/{length}$^2$]"
    assert fig.right == burgers and fig.right_label == f"|b| [1/{length}]"
    assert fig.title == f"{scene.title()}: curvature of the growth metric"
    assert fig.floor == FIGURE_FLOOR > 0


def test_report_adds_the_verdict_only_where_the_curvature_was_measured():
    scene = DiscScene()
    measured = SimpleNamespace(metrics={"einstein_norm_L2": 2.0, "einstein_norm_L2_error": 1.0},
                               verdicts=["earlier"], figures=[])
    report(scene, measured, "R", {"|b|": "burgers"})
    assert measured.verdicts[0] == "earlier" and measured.verdicts[1].startswith("incompatible")
    assert [f.file for f in measured.figures] == ["curvature.png"]
    assert measured.figures[0].right == {"|b|": "burgers"}
    unmeasured = SimpleNamespace(metrics={"burgers_max": 1.0}, verdicts=[], figures=[])
    report(scene, unmeasured, "X1", {})
    assert unmeasured.verdicts == [] and unmeasured.figures[0].x == "X1"
