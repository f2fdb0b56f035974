"""Benchmarks: run time against error, errors against the known converged energy."""

import pytest

from ngincompat.cli import main
from ngincompat.studies import bench
from ngincompat.workflow import io


def test_cheapest_setting_meeting_a_target():
    rows = [{"case": "cube", "maxh": 1, "order": 2, "solve_s": 0.1, "error": 1e-1},
            {"case": "cube", "maxh": 1, "order": 4, "solve_s": 0.5, "error": 1e-5},
            {"case": "cube", "maxh": 0.5, "order": 3, "solve_s": 0.3, "error": 1e-3},
            {"case": "cylinder", "maxh": 1, "order": 2, "solve_s": 0.01, "error": 1e-9}]
    assert bench.cheapest(rows, "cube", 1e-2)["order"] == 3
    assert bench.cheapest(rows, "cube", 1e-4)["order"] == 4
    assert bench.cheapest(rows, "cube", 1e-6) is None
    best = {(r["case"], r["target"]): r for r in bench.cheapest_rows(rows)}
    assert best[("cube", 1e-2)]["setting"] == "maxh 0.5, order 3"
    assert best[("cube", 1e-6)]["setting"] == "none in the grid"
    assert best[("cube", 1e-6)]["solve_s"] is None
    assert best[("cylinder", 1e-6)]["solve_s"] == 0.01


def test_accuracy_study_writes_table_and_plots(tmp_path):
    lines = "\n".join(bench.accuracy_main(out=tmp_path, quick=True)).splitlines()
    rows = {(r["case"], r["order"]): r
            for r in io.read_json(tmp_path / "accuracy.json")["rows"]}
    assert rows[("cube", 3)]["error"] < rows[("cube", 2)]["error"] < 10
    assert rows[("cylinder", 2)]["error"] < 1e-4
    fast = rows[("cube-fast", 3)]
    assert fast["error"] == pytest.approx(2.27e-2, rel=0.02)   # the full cube's maxh 0.5, p 3
    assert fast["tangents"] < fast["newton"]
    assert (tmp_path / "accuracy_cube.png").stat().st_size > 1000
    assert "| case | target [-] | setting | solve_s [s] |" in lines
    assert any(line.startswith("| cube | 0.01 |") for line in lines)
    assert (tmp_path / "accuracy_cheapest.csv").is_file()
    assert (tmp_path / "runs" / "cube_maxh1.0_order2" / "results.json").is_file()
    assert not (tmp_path / "cube_maxh1.0_order2").exists()


def test_bench_cube_measures_the_error_against_the_converged_energy(tmp_path, capsys):
    """One hexahedron at orders 2 and 3: the error column is |W - CUBE_ENERGY| / CUBE_ENERGY
    (not against the finest run of the table, which would show 0 for order 3) and falls with
    the order (4.1 and 0.31)."""
    assert main(["bench", "cube", "--maxh", "1", "--orders", "2", "3",
                 "--out", str(tmp_path)]) == 0
    data = io.read_json(tmp_path / "bench.json")
    assert data["units"]["strain_energy"] == "N mm" and data["units"]["solve_s"] == "s"
    rows = data["rows"]
    assert [(r["maxh"], r["order"]) for r in rows] == [(1.0, 2), (1.0, 3)]
    for r in rows:
        assert r["energy_error"] == pytest.approx(
            abs(r["strain_energy"] - bench.CUBE_ENERGY) / bench.CUBE_ENERGY, rel=1e-12)
        assert r["ndof"] > 0 and r["newton"] > 0 and r["solve_s"] > 0
    assert rows[0]["energy_error"] > rows[1]["energy_error"] > 0.1
    assert rows[1]["energy_error"] == pytest.approx(0.31, rel=0.05)
    out = capsys.readouterr().out
    assert "| maxh [mm] | order | ndof | newton | solve_s [s] | strain_energy [N mm] |" in out
    assert (tmp_path / "bench.md").is_file() and (tmp_path / "bench.csv").is_file()
    # the folder says what made it: the command, its date, its CPU time and the load
    made_by = (tmp_path / "made_by.md").read_text()
    assert made_by.startswith(f"Made by `ngincompat bench cube --maxh 1 --orders 2 3 --out "
                              f"{tmp_path}` on 20")
    assert "s of CPU time" in made_by and "load average of" in made_by
    assert (tmp_path / "runs" / "cube_h1_p3" / "results.json").is_file()
