"""ngincompat.studies.views: the interactive 3-D views of ``ngincompat paper``."""

from types import SimpleNamespace

import pytest

from ngincompat.scenes import CubeScene
from ngincompat.studies import views
from ngincompat.studies.sections import SECTIONS


@pytest.fixture(scope="module")
def cube():
    """The cube at order 1 on one hexahedron: its fields, a fraction of a second."""
    return CubeScene.from_settings({"maxh": 1.0, "order": 1}).run()


def test_the_views_are_of_cases_of_the_paper_and_not_of_the_axisymmetric_or_planar_ones():
    labels = {label: s.number for s in SECTIONS for label, _, _ in s.cases}
    assert set(views.VIEWS) <= set(labels)
    assert sorted(labels[k] for k in views.VIEWS) == ["3.1", "3.2", "3.5", "3.6"]
    for label in labels:
        expected = [f"view_{label}.html"] if label in views.VIEWS else []
        assert views.case_files(label) == expected
    assert views.case_files("cylinder") == views.case_files("folding-curved") == []


def test_the_cubes_view_is_written_with_its_title_in_the_runs_unit(cube, tmp_path):
    views.case_view(tmp_path, "cube", cube, "preview")
    (written,) = tmp_path.iterdir()
    assert written.name == "view_cube.html"
    page = written.read_text(encoding="utf-8")
    assert "<title>Fig. 1e: |b| on the planes normal to n2 [1/mm]</title>" in page
    assert "cube, deformed, preview resolution; drag to turn, wheel to zoom" in page


def test_no_view_without_one_for_the_case_without_fields_or_without_the_field(cube, tmp_path):
    views.case_view(tmp_path, "cylinder", cube, "preview")             # no view for 3.4
    no_domain = SimpleNamespace(fields=cube.fields, domain=None, units=cube.units)
    views.case_view(tmp_path, "cube", no_domain, "preview")            # read back: no fields
    fields = {k: v for k, v in cube.fields.items() if k != "|b_n2|"}
    no_field = SimpleNamespace(fields=fields, domain=cube.domain, units=cube.units)
    views.case_view(tmp_path, "cube", no_field, "preview")
    assert list(tmp_path.iterdir()) == []


def test_each_view_passes_its_field_deformation_and_camera(monkeypatch, tmp_path):
    """The crescent's growth is drawn on the skin at the end of the hold, the brain's on a cut
    at order 1 and magnified."""
    drawn = {}
    monkeypatch.setattr(views.webview, "scene",
                        lambda mesh, field, deformation, **kw: drawn.update(
                            field=field, deformation=deformation, **kw) or {"data": 1})
    monkeypatch.setattr(views.webview, "write",
                        lambda path, data, title, caption: drawn.update(path=path, title=title))
    fields = {"theta": "theta", "u": "u", "u_end_of_hold": "inflated", "|b|": "b"}
    results = SimpleNamespace(fields=fields, domain="mesh", units={"length": "cm"})
    views.case_view(tmp_path, "skin-crescent", results, "paper")
    assert drawn["field"] == "theta" and drawn["deformation"] == "inflated"
    assert drawn["path"] == tmp_path / "view_skin-crescent.html"
    assert drawn["title"] == "Fig. 6a: area growth at the end of the hold [-]"
    views.case_view(tmp_path, "atrophy", results, "paper")
    brain = views.VIEWS["atrophy"]
    assert (drawn["field"], drawn["deformation"]) == ("b", "u")
    assert (drawn["order"], drawn["clipping"], drawn["zoom"], drawn["camera"]) == (
        1, brain.clipping, 1.5, brain.camera)
    assert drawn["title"].endswith("[1/cm]")
