"""The skin-expansion scene (section 3.6), on coarse meshes."""

import json
import math

import numpy as np
import pytest

from ngincompat.errors import ConvergenceError
from ngincompat.scenes import SkinExpansionScene
from ngincompat.solver import NewtonSolver

#: The circle 7 cm across that these checks were set up on (base 38.5 cm^2, not the default).
COARSE = dict(maxh=2.5, order=2, growth_order=2, g_order=3, inflation_steps=5,
              outputs="none", footprint_area=math.pi * 3.5**2)


@pytest.fixture(scope="module")
def expanded():
    return SkinExpansionScene(footprint="circle", hold_days=2.0, **COARSE).run()


def test_inflation_meets_the_target_volume(expanded):
    results = expanded
    m = results.metrics
    assert m["volume_error_rel"] < 1e-3
    assert m["pressure_inflated"] > 0
    assert results.solver["inflation"].converged


def test_skin_grows_where_it_is_stretched_and_keeps_residual_stress(expanded):
    results = expanded
    m = results.metrics
    assert m["theta_max"] > 1.05 and m["theta_mean_footprint"] > 1.0
    assert m["burgers_max"] > 10 * m["burgers_apex"]
    assert m["max_principal_stress_released"] > 0
    assert m["strain_energy_released"] < m["strain_energy_clamped"]
    line = results.profile("line")
    theta = np.asarray(line["theta"])
    assert theta[len(theta) // 2] > theta[0] + 0.01  # growth over the expander, not at the edge


@pytest.mark.slow
@pytest.mark.parametrize("footprint", ["rectangle", "square", "crescent"])
def test_every_expander_reaches_its_volume(footprint):
    results = SkinExpansionScene(footprint=footprint, hold_days=0.0, **COARSE).run()
    assert results.metrics["volume_error_rel"] < 1e-3


def test_interrupted_hold_keeps_its_state_and_resumes(tmp_path, monkeypatch):
    """A step that fails during the hold ends the run with the last converged state on disk;
    running again with resume=true continues from it to the end of the hold."""
    original = NewtonSolver.minimise
    calls = {"hold": 0}

    def failing(self, record):
        if getattr(self.problem, "dt", None) is not None and self.problem.dt.Get() > 0:
            calls["hold"] += 1
            if calls["hold"] > 1:
                record.reason = "simulated failure"
                return False
        return original(self, record)

    monkeypatch.setattr(NewtonSolver, "minimise", failing)
    scene = SkinExpansionScene(footprint="circle", hold_days=2.0, **COARSE)
    with pytest.raises(ConvergenceError, match="simulated failure") as failed:
        scene.run(tmp_path)
    assert failed.value.results.status == "not converged"
    saved = np.load(tmp_path / "checkpoint.npz")
    assert float(saved["t"]) == pytest.approx(1.0)
    written = json.loads((tmp_path / "results.json").read_text())
    assert "resume=true" in written["error"] and written["status"] == "not converged"
    monkeypatch.setattr(NewtonSolver, "minimise", original)
    resumed = SkinExpansionScene(footprint="circle", hold_days=2.0, resume=True,
                                 **COARSE).run(tmp_path)
    hold = resumed.solver["hold"]
    assert hold.converged and hold.t_reached == pytest.approx(2.0)
    assert "inflation" not in resumed.solver
    assert hold.steps[0].t == pytest.approx(2.0)
