"""ngincompat.studies.folding_costs: ``ngincompat bench folding``, its four tables."""

import json

import pytest

from ngincompat.errors import ParameterError
from ngincompat.fem.work import KINDS
from ngincompat.studies import folding_costs

COST = {"wall_s": 10.0, "cpu_s": 9.5, "peak_mb": 300, "load": 0.5}


def _record(status="done"):
    """A results.json of two stages: 5 s and 3 s, of which the kinds of work took 4 and 2."""
    work = dict.fromkeys(KINDS, 0.0)
    first, second = dict(work), dict(work)
    first["assembly"], first["factorisation"] = 3.0, 1.0
    second["assembly"] = 2.0
    step = {"converged": True}
    return {"status": status, "metrics": {"t_reached": 40.0, "sulci": 2,
                                          "burgers_interface_mean": 3.5},
            "mesh": {"ndof": 1234},
            "versions": {"ngincompat": "1.2"},
            "provenance": {"git": {"commit": "0123456789abcdef"}},
            "timings": {"growth": 5.0, "release": 3.0, "mesh": 0.5},
            "solver": {
                "growth": {"newton_iterations": 7, "tangent_assemblies": 7, "work": first,
                           "steps": [step, {"converged": False}, step]},
                "release": {"newton_iterations": 2, "tangent_assemblies": 3, "work": second,
                            "steps": [step]}}}


def test_a_runs_rows_add_up_its_stages_and_work():
    field, work, stages, metrics = folding_costs.rows_of("curved", "preview", 1, _record(),
                                                         COST)
    assert field == {"axons": "curved", "version": "this", "preset": "preview", "threads": 1,
                     "status": "done", **COST, "program": "1.2 0123456789",
                     "t_reached": 40.0, "ndof": 1234, "newton": 9, "failed": 1}
    assert work["assembly"] == 5.0 and work["factorisation"] == 1.0
    # the stages took 8 s, the kinds of work 6 of them; the run 10 s in all
    assert work["other in the stages"] == pytest.approx(2.0)
    assert work["outside the stages"] == pytest.approx(2.0)
    assert work["wall_s"] == 10.0
    assert [(s["stage"], s["wall_s"], s["newton"], s["failed"], s["tangents"])
            for s in stages] == [("growth", 5.0, 7, 1, 7), ("release", 3.0, 2, 0, 3)]
    assert metrics["burgers_interface_mean"] == 3.5 and metrics["sulci"] == 2
    assert metrics["max_principal_stress_released"] is None     # not measured: empty
    assert set(metrics) == set(folding_costs.METRICS_COLUMNS)


def test_a_run_that_wrote_nothing_has_its_fields_row_only():
    cost = {**COST, "status": "failed: boom"}
    field, work, stages, metrics = folding_costs.rows_of("straight", "default", 2, None, cost,
                                                         "baseline")
    assert (work, stages, metrics) == (None, [], None)
    assert field["status"] == "failed: boom" and field["version"] == "baseline"
    # a run that was stopped but wrote its results keeps the cost's status
    field, *_ = folding_costs.rows_of("curved", "default", 1, _record("interrupted"),
                                      {**COST, "status": "stopped after 60 s"})
    assert field["status"] == "stopped after 60 s"


def test_an_unknown_axon_field_is_refused_before_anything_runs(monkeypatch):
    monkeypatch.setattr(folding_costs, "measure", lambda *a, **k: pytest.fail("ran"))
    with pytest.raises(ParameterError, match="unknown axon field 'sideways': allowed curved"):
        folding_costs.table(axons=("curved", "sideways"))


def test_each_field_runs_on_this_version_then_on_the_baseline(monkeypatch):
    calls = []

    def measure(scene, preset, timeout, threads, settings, source):
        calls.append((settings["axons"], source, settings.get("maxh")))
        return _record(), dict(COST)

    monkeypatch.setattr(folding_costs, "measure", measure)
    fields, work, stages, metrics = folding_costs.table(
        axons=("curved", "straight"), settings={"maxh": 0.5}, baseline="/old")
    assert calls == [("curved", None, 0.5), ("curved", "/old", 0.5),
                     ("straight", None, 0.5), ("straight", "/old", 0.5)]
    assert [(r["axons"], r["version"]) for r in fields] == [
        ("curved", "this"), ("curved", "baseline"), ("straight", "this"),
        ("straight", "baseline")]
    assert len(work) == len(metrics) == 4 and len(stages) == 8


def test_a_baseline_that_is_no_checkout_is_refused(tmp_path):
    with pytest.raises(ParameterError, match="^baseline = .* allowed a checkout of ngincompat"):
        folding_costs.main(baseline=str(tmp_path))


def test_main_writes_the_four_tables(monkeypatch, tmp_path):
    monkeypatch.setattr(folding_costs, "measure", lambda *a, **k: (_record(), dict(COST)))
    lines = folding_costs.main(axons=("concentric",), out=tmp_path)
    assert lines[-1].startswith(f"tables written to {tmp_path}")
    for name, columns in (("fields", folding_costs.FIELD_COLUMNS),
                          ("work", folding_costs.WORK_COLUMNS),
                          ("stages", folding_costs.STAGE_COLUMNS),
                          ("metrics", folding_costs.METRICS_COLUMNS)):
        table = json.loads((tmp_path / f"{name}.json").read_text())
        assert table["columns"] == list(columns), name
        assert (tmp_path / f"{name}.md").is_file() and (tmp_path / f"{name}.csv").is_file()
    assert json.loads((tmp_path / "stages.json").read_text())["units"]["wall_s"] == "s"
