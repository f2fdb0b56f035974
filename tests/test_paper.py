"""``ngincompat paper`` (the main job) on its quick settings."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.studies import paper


@pytest.fixture(scope="module")
def quick_paper(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    code = main(["paper", "--out", str(out), "--quick", "-q"])
    return code, out


def test_every_case_runs_and_is_summarised(quick_paper):
    code, out = quick_paper
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    labels = [label for label, _ in paper.cases()]
    assert [row["case"] for row in summary["rows"]] == labels
    assert all(row["status"] == "done" for row in summary["rows"])
    for label in labels:
        assert (out / label / "results.json").is_file()
    for name in ("fig2g_burgers.png", "fig2h_curl.png", "fig3e_disc_stress.png",
                 "summary.md", "summary.csv"):
        assert (out / name).stat().st_size > 0
    assert set(summary["files"]) == {*labels, "fig2g_burgers.png", "fig2h_curl.png",
                                     "fig3e_disc_stress.png", "summary.md", "summary.csv",
                                     "summary.json"}


def test_summary_carries_units_and_the_checks(quick_paper):
    _, out = quick_paper
    header = (out / "summary.md").read_text().splitlines()[0]
    assert "strain_energy [N mm]" in header and "seconds [s]" in header
    assert "t_growth [s]" in header and "t_incompatibility [s]" in header
    rows = {r["case"]: r for r in json.loads((out / "summary.json").read_text())["rows"]}
    # where the time goes, per phase: the phases add up to no more than the case's time
    for r in rows.values():
        phases = [r[f"t_{p}"] for p in paper.PHASES]
        assert all(t >= 0 for t in phases) and sum(phases) <= r["seconds"] + 0.05
    # even coarse, the closed forms hold where they are exact in the discretisation
    assert rows["cube"]["burgers_max"] == pytest.approx(1 / 12, rel=1e-4)
    assert rows["cylinder"]["b_eq27_error"] < 1e-8
    assert rows["hemisphere-linear-symmetry"]["radial_sigma_rr_error"] < 0.5


def test_a_second_run_into_the_same_folder_needs_overwrite(quick_paper, capsys):
    _, out = quick_paper
    assert main(["paper", "--out", str(out), "--quick", "-q"]) == 2
    assert "holds another run" in capsys.readouterr().err
