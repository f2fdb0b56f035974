"""The output folder: checked before anything is computed, never mixing two runs."""

import json
import logging
import os
import socket
import subprocess
import sys

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene
from ngincompat.workflow import output


def test_a_file_as_output_folder_is_refused(tmp_path):
    target = tmp_path / "results.txt"
    target.write_text("mine")
    with pytest.raises(ParameterError, match="is a file"):
        output.prepare(target)
    with pytest.raises(ParameterError, match="lies under the file"):
        output.prepare(target / "run")
    assert target.read_text() == "mine"


@pytest.mark.parametrize("empty", ["", "  "])
def test_an_empty_output_folder_name_is_refused(tmp_path, monkeypatch, empty):
    """--out '' once wrote into the current folder."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ParameterError, match="^--out '' is empty"):
        output.prepare(empty)
    assert list(tmp_path.iterdir()) == []


def test_a_folder_that_cannot_be_created_is_refused(tmp_path, monkeypatch):
    """A folder the system does not let this process make (the tests may run as root, who
    may write into any ordinary folder: the refusal is simulated)."""
    def refused(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(output.Path, "mkdir", refused)
    with pytest.raises(ParameterError, match="cannot be created: Permission denied"):
        output.prepare(tmp_path / "run")


@pytest.mark.parametrize("folder", ["/", "/etc", "/usr", "/proc/ngincompat-test/run",
                                    "/sys/ngincompat-test", "/etc/../var"])
def test_a_system_folder_is_refused_before_anything_is_made(folder, capsys):
    from ngincompat.cli import main
    assert main(["run", "cube", "--order", "1", "--maxh", "1", "--out", folder, "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is a system folder" in err[0], err
    assert not os.path.exists("/proc/ngincompat-test") and not os.path.exists(
        "/etc/" + output.LOCK) and not os.path.exists("/" + output.LOCK)


def test_a_users_files_of_a_runs_names_are_not_replaced_without_overwrite(tmp_path, capsys):
    """A folder without a run that holds someone's fields.vtu and a figure: refused in one
    line naming them, the files as they were; with --overwrite the run replaces them."""
    from ngincompat.cli import main
    (tmp_path / "fields.vtu").write_text("mine")
    (tmp_path / "stress.png").write_text("my figure")
    (tmp_path / "notes.txt").write_text("notes")
    args = ["run", "cube", "--order", "1", "--maxh", "1", "--out", str(tmp_path), "-q"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "fields.vtu, stress.png" in err[0] and "--overwrite" in err[0]
    assert (tmp_path / "fields.vtu").read_text() == "mine"
    assert {p.name for p in tmp_path.iterdir()} == {"fields.vtu", "stress.png", "notes.txt"}
    assert main([*args, "--overwrite"]) == 0
    capsys.readouterr()
    assert (tmp_path / "fields.vtu").read_bytes().startswith(b"<?xml")
    assert (tmp_path / "notes.txt").read_text() == "notes"


def test_a_folder_with_another_run_is_refused_unless_overwrite(tmp_path):
    scene = CubeScene(order=1, maxh=1.0, outputs="vtk")
    scene.run(tmp_path)
    (tmp_path / "notes.txt").write_text("the user's own file")
    with pytest.raises(ParameterError, match="holds another run.*--overwrite"):
        output.prepare(tmp_path)
    # overwrite removes what the old run wrote, and nothing else
    with output.folder(tmp_path, overwrite=True):
        assert {p.name for p in tmp_path.iterdir()} == {"notes.txt", output.LOCK}
    assert {p.name for p in tmp_path.iterdir()} == {"notes.txt"}


def test_overwrite_leaves_only_the_new_runs_files(tmp_path, caplog):
    """A run with figures, then one without: no figure of the first run is left beside the
    second's results (two runs mixed in one folder), and nothing is said to be kept (the
    first run's results.json, listed among its files, once was)."""
    CubeScene(order=1, maxh=1.0).run(tmp_path)
    assert (tmp_path / "stress.png").is_file()
    with caplog.at_level(logging.WARNING, logger="ngincompat.workflow.output"):
        results = CubeScene(order=1, maxh=1.0, outputs="none").run(tmp_path, overwrite=True)
    assert {p.name for p in tmp_path.iterdir()} == {"results.json"} == set(results.files)
    assert "kept" not in caplog.text


def test_the_folder_is_checked_before_the_solve(tmp_path, monkeypatch):
    from ngincompat.scenes import prescribed

    def forbidden(*args, **kwargs):
        raise AssertionError("the case was built")

    target = tmp_path / "file"
    target.write_text("")
    monkeypatch.setattr(prescribed.PrescribedCase, "solve", forbidden)
    monkeypatch.setattr(CubeScene, "build", forbidden)
    with pytest.raises(ParameterError, match="is a file"):
        CubeScene().run(target)


def test_growth_output_writes_the_mesh_and_the_growth_field(tmp_path):
    results = CubeScene(order=2, maxh=0.5, outputs="growth").run(tmp_path)
    assert {"mesh.vol", "growth.npz"} <= set(results.files)
    assert (tmp_path / "mesh.vol").stat().st_size > 0


def test_vtk_fields_are_interpolated_once_and_gridfunctions_kept():
    """The VTK file gets element-wise interpolants of the fields (exact for a polynomial of
    their order), the GridFunctions themselves."""
    import ngsolve as ngs

    from geometries import cube

    mesh = cube(maxh=0.5)
    u = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    fields = {"u": u, "s": ngs.x * ngs.y * ngs.z, "v": ngs.CF((ngs.x, ngs.y ** 2, 1))}
    out = output.interpolated(fields, mesh, 3)
    assert out["u"] is u
    point = mesh(0.3, 0.6, 0.7)
    assert out["s"](point) == pytest.approx(0.3 * 0.6 * 0.7, rel=1e-10)
    assert out["v"](point) == pytest.approx((0.3, 0.36, 1.0), rel=1e-10)


def _lock(folder, pid):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / output.LOCK).write_text(json.dumps(
        {"pid": pid, "host": socket.gethostname(), "started": "2026-01-01 00:00:00"}))


def test_a_folder_in_use_by_a_live_run_is_refused(tmp_path):
    """Two runs into one folder: the second is refused before it computes, naming the first;
    the first's lock stays."""
    holder = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        _lock(tmp_path, holder.pid)
        with pytest.raises(ParameterError, match=f"in use by another run \\(process "
                                                 f"{holder.pid} on "):
            CubeScene(order=1, maxh=1.0).run(tmp_path)
        assert json.loads((tmp_path / output.LOCK).read_text())["pid"] == holder.pid
        assert not (tmp_path / "results.json").exists()
    finally:
        holder.kill()
        holder.wait()


def test_two_runs_into_one_folder_the_second_exits_2_and_the_first_ends_alone(tmp_path,
                                                                            capsys):
    """Both exited 0 and mixed their files. The first, a process of its own, holds the
    folder while it computes; the second is refused in one line naming it, and the folder
    ends with the first's run alone."""
    from ngincompat.cli import main

    out = tmp_path / "run"
    first = subprocess.Popen([sys.executable, "-m", "ngincompat.cli", "run", "cube",
                              "--order", "3", "--maxh", "0.5", "--out", str(out), "-q"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        while not (out / output.LOCK).exists():
            assert first.poll() is None, first.stderr.read()
        assert main(["run", "cube", "--order", "1", "--maxh", "1", "--set", "outputs=none",
                     "--out", str(out), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"in use by another run (process {first.pid} " in err[0]
        assert first.wait(timeout=300) == 0, first.stderr.read()
    finally:
        first.kill()
        first.wait()
    written = json.loads((out / "results.json").read_text())
    assert written["params"]["order"] == 3 and "fields.vtu" in written["files"]
    assert not (out / output.LOCK).exists()


def test_the_lock_of_a_dead_run_is_taken_over_and_released_after_the_run(tmp_path, caplog):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    _lock(tmp_path, int(dead.stdout))
    with caplog.at_level(logging.WARNING, logger="ngincompat.workflow.output"):
        results = CubeScene(order=1, maxh=1.0, outputs="none").run(tmp_path)
    assert "no longer lives" in caplog.text
    assert results.status == "done" and not (tmp_path / output.LOCK).exists()


def test_the_lock_is_released_when_a_run_fails(tmp_path, monkeypatch):
    from ngincompat.scenes import prescribed

    def fails(*args, **kwargs):
        raise RuntimeError("a bug")

    monkeypatch.setattr(prescribed.PrescribedCase, "measure", fails)
    with pytest.raises(RuntimeError):
        CubeScene(order=1, maxh=1.0).run(tmp_path)
    assert not (tmp_path / output.LOCK).exists()


def test_a_process_cannot_take_its_own_folder_twice(tmp_path):
    with output.folder(tmp_path):
        assert json.loads((tmp_path / output.LOCK).read_text())["pid"] == os.getpid()
        with pytest.raises(ParameterError, match="in use by this process's own run"):
            output.prepare(tmp_path)
    assert not (tmp_path / output.LOCK).exists()


class _TruncatingVTK:
    """NGSolve's VTK writer on a full disk: it writes part of the file and reports nothing."""

    def __init__(self, mesh, coefs, names, filename, subdivision, legacy):
        self.filename = filename

    def Do(self):
        path = self.filename + ".vtu"
        with open(path, "w") as f:
            f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid">\n<Piece')
        return path


def test_a_full_disk_leaves_no_truncated_file_under_its_final_name(tmp_path, monkeypatch,
                                                                   capsys):
    from ngincompat.cli import EXIT_NOT_WRITTEN, main

    monkeypatch.setattr("ngsolve.VTKOutput", _TruncatingVTK)
    out = tmp_path / "run"
    code = main(["run", "cube", "--out", str(out), "--maxh", "1", "--order", "1", "-q"])
    err = capsys.readouterr().err
    assert code == EXIT_NOT_WRITTEN
    assert err.count("\n") == 1 and "fields.vtu was not written completely" in err
    assert "Traceback" not in err
    assert not out.exists()     # no part file, no lock, no temp: the empty folder removed


def test_a_disk_that_fills_after_the_fields_leaves_nothing_and_the_rerun_runs(tmp_path,
                                                                           monkeypatch,
                                                                           capsys):
    """fields.vtu and the figures were written, then results.json found the disk full: the
    files stayed without a record, and the next run refused them as another's."""
    from ngincompat.cli import EXIT_NOT_WRITTEN, main

    written = []
    real = output.io.write_json

    def full(path, data):
        written.extend(p.name for p in path.parent.iterdir())
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(output.io, "write_json", full)
    out = tmp_path / "run"
    args = ["run", "cube", "--out", str(out), "--maxh", "1", "--order", "1", "-q"]
    assert main(args) == EXIT_NOT_WRITTEN
    assert "fields.vtu" in written     # the disk filled after the fields were written
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "No space left" in err and "Traceback" not in err
    assert not out.exists()
    monkeypatch.setattr(output.io, "write_json", real)
    assert main(args) == 0 and output.read(out).status == "done"


def test_permissions_taken_away_during_the_run_exit_5_in_one_line(tmp_path, monkeypatch,
                                                                   capsys):
    """The folder was writable when checked; results.json is then refused (a folder made
    read-only meanwhile, as root cannot be made to see): exit 5, one line naming the file."""
    from ngincompat.cli import EXIT_NOT_WRITTEN, main

    def refused(path, data):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(output.io, "write_json", refused)
    code = main(["run", "cube", "--out", str(tmp_path / "run"), "--maxh", "1", "--order", "1",
                 "--outputs", "mechanics", "-q"])
    err = capsys.readouterr().err
    assert code == EXIT_NOT_WRITTEN and err.count("\n") == 1, err
    assert "cannot write: Permission denied" in err and "results.json" in err
    assert "Traceback" not in err


def test_a_mesh_file_netgen_left_truncated_is_refused(tmp_path, monkeypatch):
    from geometries import cube
    from ngincompat.workflow.inputs import save_mesh

    mesh = cube(maxh=1.0)
    real = type(mesh.ngmesh).Save

    def truncated(ngmesh, name):
        real(ngmesh, name)
        with open(name, "r+b") as f:
            f.truncate(100)

    monkeypatch.setattr(type(mesh.ngmesh), "Save", truncated)
    with pytest.raises(OSError, match="mesh.vol was not written completely"):
        save_mesh(tmp_path / "mesh.vol", mesh)
    assert list(tmp_path.iterdir()) == []


def test_overwrite_keeps_a_file_the_run_did_not_write_as_it_is(tmp_path):
    """A results.json edited to list a foreign file, and a figure the user changed since:
    --overwrite removes neither (the run recorded what it wrote by its SHA-256)."""
    CubeScene(order=1, maxh=1.0).run(tmp_path)
    record = json.loads((tmp_path / "results.json").read_text())
    assert set(record["file_hashes"]) == set(record["files"]) - {"results.json"}
    (tmp_path / "thesis.tex").write_text("years of work")
    record["files"].append("thesis.tex")
    (tmp_path / "results.json").write_text(json.dumps(record))
    (tmp_path / "stress.png").write_bytes(b"the user's own figure")
    with output.folder(tmp_path, overwrite=True):
        pass
    assert {p.name for p in tmp_path.iterdir()} == {"thesis.tex", "stress.png"}


def test_a_symbolic_link_as_output_folder_is_said(tmp_path, caplog):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real")
    with caplog.at_level(logging.WARNING, logger="ngincompat.workflow.output"):
        with output.folder(tmp_path / "link"):
            pass
    assert f"is a symbolic link: the run is written into {tmp_path / 'real'}" in caplog.text


def test_vtk_holds_the_tensors_and_their_kinematics_agree(tmp_path):
    """fields.vtu has P, S, sigma, Fg, Fe (9 components), J and Je, with their units in
    results.json; read back, they satisfy F = Fe Fg, J = det F, Je = det Fe and
    sigma = P F^T / J up to the interpolation of each field on its own."""
    import meshio
    import numpy as np

    CubeScene(order=3, maxh=0.5, outputs="vtk").run(tmp_path)
    data = meshio.read(tmp_path / "fields.vtu").point_data
    for name in ("P", "S", "sigma", "Fg", "Fe", "G"):
        assert data[name].shape[1] == 9, name
    T = {k: data[k].reshape(-1, 3, 3) for k in ("P", "sigma", "Fg", "Fe")}
    F = T["Fe"] @ T["Fg"]
    J = np.linalg.det(F)
    np.testing.assert_allclose(data["J"].ravel(), J, rtol=1e-2)
    np.testing.assert_allclose(data["Je"].ravel(), np.linalg.det(T["Fe"]), rtol=1e-2)
    scale = np.abs(T["sigma"]).max()
    assert scale > 0
    np.testing.assert_allclose(T["sigma"], T["P"] @ F.transpose(0, 2, 1) / J[:, None, None],
                               atol=2e-2 * scale)
    # isotropic growth, Jg = det Fg = theta: Fg = theta^(1/3) I, up to the interpolation of
    # the cube root (theta, linear, is interpolated exactly)
    theta = data["theta"].ravel()
    np.testing.assert_allclose(T["Fg"], np.cbrt(theta)[:, None, None] * np.eye(3), atol=1e-5)
    units = json.loads((tmp_path / "results.json").read_text())["field_units"]
    assert units["sigma"] == units["P"] == units["S11"] == "MPa"
    assert units["u"] == "mm" and units["G"] == "1/mm" and units["Fe"] == "-"


def test_a_folder_marked_read_only_is_refused_even_as_root(tmp_path, capsys):
    """As root, os.access says a chmod 555 folder is writable, and the run was written into
    it; the documentation says read-only folders are refused."""
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        assert main(["run", "cube", "--out", str(folder), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "read-only" in err[0], err
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o755)
