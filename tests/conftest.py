"""Shared fixtures: small meshes and evaluation helpers."""

import contextlib
import os
import signal

import ngsolve as ngs
import numpy as np
import pytest

from geometries import cube
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.materials import NeoHookean

#: Command-line settings that run the skin scene in seconds: linear elements, a mesh size of
#: 3 cm, a low dome (3 cc, inflated in one step) and half a day of growth from any stretch
#: (theta_crit = 1: at 3 cc the skin is stretched less than the default 1.05) (a smoke test:
#: the numbers are not the scene's). At 50 cc this mesh concentrates the contact model's
#: force at the apex, and its deflation takes minutes (the dead traction's path has a limit
#: point there, and the stage starts again, lowering the dome).
SKIN_COARSE = ["--set", "maxh=3", "--set", "order=1", "--set", "growth_order=0", "--set",
               "g_order=2", "--set", "volume=3", "--set", "inflation_steps=1", "--set",
               "theta_crit=1", "--set", "hold_days=0.5", "--set", "dt=0.5"]

#: Command-line settings that run the folding scene in seconds: a short, shallow bilayer on
#: a coarse subcortex, grown in one step to theta_c = 1.08, before the onset (a smoke test).
FOLDING_COARSE = ["--set", "length=0.5", "--set", "height=0.3", "--set", "maxh=0.15",
                  "--set", "t_end=10", "--set", "dt=10", "--set", "onset_dt=10"]

#: Command-line settings of the smallest bilayer seen to crease with its sulci in contact and
#: reach the paper's 75 days (docs/measurements/folding.md, "The paper's 75
#: days"): its subcortex coarse and its top refined 4 times (refined twice, its folds deepen
#: without their walls touching).
FOLDING_CREASING = ["--set", "length=1", "--set", "height=0.6", "--set", "cortex_thickness=0.1",
                    "--set", "cortex_maxh=0.05", "--set", "maxh=0.5", "--set",
                    "top_refinement=4", "--set", "t_end=75", "--set", "dt=10", "--set",
                    "onset_dt=5", "--set", "observe_dt=10"]


@contextlib.contextmanager
def local_dask_cluster():
    """A local Dask cluster of one worker process with one thread (skipped without Dask).

    Its nanny, here in the test's process, writes Dask's ``pre-spawn-environ`` into
    ``os.environ`` before it starts the worker, and leaves it there; the environment is
    restored at once, as every process a later test starts would inherit it. Of what it
    sets, ``MALLOC_TRIM_THRESHOLD_=65536`` makes glibc map every allocation of 128 KB and
    more anew and return it at every free: ``examples/folding/step_costs.py`` on the coarse
    bilayer took 74 s (54 s of it in the kernel) instead of 16 s, and in the suite a test
    file's scripts and the README sweep's case ran 5-10 times longer."""
    distributed = pytest.importorskip("dask.distributed")
    environment = dict(os.environ)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        os.environ.clear()
        os.environ.update(environment)
        yield cluster


@pytest.fixture
def ctrl_c_raises():
    """SIGINT raises KeyboardInterrupt in the test, as in a terminal, also where the suite was
    started with SIGINT ignored (a background job of a non-interactive shell: Python then
    installs no handler, and a test's own SIGINT is lost); the previous handler after it."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.fixture(scope="session")
def unit_cube_hex():
    """A 3 x 3 x 3 hexahedral mesh of the unit cube."""
    return cube(maxh=1 / 3)


@pytest.fixture(scope="session")
def unit_cube_tet():
    """A coarse tetrahedral mesh of the unit cube."""
    return cube(maxh=0.5, elements="tet")


def values_at(cf, mesh, points):
    """Evaluate a CoefficientFunction at an (n, 3) array of points; returns (n, k)."""
    pts = np.asarray(points, dtype=float)
    v = np.asarray(cf(mesh(pts[:, 0], pts[:, 1], pts[:, 2])))
    return v.reshape(len(pts), -1)


def random_points(n=20, seed=0, low=0.05, high=0.95):
    return np.random.default_rng(seed).uniform(low, high, size=(n, 3))


def l2_norm(cf, mesh, order=8):
    return float(ngs.Integrate(ngs.InnerProduct(cf, cf), mesh, order=order)) ** 0.5


def cube_problem(a=0.25, maxh=0.5, order=2, elements="hex", condense=True):
    """The paper's cube (section 3.1) with theta = 1 + a X1 t: (GrowthMechanics, time)."""
    time = ngs.Parameter(0.0)
    growth = IsotropicGrowth(1 + a * ngs.x * time)
    mesh = cube(maxh=maxh, elements=elements)
    material = NeoHookean.paper_idealized()
    return GrowthMechanics(mesh, growth, material, order=order, condense=condense), time


def peer_stand_in(folder):
    """A folder laid out like the FEniCSx peer's whose script only prints a RESULT line, with
    a known energy and solve time (the benchmark's arithmetic, not the peer, is tested);
    returns the folder and the record its script prints."""
    import json
    import sys

    from ngincompat.studies import peer
    from ngincompat.studies.bench import CUBE_ENERGY
    (folder / "debroot").mkdir(parents=True)
    (folder / peer.PEER_ENV).write_text(f'PY="{sys.executable}"\n')
    record = {"version": "0.5.2", "cell": "tet", "degree": 4, "N": 4, "solver": "lu",
              "dofs": 14739, "newton_its": 3, "t_solve": 7.5, "W": CUBE_ENERGY * (1 + 5e-2)}
    (folder / peer.PEER_SCRIPT).write_text(
        "import sys\nassert sys.argv[1:] == ['--N', '4', '--degree', '4', '--quiet']\n"
        f"print('noise')\nprint('RESULT ' + {json.dumps(json.dumps(record))})\n")
    return folder, record


#: Voxel edge of the synthetic label images (mm).
VOXEL = 5.0


def voxel_labels():
    """A label image (0 outside, 1 gray, 2 white): a 6 x 5 x 4 block, a white core of
    2 x 2 x 1, the rest gray; and one gray island."""
    lab = np.zeros((10, 9, 8), dtype=np.int16)
    lab[1:7, 1:6, 1:5] = 1
    lab[3:5, 2:4, 2:3] = 2
    lab[8, 7, 6] = 1                      # an island: not face-connected to the block
    return lab


def write_nifti(path, lab, affine=None):
    """``lab`` written as a NIfTI image of :data:`VOXEL` voxels (nibabel: the brain extra)."""
    import nibabel
    affine = np.diag([VOXEL, VOXEL, VOXEL, 1.0]) if affine is None else affine
    nibabel.save(nibabel.Nifti1Image(lab, affine), str(path))
    return str(path)
