"""Distributed runs: the cube on 3 MPI ranks (2 subdomains) against the serial run, and
Newton with an iterative linear solver against the direct one."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ngincompat.scenes.cube import CubeScene

ROOT = Path(__file__).resolve().parents[1]
# coarse: 3 hexahedra per edge, so the profile line X2 = X3 = 1/2 runs inside elements
SETTINGS = {"order": 2, "maxh": 0.34, "elements": "hex", "outputs": "vtk"}


def _mpiexec():
    """The launcher next to this Python (the mpich wheel's), or the reason MPI cannot start."""
    try:
        import mpi4py  # noqa: F401
    except ImportError:
        return None, "mpi4py is not installed (pip install '.[mpi]')"
    launcher = Path(sys.executable).parent / "mpiexec"
    launcher = str(launcher) if launcher.exists() else shutil.which("mpiexec")
    if launcher is None:
        return None, "no mpiexec next to this Python or on PATH (pip install mpich)"
    probe = subprocess.run([launcher, "-n", "2", sys.executable, "-c",
                            "from mpi4py import MPI; assert MPI.COMM_WORLD.size == 2"],
                           capture_output=True, text=True, timeout=120)
    if probe.returncode != 0:
        return None, f"MPI cannot start 2 ranks here: {probe.stderr.strip()[-300:]}"
    return launcher, ""


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The serial run (in this process) and the 3-rank run (mpiexec) of the same cube."""
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp("mpi") / "cube"
    settings = [f"--set={k}={v}" for k, v in SETTINGS.items()]
    done = subprocess.run([launcher, "-n", "3", sys.executable, "-m", "ngincompat.cli", "run",
                           "cube", "--out", str(out), "-q", *settings],
                          cwd=ROOT, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0, done.stderr[-2000:]
    serial = CubeScene(**{**SETTINGS, "outputs": "none"}).run()
    return serial, json.loads((out / "results.json").read_text()), out, done.stdout


def test_distributed_cube_matches_serial(runs):
    serial, parallel, _, _ = runs
    assert parallel["status"] == "done"
    assert parallel["mesh"]["ndof"] == serial.mesh.ndof
    assert parallel["mesh"]["ne"] == serial.mesh.ne == 27
    assert parallel["mesh"]["nv"] == serial.mesh.nv == 64
    s, p = serial.metrics, parallel["metrics"]
    for key in ("strain_energy", "max_principal_stress", "G_norm_L2", "burgers_max"):
        assert p[key] == pytest.approx(s[key], rel=1e-10), key
    # the G error is itself relative to ||G|| (and round-off small: the growth field is
    # interpolated exactly up to order g_order), so its difference is compared absolutely
    assert abs(p["G_error_L2_rel"] - s["G_error_L2_rel"]) < 1e-10
    for label in ("S11", "S22", "S33"):
        ref = serial.profiles["line"][label]
        got = np.asarray(parallel["profiles"]["line"][label])
        assert np.all(np.isfinite(got))
        scale = np.abs(ref).max()
        assert np.abs(got - ref).max() <= 1e-10 * scale, label


def test_distributed_cube_solves_with_bddc_and_reports_its_iterations(runs):
    _, parallel, _, _ = runs
    assert parallel["params"]["linear_solver"] == "auto"
    steps = parallel["solver"]["growth"]["steps"]
    assert all(s["converged"] for s in steps)
    for s in steps:
        # one CG solve per Newton direction, each a real iteration (a direct solve is 1-2)
        assert len(s["linear_iterations"]) == s["iterations"]
        assert all(3 <= n < 2000 for n in s["linear_iterations"])


def test_distributed_run_writes_results_once_and_a_parallel_vtk(runs):
    _, parallel, out, stdout = runs
    assert stdout.count("cube: done") == 1          # rank 0 alone reports
    assert {"fields.pvd", "fields_proc1.vtu", "fields_proc2.vtu"} <= set(parallel["files"])
    for name in parallel["files"]:
        assert (out / name).is_file(), name
    pvd = (out / "fields.pvd").read_text()
    assert "fields_proc1.vtu" in pvd and "fields_proc2.vtu" in pvd
    assert not list(out.glob("fields.vtu")) and not list(out.glob(".*tmp*"))


@pytest.mark.parametrize("linear_solver", ["cg", "gmres"])
def test_newton_with_bddc_matches_the_direct_solver(linear_solver):
    settings = {**SETTINGS, "outputs": "none"}
    direct = CubeScene(**settings).run()
    iterative = CubeScene(**settings, linear_solver=linear_solver).run()
    assert iterative.metrics["strain_energy"] == pytest.approx(
        direct.metrics["strain_energy"], rel=1e-10)
    steps = iterative.solver["growth"].steps
    assert [len(s.linear_iterations) for s in steps] == [s.iterations for s in steps]
    assert all(n >= 3 for s in steps for n in s.linear_iterations)
    assert iterative.newton_iterations == direct.newton_iterations


def test_linear_solver_is_checked():
    from ngincompat.errors import ParameterError
    with pytest.raises(ParameterError, match="linear_solver"):
        CubeScene(linear_solver="mumps")


def test_a_scene_that_does_not_distribute_refuses_mpi(tmp_path):
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    done = subprocess.run([launcher, "-n", "2", sys.executable, "-m", "ngincompat.cli", "run",
                           "hemisphere", "--out", str(tmp_path / "h")], cwd=ROOT,
                          capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 2
    assert "does not run distributed" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "h" / "results.json").exists()
