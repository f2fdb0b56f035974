"""``ngincompat paper`` (the main job): sections, resolutions, the summary and the figures."""

import json

import pytest
from conftest import FOLDING_COARSE

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import AtrophyScene, CubeScene, FoldingScene, SkinExpansionScene
from ngincompat.studies import figures, paper, views


@pytest.fixture(scope="module")
def idealized(tmp_path_factory):
    """Sections 3.2 and 3.3 on their preview settings (80 s at load 8)."""
    out = tmp_path_factory.mktemp("paper")
    code = main(["paper", "--out", str(out), "--only", "3.2,3.3", "-q"])
    return code, out


@pytest.mark.slow
def test_every_case_runs_and_is_summarised(idealized):
    code, out = idealized
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    labels = [label for _, label, _ in paper.cases(only=["3.2", "3.3"])]
    assert [row["case"] for row in summary["rows"]] == labels
    assert all(row["status"] == "done" for row in summary["rows"])
    assert summary["resolution"] == "preview"
    drawn = ["fig2g_burgers.png", "fig2h_curl.png", "fig2_radial_check.png",
             "fig3e_disc_stress.png", *(f for label in labels
                                        for f in figures.case_files(label)),
             *(f for label in labels for f in views.case_files(label))]
    assert "view_hemisphere-linear.html" in drawn            # 3.3's discs have no view
    for name in [*drawn, "summary.md", "summary.csv", "report.html"]:
        assert (out / name).stat().st_size > 0, name
    for label in labels:
        assert (out / label / "results.json").is_file()
    assert set(summary["files"]) == {*labels, *drawn, "report.html", "summary.md",
                                     "summary.csv", "summary.json"}


@pytest.mark.slow
def test_summary_carries_units_and_the_checks(idealized):
    _, out = idealized
    header = (out / "summary.md").read_text().splitlines()[0]
    assert "seconds [s]" in header and "t_growth [s]" in header and "| units |" in header
    rows = {r["case"]: r for r in json.loads((out / "summary.json").read_text())["rows"]}
    assert rows["disc-radial"]["units"] == "mm, MPa"
    # where the time goes, per phase: the phases add up to no more than the case's time
    for r in rows.values():
        phases = [r[f"t_{p}"] for p in paper.PHASES]
        assert all(t >= 0 for t in phases) and sum(phases) <= r["seconds"] + 0.05
    # even coarse, the closed forms hold where they are exact in the discretisation
    assert rows["disc-radial"]["b_eq22_error"] < 1e-8
    assert rows["hemisphere-linear-symmetry"]["radial_sigma_rr_error"] < 0.5


@pytest.mark.slow
def test_overwrite_replaces_the_runs(idealized):
    _, out = idealized
    before = (out / "disc-radial" / "results.json").stat().st_mtime_ns
    assert main(["paper", "--out", str(out), "--only", "3.3", "--overwrite", "-q"]) == 0
    assert (out / "disc-radial" / "results.json").stat().st_mtime_ns > before
    # --overwrite removed what the earlier job wrote, the hemispheres' runs among it
    assert not (out / "hemisphere-linear").exists()


def test_resolutions_take_the_scenes_presets():
    for cls in (CubeScene, SkinExpansionScene):
        for resolution in ("preview", "paper"):
            assert (paper.resolution_settings(cls, resolution)
                    == cls.preset_settings(resolution))
    with pytest.raises(ParameterError, match="--only 3.9: allowed sections 3.1"):
        paper.sections(["3.9"])
    with pytest.raises(ParameterError, match="--resolution 'fine'"):
        paper.resolution_settings(CubeScene, "fine")


@pytest.mark.slow
def test_the_biomedical_sections_run_into_one_report(tmp_path, monkeypatch):
    """Sections 3.5-3.7 on settings coarser than their preview (a small brain, the pressure
    expander without a hold, a small bilayer before its onset): every case runs, the field
    figures and Fig. 7 are drawn and the report has the three sections (8 min 22 s at load
    7)."""
    folding = dict(pair.split("=") for pair in FOLDING_COARSE[1::2])
    coarse = {AtrophyScene: dict(semi_axes="3,2.5,2", gray_thickness=0.5, seed="0,0,-1.5",
                                 t_end=10.0, dt=1.0, snapshots=1, maxh=1.0),
              SkinExpansionScene: dict(expander="pressure", maxh=2.5, growth_order=2,
                                       g_order=3, hold_days=0.0),
              FoldingScene: {**folding, "release": "false"}}
    for cls, settings in coarse.items():
        monkeypatch.setattr(cls, "presets", {**cls.presets, "preview": settings})
    rows = paper.run_all(tmp_path, resolution="preview", only=["3.5", "3.6", "3.7"])
    assert [r["status"] for r in rows] == ["done"] * 8
    assert (tmp_path / figures.case_files("skin-circle")[0]).stat().st_size > 0
    assert (tmp_path / "atrophy" / "brain.png").stat().st_size > 0     # its own Fig. 5
    assert (tmp_path / "fig7_folding.png").stat().st_size > 0
    for label in ("atrophy", "skin-crescent"):                 # their interactive views
        assert (tmp_path / f"view_{label}.html").stat().st_size > 0
    page = (tmp_path / "report.html").read_text()
    assert all(f'id="s{n}"' in page for n in ("3.5", "3.6", "3.7"))


def test_runs_side_by_side_give_what_runs_one_after_the_other_give(tmp_path, capsys):
    """--jobs 2 runs the cases in worker processes, each drawing its figure and view there:
    the same rows (but for the times), the same files, as --jobs 1 in this process."""
    summaries = {}
    for jobs in (1, 2):
        out = tmp_path / f"jobs{jobs}"
        assert main(["paper", "--out", str(out), "--only", "3.1,3.4", "--jobs", str(jobs),
                     "-q"]) == 0
        summaries[jobs] = json.loads((out / "summary.json").read_text())
        assert (out / "view_cube.html").stat().st_size > 0
        assert (out / figures.case_files("cube")[0]).stat().st_size > 0
    timing = {"seconds", *(f"t_{p}" for p in paper.PHASES)}
    rows = [[{k: v for k, v in r.items() if k not in timing} for r in summaries[j]["rows"]]
            for j in (1, 2)]
    assert rows[0] == rows[1] and [r["case"] for r in rows[0]] == ["cube", "cylinder"]
    assert sorted(summaries[1]["files"]) == sorted(summaries[2]["files"])
    capsys.readouterr()
    assert main(["paper", "--out", str(tmp_path / "zero"), "--only", "3.1", "--jobs", "0",
                 "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["ngincompat: error: --jobs 0: allowed an integer >= 1"]
    assert not (tmp_path / "zero").exists()


def test_sigterm_to_a_paper_job_with_workers_ends_it_cleanly(tmp_path):
    """A batch system's stop (SIGTERM to every process of the job) while two workers run
    cases: exit 130 in one line, no traceback (the workers died of it: BrokenProcessPool,
    naming an error.txt that did not exist), no lock left in any folder, and the cases
    that were running marked "interrupted" in their records."""
    import os
    import signal
    import subprocess
    import sys

    out = tmp_path / "paper"
    process = subprocess.Popen([sys.executable, "-m", "ngincompat.cli", "paper", "--only",
                                "3.1,3.4", "--jobs", "2", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    lines, started = [], 0
    for line in process.stderr:
        lines.append(line)
        started += "] growth" in line
        if started >= 2:          # both workers are computing their cases
            os.killpg(process.pid, signal.SIGTERM)
            break
    _, rest = process.communicate(timeout=300)
    err = "".join(lines) + rest
    assert process.returncode == 130, err
    assert "Traceback" not in err and "BrokenProcessPool" not in err and "error.txt" not in err
    assert not list(out.rglob(".ngincompat.lock")), err
    records = {p.parent.name: json.loads(p.read_text())["status"]
               for p in out.glob("*/results.json")}
    assert records and set(records.values()) <= {"done", "interrupted"}, err
    rows = json.loads((out / "summary.json").read_text())["rows"]    # what has ended
    assert {r["case"]: r["status"] for r in rows} == records


@pytest.mark.parametrize("only", ["", " , "])
def test_the_paper_job_with_an_empty_section_list_is_refused(only, tmp_path, capsys):
    """--only '' ran every section, silently."""
    out = tmp_path / "paper"
    assert main(["paper", "--only", only, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--only" in err[0] and "names no section" in err[0], err
    assert not out.exists()
