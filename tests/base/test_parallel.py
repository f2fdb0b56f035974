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

ROOT = Path(__file__).resolve().parents[2]
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


def _run(launcher, ranks, *args, timeout=600):
    """``ngincompat run ARGS`` launched on ``ranks`` MPI ranks, from this worktree."""
    return subprocess.run([launcher, "-n", str(ranks), sys.executable, "-m", "ngincompat.cli",
                           "run", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, env={**os.environ, "PYTHONPATH": str(ROOT)})


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """The serial run (in this process) and the 3-rank run (mpiexec) of the same cube."""
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp("mpi") / "cube"
    settings = [f"--set={k}={v}" for k, v in SETTINGS.items()]
    done = _run(launcher, 3, "cube", "--out", str(out), "-q", *settings)
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
    done = _run(launcher, 2, "hemisphere", "--out", str(tmp_path / "h"), timeout=300)
    assert done.returncode == 2
    assert "does not run distributed" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "h" / "results.json").exists()


#: A coarse ellipsoidal brain (1295 curved tetrahedra, 11k dofs), two equilibria.
ATROPHY = {"maxh": 1.0, "semi_axes": "3,2.5,2", "gray_thickness": 0.5, "t_end": 10.0,
           "dt": 1.0, "snapshots": 2, "seed": "0,0,-1.5", "outputs": "vtk"}


@pytest.mark.slow
def test_distributed_atrophy_matches_serial(tmp_path):
    """Transport (Jacobi-CG on the ranks' parts, upwinding on the summed entries), the
    mixed mechanics (BDDC-CG), the reduced measures and the depth profile on 3 ranks
    against the serial run (sparse direct solvers) of the same curved ellipsoid."""
    from ngincompat.scenes.atrophy import AtrophyScene

    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    out = tmp_path / "atrophy"
    settings = [f"--set={k}={v}" for k, v in ATROPHY.items()]
    done = _run(launcher, 3, "atrophy", "--out", str(out), "-q", *settings, timeout=1200)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.count("atrophy: done") == 1
    parallel = json.loads((out / "results.json").read_text())
    serial = AtrophyScene(**{**ATROPHY, "outputs": "none"}).run()
    assert parallel["mesh"]["ne"] == serial.mesh.ne == 1295
    assert parallel["mesh"]["ndof"] == serial.mesh.ndof
    s, p = serial.metrics, parallel["metrics"]
    for key in ("volume_loss", "gray_volume_loss", "white_volume_loss", "strain_energy",
                "max_principal_stress", "burgers_max", "c_integral", "c_min", "front_radius",
                "gray_volume", "burgers_interface_fraction", "stress_interface_over_surface"):
        assert p[key] == pytest.approx(s[key], rel=1e-8), key
    assert s["gray_volume_loss"] > 10 * s["white_volume_loss"] > 0
    # the profile along +X1: a point on a face between two elements takes the value of
    # either (the one the serial search finds need not be the one a rank finds: the stress
    # jumps there, and P1's c differs by its gradient times the search's tolerance), so all
    # but such points agree (on this mesh one point of 401)
    line = parallel["profiles"]["line"]
    for key in ("c", "sigma_max_principal"):
        ref, got = serial.profiles["line"][key], np.asarray(line[key], dtype=float)
        inside = np.isfinite(ref)
        assert np.array_equal(np.isfinite(got), inside), key
        equal = np.abs(got - ref)[inside] <= 1e-8 * np.abs(ref[inside]).max()
        assert np.count_nonzero(~equal) <= 2, key
    surface = parallel["profiles"]["surface"]
    assert len(surface["points"]) == len(serial.profiles["surface"]["points"])
    assert len(surface["triangles"]) == len(serial.profiles["surface"]["triangles"])
    for step in parallel["solver"]["t=10"]["steps"]:
        assert all(n >= 3 for n in step["linear_iterations"])      # CG, not a direct solve
    assert {"fields.pvd", "fields_proc1.vtu", "fields_proc2.vtu"} <= set(parallel["files"])
    # the time series: a frame per equilibrium (t = 5, 10), each in two parts
    series = (out / "fields_series.pvd").read_text()
    for k, t in enumerate((5.0, 10.0)):
        for rank in (1, 2):
            name = f"fields_{k:03d}_proc{rank}.vtu"
            assert (out / name).is_file() and name in parallel["files"]
            assert f'timestep="{t!r}" group="" part="{rank - 1}" file="{name}"' in series


#: The fsaverage hemisphere at its default mesh (ico 4, 2 layers of prisms: 39825 tetrahedra)
#: with linear displacements, one equilibrium at 10 years.
FSAVERAGE = {"geometry": "fsaverage", "order": 1, "formulation": "displacement",
             "t_end": 10.0, "dt": 1.0, "snapshots": 1, "outputs": "none"}


@pytest.mark.slow
def test_distributed_fsaverage_matches_serial(tmp_path, monkeypatch):
    """The anatomical brain on 3 ranks: the mesh built on rank 0 (into an empty cache) and
    distributed, the elements across the cortex counted by point location on every rank's
    part and merged, against the serial run of the same mesh read from that cache."""
    from ngincompat.scenes.atrophy import AtrophyScene

    pytest.importorskip("nilearn")
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(tmp_path / "cache"))
    out = tmp_path / "fsaverage"
    settings = [f"--set={k}={v}" for k, v in FSAVERAGE.items()]
    done = _run(launcher, 3, "atrophy", "--out", str(out), "-q", *settings, timeout=1800)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.count("atrophy: done") == 1
    assert done.stderr.count("equilibrium_residual_rel") == 1        # rank 0 alone warns
    parallel = json.loads((out / "results.json").read_text())
    assert len(list((tmp_path / "cache").glob("fsaverage_left_ico4_L2_*"))) == 1
    serial = AtrophyScene(**FSAVERAGE).run()
    assert parallel["mesh"]["ne"] == serial.mesh.ne == 39825
    assert parallel["mesh"]["ndof"] == serial.mesh.ndof
    s, p = serial.metrics, parallel["metrics"]
    for key in ("volume_loss", "gray_volume_loss", "white_volume_loss", "strain_energy",
                "max_principal_stress", "burgers_max", "c_integral", "gray_volume",
                "white_volume", "cortex_elements_across_min", "cortex_elements_across_median",
                "burgers_interface_fraction", "stress_interface_over_surface",
                "Je_deviation_max"):
        assert p[key] == pytest.approx(s[key], rel=1e-8), key
    assert p["cortex_elements_across_median"] == pytest.approx(2.0, abs=0.05)
    assert p["volume_surface_deviation"] < 1e-10
    assert s["gray_volume_loss"] > 10 * s["white_volume_loss"] > 0
