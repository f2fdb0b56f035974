"""ngincompat.studies.figures: the figures of ``ngincompat paper``, laid out as the paper's."""

from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.image import imread

from ngincompat.scenes import CubeScene
from ngincompat.studies import figures
from ngincompat.studies.sections import SECTIONS
from ngincompat.workflow.results import MeshInfo, Results

R = np.linspace(0.0, 1.0, 11)


@pytest.fixture(scope="module")
def cube():
    """The cube at order 1 on one hexahedron: its fields, a fraction of a second."""
    return CubeScene.from_settings({"maxh": 1.0, "order": 1}).run()


def _results(line, status="done", units=None, params=None):
    return Results(scene="fake", params=params or {},
                   units=units or {"length": "mm", "stress": "MPa"},
                   mesh=MeshInfo(ne=1, nv=1, order=1, maxh=1.0), status=status,
                   profiles={"line": line})


@pytest.mark.parametrize("label, files", [
    ("cube", ["fig1_cube.png"]), ("hemisphere-concave", ["fig2_hemisphere-concave.png"]),
    ("hemisphere-linear-symmetry", []), ("disc-radial", ["fig3_disc-radial.png"]),
    ("cylinder", ["fig4_cylinder.png"]), ("skin-circle", ["fig6_skin-circle.png"]),
    ("atrophy", []), ("folding-curved", [])])
def test_a_case_has_the_field_figure_of_its_scenes_paper_figure(label, files):
    """The symmetry case is a check with its own figure; atrophy draws its own Fig. 5 and
    folding, two-dimensional, the section's Fig. 7."""
    assert figures.case_files(label) == files


def test_every_figure_the_job_may_draw_is_listed():
    labels = [label for s in SECTIONS for label, _, _ in s.cases]
    every = figures.all_files(labels)
    assert len(set(every)) == len(every)
    assert {"fig2g_burgers.png", "fig2h_curl.png", "fig2_radial_check.png",
            "fig3e_disc_stress.png", "fig7_folding.png", "fig7_onset.png"} <= set(every)
    assert figures.section_files("3.1") == [] and figures.section_files("3.4") == []
    assert set(figures.all_files(["cube"])) == {"fig1_cube.png", *(
        f for s in SECTIONS for f in figures.section_files(s.number))}


def test_the_cubes_panels_carry_units_signs_and_the_burgers_vectors(cube, tmp_path,
                                                                   monkeypatch):
    drawn = {}

    def capture(mesh, u, panels, title, unit, view, ncols):
        drawn.update(panels=panels, title=title, unit=unit, view=view, ncols=ncols)
        return "figure"

    monkeypatch.setattr(figures.surface, "surface_figure", capture)
    monkeypatch.setattr(figures.plots, "save", lambda fig, path: drawn.update(path=path))
    figures.case_figure(tmp_path, "cube", cube, "preview")
    titles = [p.title for p in drawn["panels"]]
    assert len(titles) == len(figures.FIELDS["cube"][2]) == 8
    assert titles[1] == r"(b) Curl $F^g$ : Curl $F^g$ [1/mm$^2$]"
    assert titles[3] == r"(e) |b| on $\bar n_2$ [1/mm], arrows: b"
    assert titles[4] == r"(f) $S_{11}$ [MPa]"
    assert [p.signed for p in drawn["panels"]] == [False] * 4 + [True] * 3 + [False]
    assert [p.arrows is not None for p in drawn["panels"]] == [False] * 3 + [True] + \
        [False] * 3 + [True]
    assert drawn["title"] == "Fig. 1: cube (deformed; preview resolution)"
    assert (drawn["unit"], drawn["view"], drawn["ncols"]) == ("mm", (22, -58), 4)
    assert drawn["path"] == tmp_path / "fig1_cube.png"


def test_the_cubes_field_figure_is_drawn(cube, tmp_path):
    figures.case_figure(tmp_path, "cube", cube, "preview")
    image = imread(tmp_path / "fig1_cube.png")
    assert image.shape[0] > 100 and image[..., :3].std() > 0.05       # not blank


def test_no_field_figure_without_fields_or_panels(cube, tmp_path):
    figures.case_figure(tmp_path, "atrophy", cube, "preview")        # no figure of its own
    no_domain = SimpleNamespace(domain=None, fields=cube.fields, units=cube.units)
    figures.case_figure(tmp_path, "cube", no_domain, "preview")
    none_of_them = SimpleNamespace(domain=cube.domain, fields={"u": cube.fields["u"]},
                                   units=cube.units)
    figures.case_figure(tmp_path, "cube", none_of_them, "preview")
    assert list(tmp_path.iterdir()) == []


def _discs(status="done"):
    line = {"R": R, "sigma_r": 1 - R * R, "sigma_theta": 1 - 2 * R * R}
    return {"disc-radial": _results(line),
            "disc-circumferential": _results({k: v / 2 for k, v in line.items()}, status)}


def test_the_discs_comparison_is_drawn_when_both_families_finished(tmp_path):
    (disc,) = [s for s in SECTIONS if s.number == "3.3"]
    figures.section_figures(tmp_path / "partial", disc, _discs("not converged"))
    assert not (tmp_path / "partial").exists()
    figures.section_figures(tmp_path, disc, _discs())
    assert [p.name for p in tmp_path.iterdir() if p.is_file()] == ["fig3e_disc_stress.png"]
    assert imread(tmp_path / "fig3e_disc_stress.png")[..., :3].std() > 0.05


def test_the_hemispheres_profiles_are_drawn_without_the_check_when_it_did_not_run(tmp_path):
    (hemisphere,) = [s for s in SECTIONS if s.number == "3.2"]
    results = {f"hemisphere-{p}": _results({"R": R, "|b_meridional|": R + k,
                                            "curlFg_sq": R * k})
               for k, p in enumerate(figures.PROFILES)}
    figures.section_figures(tmp_path, hemisphere, results)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig2g_burgers.png",
                                                          "fig2h_curl.png"]


def test_sections_without_their_runs_draw_nothing(tmp_path):
    """Fig. 7 needs the folding fields ("section" profiles); 3.1 has no comparison."""
    by_number = {s.number: s for s in SECTIONS}
    figures.section_figures(tmp_path, by_number["3.7"], {"folding-curved": _results({})})
    figures.section_figures(tmp_path, by_number["3.1"], {"cube": _results({})})
    figures.section_figures(tmp_path, by_number["3.2"], {})
    assert list(tmp_path.iterdir()) == []


def test_every_burgers_panel_draws_the_vectors_of_its_plane():
    """A panel of |b| names the norm of a plane's b (``|b_<plane>|``), whose vector field
    ``b_<plane>`` every scene's incompatibility writes and the panel draws as arrows; the
    largest over the planes, ``|b|``, has no vector field, and its panel would draw none."""
    keys = [key for _, _, panels in figures.FIELDS.values() for _, key, _, _ in panels
            if key.startswith("|b")]
    assert len(keys) >= 7
    for key in keys:
        assert key != "|b|" and figures._vector(key).startswith("b_"), key
