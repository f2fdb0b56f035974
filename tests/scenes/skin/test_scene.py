"""ngincompat.scenes.skin.scene: the skin scene's parameters, its expander, its contact metrics
and its checks before anything is computed (section 3.6)."""

import math

import ngsolve as ngs
import pytest
from scenes.skin.test_case import COARSE

from geometries import footprint_area
from geometries.skin_patch import SIDE, THICKNESS
from ngincompat.errors import ParameterError
from ngincompat.names import FOOTPRINTS
from ngincompat.scenes.skin.case import SkinCase
from ngincompat.scenes.skin.scene import (
    CONTACT_MEASURES,
    CONTACT_METRICS,
    MOMENTS,
    SkinExpansionScene,
)


@pytest.mark.parametrize("footprint", FOOTPRINTS)
def test_every_expander_has_the_base_area_it_is_given(footprint):
    """The paper compares shapes of one base area: the dome's footprint has it exactly."""
    dome = SkinExpansionScene(footprint=footprint, footprint_area=20.0).expander_body()
    assert dome.footprint == footprint
    assert footprint_area(footprint, dome.size) == pytest.approx(20.0, rel=1e-12)


def test_the_pressure_model_has_no_dome():
    assert SkinExpansionScene(expander="pressure").expander_body() is None


def test_a_footprint_too_large_for_the_patch_is_refused_naming_the_limit():
    largest = footprint_area("square", SIDE - 2 * THICKNESS)
    SkinExpansionScene(footprint="square", footprint_area=largest)     # the edge is allowed
    with pytest.raises(ParameterError, match=r"footprint_area.*square"):
        SkinExpansionScene(footprint="square", footprint_area=largest * 1.01)


def test_a_hold_of_too_many_steps_is_refused():
    with pytest.raises(ParameterError, match="dt"):
        SkinExpansionScene(hold_days=365.0, dt=0.01)


def test_the_contact_metrics_are_each_measure_at_each_moment_in_order():
    assert list(CONTACT_METRICS) == [f"{k}_{when}" for when in MOMENTS
                                     for k in CONTACT_MEASURES]
    for when in MOMENTS:
        for k, measure in CONTACT_MEASURES.items():
            metric = CONTACT_METRICS[f"{k}_{when}"]
            assert metric.quantity == measure.quantity
            assert metric.meaning.startswith(measure.meaning)
            assert "contact model only" in metric.meaning
    assert SkinExpansionScene.metric_unit("contact_force_end_of_hold") == "MPa cm^2"
    assert set(CONTACT_METRICS) <= set(SkinExpansionScene.metrics)


def test_the_law_is_the_hill_law_of_the_parameters():
    law = SkinExpansionScene(k=0.2, K=0.3, n=3.0, theta_crit=1.1, theta_max=2.0).law()
    assert (law.k, law.K, law.n, law.theta_crit, law.theta_max) == (0.2, 0.3, 3.0, 1.1, 2.0)


def test_build_meshes_the_patch_with_its_footprint():
    case = SkinExpansionScene(footprint="circle", **COARSE).build()
    assert isinstance(case, SkinCase)
    mesh = case.mesh
    assert "footprint" in mesh.GetBoundaries()
    area = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("footprint"))
    assert area == pytest.approx(COARSE["footprint_area"], rel=0.05)   # a polygonal circle
    assert ngs.Integrate(1, mesh) == pytest.approx(SIDE * SIDE * THICKNESS, rel=1e-9)
    assert math.isclose(case.scene.volume, 50.0)
