"""ngincompat.parallel: MPI runs against serial ones; every reduction the identity in serial."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

from geometries import cube
from ngincompat import parallel
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


def test_distributed_bddc_on_the_vertices_alone_meets_the_serial_equilibrium(runs, tmp_path):
    """``coarse=vertices`` on 3 ranks: the serial energy to 1e-10, in more CG iterations per
    direction than any of the default coarse space's (the vertex and edge dofs)."""
    serial, default, _, _ = runs
    launcher, _ = _mpiexec()
    settings = [f"--set={k}={v}" for k, v in {**SETTINGS, "outputs": "none"}.items()]
    done = _run(launcher, 3, "cube", "--out", str(tmp_path / "v"), "-q", *settings,
                "--set=coarse=vertices")
    assert done.returncode == 0, done.stderr[-2000:]
    assert "undocumented" not in done.stdout + done.stderr
    vertices = json.loads((tmp_path / "v" / "results.json").read_text())
    assert vertices["metrics"]["strain_energy"] == pytest.approx(
        serial.metrics["strain_energy"], rel=1e-10)
    counts = [[n for s in run["solver"]["growth"]["steps"] for n in s["linear_iterations"]]
              for run in (default, vertices)]
    assert min(counts[1]) > max(counts[0])


def test_distributed_run_writes_results_once_and_a_parallel_vtk(runs):
    _, parallel, out, stdout = runs
    assert stdout.count("cube: done") == 1          # rank 0 alone reports
    assert {"fields.pvd", "fields_proc1.vtu", "fields_proc2.vtu"} <= set(parallel["files"])
    for name in parallel["files"]:
        assert (out / name).is_file(), name
    pvd = (out / "fields.pvd").read_text()
    assert "fields_proc1.vtu" in pvd and "fields_proc2.vtu" in pvd
    assert not list(out.glob("fields.vtu")) and not list(out.glob(".*tmp*"))


def test_a_scene_that_does_not_distribute_refuses_mpi(tmp_path):
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    done = _run(launcher, 2, "hemisphere", "--out", str(tmp_path / "h"), timeout=300)
    assert done.returncode == 2
    assert done.stderr.count("does not run distributed") == 1       # said once, by rank 0
    assert "Traceback" not in done.stderr
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


def _brain_on_3_ranks(settings, out, monkeypatch, timeout):
    """The atrophy scene with ``settings`` on a brain of nilearn's (its mesh built into an
    empty cache, which the serial run then reads) run on 3 ranks into ``out``; the
    completed process, checked to have ended with 0."""
    pytest.importorskip("nilearn")
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(out.parent / "cache"))
    done = _run(launcher, 3, "atrophy", "--out", str(out), "-q",
                *[f"--set={k}={v}" for k, v in settings.items()], timeout=timeout)
    assert done.returncode == 0, done.stderr[-2000:]
    return done


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

    out = tmp_path / "fsaverage"
    done = _brain_on_3_ranks(FSAVERAGE, out, monkeypatch, timeout=1800)
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


#: The MNI152 brain at 2 cm voxels (214 hexahedra): the transport's upwinding sums, across
#: the ranks, entries of vertex pairs that are no edges (the diagonals of the voxels' faces).
VOXEL_BRAIN = {"geometry": "mni152", "maxh": 2.0, "seed": "entorhinal", "t_end": 10.0,
               "dt": 0.5, "snapshots": 1, "outputs": "none"}


def test_distributed_voxel_brain_matches_serial(tmp_path, monkeypatch):
    """Hexahedra on 3 ranks: the run ends (it hung, the workers' transport failing alone)
    and gives the serial run's metrics, c staying in [0, 1]."""
    from ngincompat.scenes.atrophy import AtrophyScene

    out = tmp_path / "mni152"
    _brain_on_3_ranks(VOXEL_BRAIN, out, monkeypatch, timeout=300)
    p = json.loads((out / "results.json").read_text())["metrics"]
    s = AtrophyScene(**VOXEL_BRAIN).run().metrics
    for key in ("c_integral", "c_min", "c_max", "volume_loss", "gray_volume_loss",
                "strain_energy", "max_principal_stress"):
        assert p[key] == pytest.approx(s[key], rel=1e-8, abs=1e-300), key
    assert 0 <= s["c_min"] < s["c_max"] <= 1


def test_an_error_of_one_rank_alone_ends_the_job_and_a_shared_one_passes():
    """A rank that raises alone inside ``alone_ends_the_job`` ends every rank (without it
    the others wait in the barrier for ever); an error of a collective kind, raised on
    every rank, passes to each."""
    launcher, reason = _mpiexec()
    if launcher is None:
        pytest.skip(reason)
    script = (
        "from ngincompat import parallel\n"
        "comm = parallel.world()\n"
        "try:\n"
        "    with parallel.alone_ends_the_job((ValueError,)):\n"
        "        raise ValueError('everywhere')\n"
        "except ValueError:\n"
        "    print('passed', flush=True)\n"
        "with parallel.alone_ends_the_job((ValueError,)):\n"
        "    if comm.rank == 1:\n"
        "        raise KeyError('on rank 1 alone')\n"
        "    comm.barrier()\n"
        "print('not reached', flush=True)\n")
    done = subprocess.run([launcher, "-n", "2", sys.executable, "-c", script], cwd=ROOT,
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 1
    assert done.stdout.count("passed") == 2 and "not reached" not in done.stdout
    assert "KeyError: 'on rank 1 alone'" in done.stderr


# ---------------------------------------------------------------- serial runs


@pytest.fixture
def serial(monkeypatch):
    """A run launched without MPI: no launcher's variables, the world asked for anew."""
    for variable in parallel._SIZE_VARIABLES:
        monkeypatch.delenv(variable, raising=False)
    parallel.world.cache_clear()
    yield
    parallel.world.cache_clear()


def test_a_run_without_a_launcher_or_on_one_rank_is_serial(serial, monkeypatch):
    assert parallel.world() is None and parallel.is_root()
    parallel.world.cache_clear()
    monkeypatch.setenv("PMI_SIZE", "1")
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "one")        # not a number: ignored
    assert parallel.world() is None and parallel.is_root()


def test_several_ranks_without_mpi4py_is_an_error_naming_the_extra(serial, monkeypatch):
    monkeypatch.setenv("OMPI_COMM_WORLD_SIZE", "4")
    monkeypatch.setitem(sys.modules, "mpi4py", None)         # import mpi4py fails
    with pytest.raises(ImportError, match=r"several MPI ranks.*pip install 'ngincompat\[mpi\]'"):
        parallel.world()


def test_in_a_serial_run_every_reduction_is_the_identity(serial):
    """The sums and maxima over the ranks are the rank's own number (as float), the merged
    point values and gathered rows are the arrays given, the counts the mesh's."""
    mesh = cube(maxh=0.5)
    assert not parallel.distributed(mesh)
    assert parallel.total(mesh, 3) == 3.0 and isinstance(parallel.total(mesh, 3), float)
    assert parallel.maximum(mesh, -np.inf) == -np.inf
    values = np.array([1.0, np.nan, 2.0])
    assert parallel.first_found(mesh, values) is values
    rows = np.arange(6.0).reshape(3, 2)
    assert parallel.gather_rows(mesh, rows) is rows
    assert parallel.counts(mesh) == (8, 27)


def test_in_a_serial_run_the_mesh_is_built_once_and_whole(serial):
    built = []

    def build():
        built.append(cube(maxh=0.5))
        return built[-1]

    mesh = parallel.distribute(build)
    assert mesh is built[0] and len(built) == 1


def test_a_geometry_is_meshed_and_curved_in_a_serial_run(serial):
    """The unit ball of maxh 0.5: curved to order 3, its volume is 4 pi / 3 to 1e-3; straight,
    the inscribed polyhedron's is visibly smaller."""
    from netgen.occ import OCCGeometry, Pnt, Sphere

    geometry = OCCGeometry(Sphere(Pnt(0, 0, 0), 1.0))
    curved = parallel.distribute_geometry(geometry, maxh=0.5, curve_order=3)
    straight = parallel.distribute_geometry(geometry, maxh=0.5)
    assert ngs.Integrate(1, curved) == pytest.approx(4 / 3 * np.pi, rel=1e-3)
    assert ngs.Integrate(1, straight) < 0.98 * 4 / 3 * np.pi
    assert curved.ne == straight.ne > 0


def test_on_root_returns_the_result_or_raises_the_error_of_the_call(serial):
    assert parallel.on_root(divmod, 7, 2) == (3, 1)
    assert parallel.on_root(int, "ff", base=16) == 255

    def fails(path):
        raise FileNotFoundError(path)

    with pytest.raises(FileNotFoundError, match="nowhere"):
        parallel.on_root(fails, "nowhere")
