"""ngincompat.studies.validation: ``ngincompat bench validation``, its four tables."""

import json
from types import SimpleNamespace

import pytest

from ngincompat.fem.transport import logistic_integral
from ngincompat.mechanics.atrophy import AtrophyLaw
from ngincompat.scenes import AtrophyScene, FoldingScene
from ngincompat.studies import validation
from ngincompat.studies.bench import CUBE_ENERGY


def _exact(scene):
    """The closed form of the uniform atrophy's volume loss, 1 - theta(int_0^t c ds)."""
    return 1 - AtrophyLaw(scene.rate_gray, scene.theta_min).theta(
        logistic_integral(scene.t_end, scene.c0, scene.alpha))


def test_the_closed_forms_are_sections_3_1_to_3_4_with_the_cubes_energy_error(monkeypatch):
    asked = {}

    def run_all(out, progress, resolution, only):
        asked.update(out=out, resolution=resolution, only=only)
        return [{"case": "cube", "strain_energy": CUBE_ENERGY * 1.01},
                {"case": "cylinder", "strain_energy": 1.0}]

    monkeypatch.setattr(validation.paper, "run_all", run_all)
    rows = validation.closed_forms("preview")
    assert asked == {"out": None, "resolution": "preview", "only": ("3.1", "3.2", "3.3", "3.4")}
    assert rows[0]["energy_error"] == pytest.approx(0.01)
    assert "energy_error" not in rows[1]


def test_the_logistic_rows_give_the_observed_order_between_successive_steps(monkeypatch):
    """A volume loss off its closed form by 0.1 dt (relative): error 0.1 dt, order 1."""
    made = []

    class Uniform(AtrophyScene):
        def run(self):
            made.append(self)
            loss = _exact(self) * (1 + 0.1 * self.dt)
            return SimpleNamespace(metrics={"volume_loss": loss, "burgers_max": 0.0,
                                            "G_norm_L2": 0.0, "Je_deviation_max": 0.0})

    monkeypatch.setattr(validation, "AtrophyScene", Uniform)
    rows = validation.logistic_table((2.0, 1.0, 0.5), maxh=3.0)
    assert [r["error"] for r in rows] == pytest.approx([0.2, 0.1, 0.05])
    assert "order" not in rows[0]
    assert [r["order"] for r in rows[1:]] == pytest.approx([1.0, 1.0])
    scene = made[0]
    assert (scene.maxh, scene.seed, scene.rate_gray, scene.rate_white) == (
        3.0, "uniform", 0.03, 0.03)
    assert rows[0]["closed_form"] == pytest.approx(_exact(scene))


def test_the_onset_rows_set_each_mesh_against_the_stroh_analysis(monkeypatch):
    """The oracle is the same bilayer's; a mesh whose run found no onset has no error."""
    made = []

    class Bilayer(FoldingScene):
        def run(self):
            made.append(self)
            metrics = ({} if self.cortex_maxh > 0.04 else
                       {"onset_growth": 1.25 * 1.002, "onset_wavelength": self.length / 3})
            return SimpleNamespace(metrics=metrics, mesh=SimpleNamespace(ndof=100))

    monkeypatch.setattr(validation, "FoldingScene", Bilayer)
    monkeypatch.setattr(validation, "onset", lambda bilayer, length: SimpleNamespace(
        growth=1.25, wavelength=length / 3, mode=6))
    rows = validation.onset_table(((0.05, 0.3), (0.025, 0.1)), cortex_thickness=0.1)
    assert "growth_error" not in rows[0] and rows[0]["stroh_growth"] == 1.25
    assert rows[1]["growth_error"] == pytest.approx(0.002)
    assert rows[1]["mode"] == 6 == rows[1]["stroh_mode"]
    assert [(s.cortex_maxh, s.maxh, s.cortex_thickness, s.buckle, s.axons) for s in made] == [
        (0.05, 0.3, 0.1, False, "none"), (0.025, 0.1, 0.1, False, "none")]


def test_main_writes_the_four_tables_and_the_two_convergence_plots(monkeypatch, tmp_path):
    monkeypatch.setattr(validation, "closed_forms", lambda resolution, progress: [
        {"case": "cube", "ndof": 10, "energy_error": 1e-3}])
    monkeypatch.setattr(validation, "onset_table", lambda meshes, progress, **bilayer: [
        {"cortex_maxh": m[0], "maxh": m[1], "ndof": 100 * (k + 1), "growth_error": 0.0}
        for k, m in enumerate(meshes)])
    monkeypatch.setattr(validation, "logistic_table", lambda dts, progress: [
        {"dt": dt, "error": 0.1 * dt} for dt in dts])
    monkeypatch.setattr(validation, "balance_table", lambda maxhs, progress: [
        {"maxh": h} for h in maxhs])
    lines = validation.main(out=tmp_path, quick=True)
    assert lines[-1] == f"tables and plots written to {tmp_path}"
    for name in ("closed_forms", "onset", "atrophy_logistic", "atrophy_balance"):
        assert f"{name}:" in lines
        record = json.loads((tmp_path / f"{name}.json").read_text())
        assert record["quick"] is True
    assert len(json.loads((tmp_path / "onset.json").read_text())["rows"]) == len(
        validation.QUICK["onset"])
    # an error of zero is drawn at 1e-16 on the logarithmic axis, not left out
    assert (tmp_path / "onset.png").stat().st_size > 0
    assert (tmp_path / "atrophy_logistic.png").stat().st_size > 0


@pytest.mark.slow
def test_uniform_atrophy_is_compatible_and_converges_at_first_order_in_the_time_step():
    """Equal gray and white rates under a uniform seed: G and b vanish to round-off, Je = 1,
    and backward Euler's error in the volume loss falls with the step (order near 1)."""
    rows = validation.logistic_table((2.0, 1.0), maxh=2.0)
    for row in rows:
        assert row["burgers_max"] < 1e-10 and row["Je_deviation_max"] < 1e-12
    assert rows[1]["error"] < rows[0]["error"] < 0.5
    assert 0.6 < rows[1]["order"] < 1.4
