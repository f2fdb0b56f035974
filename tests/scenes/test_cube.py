"""ngincompat.scenes.cube: the cube of section 3.1 end to end: its results, the profile of Fig.
1g, the quarter model and the mixed formulation."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene

REQUIRED = {"scene", "status", "params", "units", "versions", "mesh", "solver", "timings",
            "metrics", "profiles", "figures", "files"}


@pytest.fixture(scope="module")
def cube_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cube")
    code = main(["run", "cube", "--out", str(out), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "-q"])
    assert code == 0
    return out, json.loads((out / "results.json").read_text())


def test_cube_run_writes_complete_results(cube_run):
    out, results = cube_run
    assert REQUIRED <= set(results)
    assert results["scene"] == "cube"
    assert results["mesh"]["order"] == 3 and results["mesh"]["maxh"] == 0.5
    assert results["mesh"]["ndof"] > 0 and results["mesh"]["ne"] == 8
    assert set(results["versions"]) >= {"ngincompat", "ngsolve", "netgen", "numpy", "python"}
    solver = results["solver"]["growth"]
    assert results["status"] == "done"
    assert solver["converged"] and solver["steps"][-1]["residuals"]
    assert all(s["iterations"] == len(s["residuals"]) - 1 for s in solver["steps"])
    assert {"mesh", "growth", "incompatibility", "postprocess", "output"} <= set(
        results["timings"])
    metrics = results["metrics"]
    assert metrics["strain_energy"] == pytest.approx(2.19533e-7, rel=0.1)
    assert metrics["G_error_L2_rel"] < 1e-5
    # max |b| over the planes n2, n3: 1 / (12 theta^(4/3)) at theta = 1, i.e. X1 = 0
    assert metrics["burgers_max"] == pytest.approx(1 / 12, rel=1e-5)
    assert metrics["G_elastic_vs_growth_L2_rel"] < 0.05
    assert {p.name for p in out.iterdir()} == {"results.json", "fields.vtu", "profile.png",
                                              "burgers.png", "stress.png"}


def test_cube_profile_is_fig1g(cube_run):
    """Along the X1 centre line: Curl Fg : Curl Fg = 2 a^2 / (9 theta^(4/3)) (from eq. 15)
    decreases with X1, and Psi > 0."""
    _, results = cube_run
    line = results["profiles"]["line"]
    import numpy as np
    X1 = np.asarray(line["X1"])
    theta = 1 + X1 / 4
    np.testing.assert_allclose(line["curlFg_sq"], 2 * 0.0625 / (9 * theta ** (4 / 3)),
                               rtol=1e-5)
    np.testing.assert_allclose(line["theta"], theta, rtol=1e-8)
    assert min(line["Psi"]) > 0
    assert X1[0] == pytest.approx(0) and X1[-1] == pytest.approx(1)


def test_quarter_cube_is_the_full_cube_with_mirror_planes(cube_run, tmp_path):
    """The quarter model (two mirror planes, one pinned dof) gives the full cube's energy,
    G error and largest stress from a quarter of the elements."""
    _, full = cube_run
    code = main(["run", "cube", "--out", str(tmp_path), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "--set", "model=quarter", "--set", "outputs=none", "-q"])
    assert code == 0
    quarter = json.loads((tmp_path / "results.json").read_text())
    assert quarter["mesh"]["ne"] * 4 == full["mesh"]["ne"]
    for key in ("strain_energy", "max_principal_stress", "G_norm_L2"):
        assert quarter["metrics"][key] == pytest.approx(full["metrics"][key], rel=1e-6), key
    assert quarter["metrics"]["G_error_L2_rel"] < 1e-8


def test_mixed_formulation_from_the_command_line(cube_run, tmp_path):
    """At nu = 0.4 the mixed and the displacement formulation agree to the discretisation
    error (order 3 on 2 x 2 x 2 hexahedra: 0.9 %, against 2.3 % of the displacement one from
    the converged 2.195334e-7)."""
    _, full = cube_run
    code = main(["run", "cube", "--out", str(tmp_path), "--order", "3", "--maxh", "0.5",
                 "--set", "elements=hex", "--set", "formulation=mixed", "--set", "outputs=none",
                 "-q"])
    assert code == 0
    mixed = json.loads((tmp_path / "results.json").read_text())
    reference = 2.195334e-7
    e_mixed, e_displacement = mixed["metrics"]["strain_energy"], full["metrics"]["strain_energy"]
    assert abs(e_mixed - reference) < abs(e_displacement - reference)
    assert abs(e_mixed - reference) / reference < 0.02


@pytest.mark.parametrize("setting, message", [
    (dict(a=-1.0), r"^a = -1\.0 is out of range: allowed > -1 / side \(theta stays positive\)"),
    (dict(a=-0.5, side=2.0), r"^a = -0\.5 .* > -1 / side"),
    (dict(quadrature="symmetric", elements="hex"), r"^quadrature = 'symmetric' .* elements=tet"),
])
def test_a_growth_that_vanishes_or_a_rule_for_tetrahedra_on_hexahedra_is_refused(setting,
                                                                                 message):
    """theta = 1 + a X1 at t = 1 must stay positive over the cube, X1 in [0, side]."""
    with pytest.raises(ParameterError, match=message):
        CubeScene(**setting)
    assert CubeScene(a=-0.99).a == -0.99


def test_the_quarter_case_holds_its_mirror_planes_and_reports_for_the_whole_cube():
    """Normal displacement held on the planes X2, X3 = side / 2 (the quarter's back and top);
    the full cube has none; the profile runs along X1 through the centre."""
    quarter = CubeScene(model="quarter", maxh=0.5, order=1, g_order=2).build()
    full = CubeScene(maxh=0.5, order=1, g_order=2).build()
    assert (quarter.symmetry, quarter.mirror) == ({"back": "y", "top": "z"}, 4)
    assert (full.symmetry, full.mirror) == ({}, 1)
    assert full.line == ((0.0, 0.5, 0.5), (1.0, 0.5, 0.5), "X1")
    assert set(full.planes) == {"n1", "n2", "n3"}
    assert set(full.components) == {"S11", "S22", "S33"}
