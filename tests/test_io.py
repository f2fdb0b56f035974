"""Atomic result files with provenance."""

import json
import os
import stat

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat.atomic import atomic_path
from ngincompat.workflow import io


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


@pytest.mark.skipif(os.name != "posix", reason="file modes and the umask are POSIX")
@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002], ids=oct)
def test_files_get_the_mode_open_would_give(tmp_path, umask):
    """Results are as readable as any file the user writes, 0o666 less the umask: a temporary
    file from tempfile.mkstemp would keep its 0o600 through the rename."""
    old = os.umask(umask)
    try:
        path = io.write_json(tmp_path / "results.json", {"step": 1})
        new = stat.S_IMODE(path.stat().st_mode)
        io.write_json(path, {"step": 2})  # replacing an existing file
        replaced = stat.S_IMODE(path.stat().st_mode)
        with atomic_path(tmp_path / "figure.png") as tmp:
            tmp.write_bytes(b"png")
        figure = stat.S_IMODE((tmp_path / "figure.png").stat().st_mode)
    finally:
        os.umask(old)
    assert new == replaced == figure == 0o666 & ~umask
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figure.png", "results.json"]
