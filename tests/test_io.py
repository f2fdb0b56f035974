"""Atomic result files with provenance."""

import json

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat import io


def test_json_is_atomic_and_sanitised(tmp_path):
    path = tmp_path / "sub" / "results.json"
    io.write_json(path, {"a": np.float64(1.5), "nan": float("nan"), "arr": np.arange(3),
                         "n": np.int64(4), "p": tmp_path})
    data = json.loads(path.read_text())
    assert data == {"a": 1.5, "nan": None, "arr": [0, 1, 2], "n": 4, "p": str(tmp_path)}
    assert [p.name for p in path.parent.iterdir()] == ["results.json"]


def test_failed_write_leaves_previous_file_intact(tmp_path):
    path = tmp_path / "results.json"
    io.write_json(path, {"step": 1})
    with pytest.raises(TypeError):
        io.write_json(path, {"step": object()})
    assert json.loads(path.read_text()) == {"step": 1}
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_versions_name_the_packages():
    v = io.versions()
    assert set(v) == {"ngincompat", "ngsolve", "netgen", "numpy", "python"}
    assert v["ngsolve"] == ngs.__version__


def test_vtk_written_under_final_name(tmp_path, unit_cube_hex):
    path = io.write_vtk(tmp_path / "fields.vtu", unit_cube_hex,
                        {"x": ngs.x, "v": ngs.CF((ngs.x, ngs.y, 0))})
    assert path.exists() and path.stat().st_size > 1000
    assert b"<VTKFile" in path.read_bytes()[:400]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fields.vtu"]
