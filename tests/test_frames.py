"""Time series of the time-dependent scenes (fields.pvd): the frames of the skin's stages and
of the folding march, each frame file a readable VTK file holding the state of its time."""

import xml.etree.ElementTree as ET

import meshio
import ngsolve as ngs
import numpy as np
import pytest
from conftest import FOLDING_COARSE, SKIN_COARSE

from ngincompat.cli import main
from ngincompat.scenes import FoldingScene
from ngincompat.workflow.frames import Frames


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
