"""Atomic result files with provenance."""

import datetime
import json
import os
import platform
import shlex
import stat
import subprocess
import sys

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat import config
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
    import scipy

    v = io.versions()
    assert set(v) == {"ngincompat", "ngsolve", "netgen", "numpy", "scipy", "python"}
    assert v["ngsolve"] == ngs.__version__
    assert v["scipy"] == scipy.__version__ and v["numpy"] == np.__version__
    assert v["python"] == platform.python_version()


def test_run_record_says_when_where_and_how():
    before = datetime.datetime.now(datetime.UTC).replace(microsecond=0)
    record = io.run_record()
    date = datetime.datetime.fromisoformat(record["date"])
    assert date.utcoffset() == datetime.timedelta(0)                 # UTC, said so
    assert before <= date <= datetime.datetime.now(datetime.UTC)
    assert record["host"] == platform.node() and record["host"]
    assert record["threads"] == config.settings()["threads"] >= 1
    assert shlex.split(record["command"]) == sys.orig_argv          # the whole command line
    assert record["cwd"] == os.getcwd() and record["executable"] == sys.executable
    with config.using(threads=3):
        assert io.run_record()["threads"] == 3                      # the threads in force


def _git_out(*args):
    return subprocess.run(["git", *args], cwd=io.SOURCE_ROOT, capture_output=True, text=True,
                          check=True).stdout.strip()


@pytest.mark.skipif(not (io.SOURCE_ROOT / ".git").exists(), reason="not run from a checkout")
def test_run_record_names_the_commit_of_the_checkout():
    git = io.run_record()["git"]
    assert git["commit"] == _git_out("rev-parse", "HEAD")
    assert git["dirty"] == bool(_git_out("status", "--porcelain", "--untracked-files=no"))


def test_no_commit_outside_a_checkout(tmp_path, monkeypatch):
    state = io.git_state.__wrapped__         # not the answer cached for the package
    assert state(tmp_path) is None           # no repository at all
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    (tmp_path / "site-packages").mkdir()
    assert state(tmp_path / "site-packages") is None     # inside a repository, not its top
    monkeypatch.setenv("PATH", str(tmp_path / "nowhere"))
    assert state(io.SOURCE_ROOT) is None     # git not installed
    monkeypatch.setattr(io, "git_state", lambda: None)
    assert "git" not in io.run_record()


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
