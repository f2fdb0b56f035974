"""Time series of the time-dependent scenes (fields.pvd): the frames of the skin's stages and
of the folding march, each frame file a readable VTK file holding the state of its time."""

import json
import os
import signal
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import ngsolve as ngs
import numpy as np
import pytest
from conftest import FOLDING_COARSE, SKIN_COARSE

from ngincompat.cli import EXIT_INTERRUPTED, EXIT_NOT_CONVERGED, main
from ngincompat.fem.solver import NewtonSolver
from ngincompat.scenes import FoldingScene
from ngincompat.workflow import io
from ngincompat.workflow.frames import Frames

pytestmark = pytest.mark.usefixtures("ctrl_c_raises")


def series(folder, collection="fields.pvd"):
    """(time, frame read by meshio) of every data set of the collection, in its order; the
    times increase strictly and every frame names the fields of the first."""
    root = ET.parse(folder / collection).getroot()
    assert root.get("type") == "Collection"
    sets = root.find("Collection").findall("DataSet")
    times = [float(d.get("timestep")) for d in sets]
    assert len(times) >= 2 and np.all(np.diff(times) > 0), times
    frames = [(t, meshio.read(folder / d.get("file"))) for t, d in zip(times, sets,
                                                                        strict=True)]
    for _, frame in frames:
        assert frame.points.shape[0] > 0
        assert set(frame.point_data) == set(frames[0][1].point_data)
        assert all(np.all(np.isfinite(v)) for v in frame.point_data.values())
    return frames


def test_a_frame_is_frozen_and_an_earlier_time_replaces_the_later_frames(unit_cube_hex):
    gf = ngs.GridFunction(ngs.H1(unit_cube_hex, order=1))
    gf.Set(1.0)
    frames = Frames(unit_cube_hex, 1, lambda: {"g": gf, "twice": 2 * gf}, names=("g", "twice"))
    for t in (0.0, 1.0, 2.0):
        frames.take(t)
        gf.Set(10.0 + t)                    # changes of the state after do not reach it
    point = unit_cube_hex(0.3, 0.4, 0.5)
    assert [f["g"](point) for _, f in frames] == pytest.approx([1.0, 10.0, 11.0])
    assert [f["twice"](point) for _, f in frames] == pytest.approx([2.0, 20.0, 22.0])
    frames.take(1.0)                        # a stage that started again from t = 1
    assert frames.times() == [0.0, 1.0] and frames.taken[1][1]["g"](point) == pytest.approx(12.0)
    steps = Frames(unit_cube_hex, 1, lambda: {"g": gf})
    steps.take(sum([0.1] * 10) - 1)         # -1.1e-16: the skin's inflation, ten steps
    steps.take(0.0)                         # the contact stage's correction: replaces it
    assert steps.times() == [0.0]
    only = Frames(unit_cube_hex, 1, lambda: {"g": gf, "twice": 2 * gf}, names=("g",))
    only.take(0.0)
    assert set(only.taken[0][1]) == {"g"}
    off = Frames(unit_cube_hex, 1, lambda: pytest.fail("computed without vtk"), enabled=False)
    off.take(0.0)
    assert len(off) == 0


def test_the_skin_writes_a_frame_per_step_of_every_stage(tmp_path, capsys):
    """Inflation in two steps (at -0.5 and 0: growth frozen, theta = 1), the hold (0.5 days:
    growth), the deflation after it (growth frozen: theta stays the hold's), the clamped
    and the released equilibria at hold_days + 2 and + 3."""
    out = tmp_path / "skin"
    assert main(["run", "skin", *SKIN_COARSE, "--set", "inflation_steps=2",
                 "--set", "outputs=vtk", "--out", str(out), "-q"]) == 0
    frames = series(out)
    times = [t for t, _ in frames]
    assert times[:3] == [-0.5, 0.0, 0.5] and times[-2:] == [2.5, 3.5]
    assert all(0.5 < t <= 1.5 for t in times[3:-2]) and len(times) > 5    # the deflation
    theta = {t: f.point_data["theta"].ravel() for t, f in frames}
    u = {t: f.point_data["u"] for t, f in frames}
    for t in (-0.5, 0.0):
        np.testing.assert_allclose(theta[t], 1.0, atol=1e-12)
    assert theta[0.5].max() > 1.001
    for t in times[3:]:
        np.testing.assert_allclose(theta[t], theta[0.5], atol=1e-12)
    lift = {t: np.abs(u[t][:, 2]).max() for t in times}
    assert 0 < lift[-0.5] < lift[0.0]                  # inflated in two steps
    assert lift[times[3]] < lift[0.5]                  # the deflation lowers it
    assert {f"fields_{k:03d}.vtu" for k in range(len(times))} <= {
        p.name for p in out.iterdir()}
    capsys.readouterr()


def test_the_folding_march_writes_a_frame_per_record(tmp_path, capsys):
    """The coarse flat branch in two steps of 5 days: a frame at each, whose cortex growth
    is theta_c = 1 + cortex_rate t (prescribed) and whose subcortex does not grow."""
    out = tmp_path / "folding"
    assert main(["run", "folding", *FOLDING_COARSE, "--set", "dt=5", "--set", "onset_dt=5",
                 "--set", "release=false", "--set", "outputs=vtk", "--out", str(out),
                 "-q"]) == 0
    frames = series(out)
    assert [t for t, _ in frames] == [5.0, 10.0]
    rate = FoldingScene().cortex_rate
    for t, frame in frames:
        theta = frame.point_data["theta"].ravel()
        assert theta.max() == pytest.approx(1 + rate * t, rel=1e-10)
        assert theta.min() == pytest.approx(1.0, abs=1e-10)
    capsys.readouterr()


def listed(folder):
    """The frame files fields.pvd lists (it parses as XML), after checking that they are
    exactly the frame files in the folder, that no temporary file is left, and that
    results.json lists them with the collection."""
    sets = ET.parse(folder / "fields.pvd").getroot().find("Collection").findall("DataSet")
    names = [d.get("file") for d in sets]
    present = sorted(p.name for p in folder.glob("fields_*.vtu"))
    assert sorted(names) == present, (names, present)
    assert not [p.name for p in folder.iterdir() if p.name.startswith(".")]
    files = json.loads((folder / "results.json").read_text())["files"]
    assert set(names) | {"fields.pvd"} <= set(files)
    return [float(d.get("timestep")) for d in sets]


def _on_call(monkeypatch, owner, name, when, action):
    """Call ``action()`` (once) before the call of ``owner.name`` whose arguments satisfy
    ``when``."""
    original, done = getattr(owner, name), []

    def wrapped(*args, **kwargs):
        if not done and when(*args, **kwargs):
            done.append(1)
            action()
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, wrapped)


def _sigint():
    os.kill(os.getpid(), signal.SIGINT)


def test_an_interrupted_skin_writes_the_frames_taken_before(tmp_path, monkeypatch, capsys):
    """Ctrl-C at the hold's first frame: the inflation's two frames are written and the
    series lists exactly them; results.json says "interrupted"."""
    _on_call(monkeypatch, Frames, "take", lambda self, t, *a: t > 0, _sigint)
    out = tmp_path / "skin"
    assert main(["run", "skin", *SKIN_COARSE, "--set", "inflation_steps=2",
                 "--set", "outputs=vtk", "--out", str(out), "-q"]) == EXIT_INTERRUPTED
    assert json.loads((out / "results.json").read_text())["status"] == "interrupted"
    assert listed(out) == [-0.5, 0.0]
    assert [t for t, _ in series(out)] == [-0.5, 0.0]          # readable frames
    assert "Traceback" not in capsys.readouterr().err


def test_a_skin_whose_hold_does_not_converge_writes_the_frames_taken_before(
        tmp_path, monkeypatch, capsys):
    """Every Newton solve fails once the inflation has ended (its frame at t = 0 taken):
    the hold does not converge (exit 3), and the inflation's frames are written."""
    ended = []

    def fails_after_the_inflation(self, record):
        if ended:
            record.reason = "simulated failure"
            return False
        return minimise(self, record)

    minimise = NewtonSolver.minimise
    monkeypatch.setattr(NewtonSolver, "minimise", fails_after_the_inflation)
    _on_call(monkeypatch, Frames, "take", lambda self, t, *a: t == 0.0,
             lambda: ended.append(1))
    out = tmp_path / "skin"
    assert main(["run", "skin", *SKIN_COARSE, "--set", "inflation_steps=2",
                 "--set", "outputs=vtk", "--out", str(out), "-q"]) == EXIT_NOT_CONVERGED
    written = json.loads((out / "results.json").read_text())
    assert written["status"] == "not converged" and "simulated failure" in written["error"]
    assert listed(out) == [-0.5, 0.0]
    capsys.readouterr()


def test_ctrl_c_while_writing_the_frames_keeps_a_series_of_those_written(tmp_path, monkeypatch,
                                                                         capsys):
    """The folding march's two frames: Ctrl-C as the second is written, between its writer
    and the rename to its name, leaves the first, a series listing it alone, no temporary
    file, and results.json marked "interrupted"."""
    _on_call(monkeypatch, io, "complete",
             lambda path, ending, final=None: Path(final or path).name == "fields_001.vtu",
             _sigint)
    out = tmp_path / "folding"
    assert main(["run", "folding", *FOLDING_COARSE, "--set", "dt=5", "--set", "onset_dt=5",
                 "--set", "release=false", "--set", "outputs=vtk", "--out", str(out),
                 "-q"]) == EXIT_INTERRUPTED
    written = json.loads((out / "results.json").read_text())
    assert written["status"] == "interrupted" and "writing" in written["error"]
    assert listed(out) == [5.0]
    assert set(written["file_hashes"]) == set(written["files"]) - {"results.json"}
    assert "Traceback" not in capsys.readouterr().err
