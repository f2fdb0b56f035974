"""Benchmarks: run time against error."""

import argparse

import pytest

from ngincompat import bench


def test_cheapest_setting_meeting_a_target():
    rows = [{"case": "cube", "maxh": 1, "order": 2, "solve_s": 0.1, "error": 1e-1},
            {"case": "cube", "maxh": 1, "order": 4, "solve_s": 0.5, "error": 1e-5},
            {"case": "cube", "maxh": 0.5, "order": 3, "solve_s": 0.3, "error": 1e-3},
            {"case": "cylinder", "maxh": 1, "order": 2, "solve_s": 0.01, "error": 1e-9}]
    assert bench.cheapest(rows, "cube", 1e-2)["order"] == 3
    assert bench.cheapest(rows, "cube", 1e-4)["order"] == 4
    assert bench.cheapest(rows, "cube", 1e-6) is None


def test_accuracy_study_writes_table_and_plots(tmp_path, monkeypatch):
    monkeypatch.setattr(bench, "ACCURACY", {
        "cube": ("cube", [dict(maxh=1.0, order=2), dict(maxh=1.0, order=3)]),
        "cube-fast": ("cube", [dict(maxh=0.5, order=3, model="quarter", reuse_tangent=True)]),
        "cylinder": ("cylinder", [dict(maxh=0.5, order=2)]),
    })
    lines = bench.accuracy_main(argparse.Namespace(out=str(tmp_path)))
    rows = {(r["case"], r["order"]): r for r in
            __import__("json").loads((tmp_path / "accuracy.json").read_text())["rows"]}
    assert rows[("cube", 3)]["error"] < rows[("cube", 2)]["error"] < 10
    assert rows[("cylinder", 2)]["error"] < 1e-4
    fast = rows[("cube-fast", 3)]
    assert fast["error"] == pytest.approx(2.27e-2, rel=0.02)   # the full cube's maxh 0.5, p 3
    assert fast["tangents"] < fast["newton"]
    assert (tmp_path / "accuracy_cube.png").stat().st_size > 1000
    assert any("cheapest" in line for line in lines)
    assert any(line.startswith("| cube | 0.01 |") for line in lines)


def test_cube_reference_energy_matches_the_independent_value():
    assert bench.CUBE_ENERGY == pytest.approx(2.19533e-7, rel=2e-6)
