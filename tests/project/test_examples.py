"""The measuring scripts under ``examples/`` that the docs quote run, on a coarse bilayer or
brain, as a user would call them (``python examples/<folder>/<script>.py key=value ...``)."""

import importlib.util
import json
import re
import subprocess
import sys
from pathlib import Path

import ngsolve as ngs
import pytest
from netgen.meshing import Element3D, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh

ROOT = Path(__file__).resolve().parents[2]

#: The folding tests' coarse bilayer (``conftest.FOLDING_COARSE``) as the scripts' arguments.
COARSE = ["length=0.5", "height=0.3", "maxh=0.15", "cortex_maxh=0.025"]


def _run(script, *args, folder="folding"):
    done = subprocess.run([sys.executable, str(ROOT / "examples" / folder / script), *args],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    return done.stdout


def test_step_costs_times_every_part_of_a_step():
    out = _run("step_costs.py", *COARSE)
    for part in ("residual", "tangent assembly", "factorisation umfpack", "eigenpairs (6)",
                 "top_stretch"):
        line = next(line for line in out.splitlines() if line.startswith(part))
        assert float(line.split()[-2]) > 0


def test_march_reports_the_onset_and_the_march_records():
    """The coarse bilayer's perfect branch finds the onset at its step to t = 40 (theta_c =
    1.283 at t = 35.4), and the march goes on to t_end = 42 in 3 steps (45 s alone; to
    t_end = 45, 10 steps and a cut, 70 s)."""
    out = _run("march.py", "axons=curved", "t_end=42", "dt=10", "onset_dt=10", *COARSE)
    assert "onset {" in out and "onset_growth" in out
    assert "buckling:" in out
    assert out.rstrip().endswith("status done None")


def test_coarse_spaces_compares_the_shapes_and_the_cg_iterations():
    """On a coarse ellipsoid the vertices alone make a smaller coarse space than with the
    edges, and CG needs more iterations with it; the shape percentiles are ordered and at
    most 1 (the regular tetrahedron's)."""
    out = _run("coarse_spaces.py", "maxh=2", "maxiter=2000", folder="brain")
    shape = re.search(r"min ([\d.e-]+), 1 % ([\d.e-]+), 10 % ([\d.e-]+), median ([\d.e-]+)", out)
    q = [float(v) for v in shape.groups()]
    assert 0 < q[0] <= q[1] <= q[2] <= q[3] <= 1
    runs = {m[0]: (int(m[1]), int(m[2])) for m in
            re.findall(r"^(\w+): \d+ unknowns, coarse space (\d+), CG iterations \[(\d+)\]",
                       out, flags=re.M)}
    assert runs["vertices"][0] < runs["edges"][0]
    assert runs["edges"][1] < runs["vertices"][1] < 2000


def test_coarse_spaces_runs_on_a_voxel_brain_of_hexahedra():
    """The MPI guide sends users' own brains to the script; a voxel brain's hexahedra have
    no tetrahedron shape (it raised a LinAlgError), but its CG iterations are measured."""
    pytest.importorskip("nilearn")
    out = _run("coarse_spaces.py", "geometry=mni152", "maxh=2", folder="brain")
    assert "no tetrahedra among the 214 elements" in out
    assert re.search(r"^vertices: \d+ unknowns, coarse space \d+, CG iterations \[\d+\]", out,
                     flags=re.M)


@pytest.mark.parametrize("arg, named", [("lam=abc", "lam"), ("maxiter=0", "maxiter"),
                                        ("coarse=faces", "coarse"), ("nu=0.6", "nu"),
                                        ("maxh", "key=value")])
def test_coarse_spaces_names_the_bad_setting(arg, named):
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "brain" / "coarse_spaces.py"),
                           arg], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert named in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("corners, q", [
    ([(0, 0, 0), (1, 0, 0), (0.5, 3 ** 0.5 / 2, 0), (0.5, 3 ** 0.5 / 6, (2 / 3) ** 0.5)], 1.0),
    ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], 2 ** 0.5 / 1.5 ** 1.5),   # a cube's corner
    ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0.3, 0.3, 1e-4)], 0.0)])             # nearly flat
def test_the_shape_measure_is_one_for_the_regular_tetrahedron(corners, q):
    """q = 6 sqrt(2) V / l^3: 1 for the regular tetrahedron, sqrt(2) / 1.5^1.5 for the corner
    of a cube (three edges 1, three sqrt(2)), about 0 for a flat one."""
    spec = importlib.util.spec_from_file_location("coarse_spaces",
                                                  ROOT / "examples" / "brain" / "coarse_spaces.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    mesh = NetgenMesh(dim=3)
    points = [mesh.Add(MeshPoint(Pnt(*corner))) for corner in corners]
    mesh.Add(Element3D(1, points))
    assert module.shapes(ngs.Mesh(mesh))[0] == pytest.approx(q, abs=2e-3)


def _fake_run(folder, axons, metrics, contact):
    """A ``results.json`` of a folding run with ``metrics`` and march records whose contact
    lengths are ``contact`` at the days 50, 51, 52, ..."""
    run = Path(folder) / axons
    run.mkdir(parents=True)
    days = [50.0 + k for k in range(len(contact))]
    (run / "results.json").write_text(json.dumps({
        "status": "done", "metrics": metrics, "mesh": {"ndof": 100},
        "timings": {"buckling": 2.0, "release": 1.0},
        "profiles": {"buckling": {"t": days, "contact_length": contact}},
        "provenance": {"date": "2026-11-28T10:00:00", "git": {"commit": "abc"}}}))


def test_convergence_compares_each_level_with_the_next_finer(tmp_path):
    """Two levels of two axon fields: each measure's values side by side and the coarse
    level's difference relative to the fine one; the crease day is the first record in
    contact, missing where the top never touched itself."""
    _fake_run(tmp_path / "L0", "curved", {"sulci": 9, "burgers_interface_mean": 7.5}, [0, 0])
    _fake_run(tmp_path / "L1", "curved", {"sulci": 9, "burgers_interface_mean": 10.0},
              [0, 0.1, 0.2])
    _fake_run(tmp_path / "L0", "straight", {"sulci": 8.5}, [0.3])
    _fake_run(tmp_path / "L1", "straight", {"sulci": 8.0}, [0, 0, 0.1])
    out = tmp_path / "table"
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "folding" / "convergence.py"),
                           "--out", str(out), f"L0={tmp_path / 'L0'}", f"L1={tmp_path / 'L1'}"],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    rows = {(r["axons"], r["measure"]): r
            for r in json.loads((out / "convergence.json").read_text())["rows"]}
    b = rows["curved", "burgers_interface_mean"]
    assert (b["L0"], b["L1"], b["L0 vs L1 [%]"], b["unit"]) == (7.5, 10.0, -25.0, "1/cm")
    assert rows["curved", "crease_day"]["L0"] is None
    assert rows["curved", "crease_day"]["L1"] == 51.0
    assert rows["straight", "crease_day"]["L0 vs L1 [%]"] == pytest.approx(-3.8)
    assert rows["straight", "sulci"]["L0 vs L1 [%]"] == 6.2
    assert ("concentric", "sulci") not in rows
    assert "L0 curved: 100 unknowns, 3 s, done" in (out / "made_by.md").read_text()
