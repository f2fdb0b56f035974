"""``ngincompat bench scenes``: each (scene, preset) in its own process, its cost measured and
its accuracy metric against the closed form or the finest run."""

import shutil
from pathlib import Path

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.studies import costs
from ngincompat.studies.bench import CUBE_ENERGY
from ngincompat.workflow import io


def test_the_cube_preview_row_has_its_cost_and_its_energy_error(tmp_path, capsys):
    assert main(["bench", "scenes", "--scenes", "cube", "--presets", "preview",
                 "--out", str(tmp_path)]) == 0
    data = io.read_json(tmp_path / "scenes.json")
    [row] = data["rows"]
    assert (row["scene"], row["preset"], row["status"]) == ("cube", "preview", "done")
    # the preview's mesh: order 3 on the 28 tetrahedra of maxh 0.5
    assert row["ndof"] == 681 and row["newton"] >= 1
    assert 0 < row["cpu_s"] and 0 < row["wall_s"]
    assert row["peak_mb"] > 50                      # NGSolve alone is larger than this
    assert row["error"] == pytest.approx(abs(row["value"] - CUBE_ENERGY) / CUBE_ENERGY)
    assert row["reference"] == "closed form" and 1e-3 < row["error"] < 1e-1
    assert data["units"]["peak_mb"] == "MB"
    assert "| scene | preset | status | ndof |" in capsys.readouterr().out
    assert (tmp_path / "scenes.md").is_file() and (tmp_path / "scenes.csv").is_file()


def test_without_a_closed_form_the_finest_preset_is_the_reference():
    rows = [{"scene": "disc", "preset": p, "value": v}
            for p, v in (("preview", 1.1), ("default", 0.99), ("paper", 1.0))]
    costs._errors(rows, {r["preset"]: {"metrics": {}} for r in rows})
    assert [r["reference"] for r in rows] == ["paper"] * 3
    assert [r["error"] for r in rows] == pytest.approx([0.1, 0.01, 0.0])


def test_a_run_past_its_time_is_stopped_and_reported():
    record, cost = costs.measure("cube", "preview", timeout=0.05)
    assert record is None and cost["status"] == "stopped after 0.05 s"


def test_unknown_names_are_refused_before_anything_runs():
    with pytest.raises(ParameterError, match="unknown scene 'cubes'"):
        costs.table(["cubes"])
    with pytest.raises(ParameterError, match="unknown preset 'fast'"):
        costs.table(["cube"], ["fast"])


def test_a_later_run_replaces_its_own_rows_and_keeps_the_others():
    old = [{"scene": "disc", "preset": "default", "wall_s": 1.0},
           {"scene": "cube", "preset": "paper", "wall_s": 2.0},
           {"scene": "cube", "preset": "preview", "wall_s": 3.0}]
    new = [{"scene": "cube", "preset": "preview", "wall_s": 4.0}]
    rows = costs.merged(old, new)
    assert [(r["scene"], r["preset"], r["wall_s"]) for r in rows] == [
        ("cube", "preview", 4.0), ("cube", "paper", 2.0), ("disc", "default", 1.0)]


def test_a_preview_measured_alone_is_compared_with_the_earlier_default(tmp_path, monkeypatch):
    """A run of the preview alone into a table that has the default: its error is against
    the default's value, not against itself."""
    earlier = [{"scene": "disc", "preset": "default", "status": "done", "value": 2.0}]
    costs.tables.write(tmp_path, "scenes", earlier, list(costs.COLUMNS), costs.UNITS)
    monkeypatch.setattr(costs, "measure", lambda scene, preset, timeout: (
        {"status": "done", "mesh": {"ndof": 10}, "solver": {},
         "metrics": {"strain_energy": 2.5}}, {"wall_s": 1.0}))
    costs.main(["disc"], ["preview"], out=tmp_path)
    rows = io.read_json(tmp_path / "scenes.json")["rows"]
    assert [(r["preset"], r["reference"], r["error"]) for r in rows] == [
        ("preview", "default", 0.25), ("default", "default", 0.0)]


def test_bench_folding_splits_each_fields_time_into_kinds_of_work(tmp_path, capsys):
    """``bench folding`` on the coarse bilayer to 10 days: the row of its run, the seconds of
    each kind of work, which with the rest of the stages add up to the stages' wall time, and
    one row per stage."""
    from ngincompat.fem.work import KINDS
    assert main(["bench", "folding", "--axons", "straight", "--preset", "preview",
                 "--set", "t_end=10", "--set", "release=false", "--out", str(tmp_path)]) == 0
    [run] = io.read_json(tmp_path / "fields.json")["rows"]
    assert (run["axons"], run["status"], run["t_reached"]) == ("straight", "done", 10.0)
    assert run["newton"] >= 1 and run["failed"] == 0 and run["threads"] == 1
    [spent] = io.read_json(tmp_path / "work.json")["rows"]
    stages = io.read_json(tmp_path / "stages.json")["rows"]
    assert [s["stage"] for s in stages] == ["perfect"]
    assert spent["assembly"] > 0 and spent["residual"] > 0
    in_stages = sum(spent[kind] for kind in KINDS) + spent["other in the stages"]
    assert in_stages == pytest.approx(sum(s["wall_s"] for s in stages))
    assert spent["outside the stages"] == pytest.approx(run["wall_s"] - in_stages)
    [measures] = io.read_json(tmp_path / "metrics.json")["rows"]
    assert measures["Je_min"] > 0 and measures["burgers_interface_mean"] > 0
    assert "| axons | version | assembly [s] | factorisation [s]" in capsys.readouterr().out


def test_bench_folding_runs_each_field_on_a_baseline_checkout_after_this_one(tmp_path, capsys):
    """``--baseline`` a checkout (here a copy of this one's packages, its version marked
    in metadata of its own):
    each field twice, this version first, the baseline's row from the copy's code, the same
    results; a folder that is no checkout is refused in one line."""
    root, base = Path(__file__).resolve().parents[2], tmp_path / "base"
    for package in ("ngincompat", "geometries"):
        shutil.copytree(root / package, base / package,
                        ignore=shutil.ignore_patterns("__pycache__"))
    # the copy's own metadata, found first on its path: the version its runs report
    info = base / "ngincompat-0+baseline.test.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: ngincompat\n"
                                   "Version: 0+baseline.test\n")
    out = tmp_path / "out"
    assert main(["bench", "folding", "--axons", "straight", "--preset", "preview",
                 "--set", "t_end=10", "--set", "release=false", "--baseline", str(base),
                 "--out", str(out)]) == 0
    runs = io.read_json(out / "fields.json")["rows"]
    assert [(r["axons"], r["version"], r["status"]) for r in runs] == [
        ("straight", "this", "done"), ("straight", "baseline", "done")]
    assert not runs[0]["program"].startswith("0+baseline")
    assert runs[1]["program"].startswith("0+baseline.test")
    this, baseline = io.read_json(out / "metrics.json")["rows"]
    assert this.pop("version") == "this" and baseline.pop("version") == "baseline"
    assert this == baseline
    assert main(["bench", "folding", "--baseline", str(out)]) == 2
    assert "baseline" in capsys.readouterr().err
