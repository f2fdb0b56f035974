"""ngincompat.studies.mpi_costs: the cost per rank of a distributed run and its model."""

import math

import pytest

from ngincompat.errors import ParameterError
from ngincompat.studies import costs, mpi_costs

#: A model to generate rows from and recover.
MODEL = {"base_mib": 200.0, "m": 0.004, "c": 3e-4, "alpha": 1.3, "t": 2e-3, "beta": 1.1}


def _rows(model, sizes=(5e4, 1.5e5, 4e5), ranks=(2, 3, 5)):
    """Rows as :func:`mpi_costs.row` makes them, their numbers from ``model``; the times of
    the runs with several workers off the model (shared cores: not fitted)."""
    rows = []
    for n in sizes:
        for r in ranks:
            p = mpi_costs.predict(model, n, r - 1)
            rows.append({"ndof": n, "ranks": r, "status": "done",
                         "worker_mib": p["worker_mib"], "rank0_mib": p["rank0_mib"],
                         "equilibrium_s": p["equilibrium_s"] * (1 if r == 2 else 3)})
    return rows


def test_the_fit_recovers_the_model_the_rows_were_made_from():
    model = mpi_costs.fit(_rows(MODEL) + [{"ndof": 1e6, "ranks": 2, "status": "failed"}],
                          MODEL["base_mib"])
    for key, value in MODEL.items():
        assert model[key] == pytest.approx(value, rel=1e-9), key


def test_the_model_has_a_worker_lighter_with_more_workers_and_rank_0_not():
    few, many = (mpi_costs.predict(MODEL, 3e6, w) for w in (8, 64))
    assert many["worker_mib"] < few["worker_mib"]
    assert many["rank0_mib"] == few["rank0_mib"] > MODEL["base_mib"]
    assert many["worker_mib"] - MODEL["base_mib"] == pytest.approx(
        (few["worker_mib"] - MODEL["base_mib"]) / 8)


def test_what_the_rows_do_not_carry_the_model_leaves_out():
    """One size: no exponent for rank 0 or the time; no finished row: an error."""
    model = mpi_costs.fit(_rows(MODEL, sizes=(1e5,)), MODEL["base_mib"])
    assert model["m"] == pytest.approx(MODEL["m"])
    assert model["alpha"] is model["c"] is model["t"] is model["beta"] is None
    assert mpi_costs.predict(model, 1e6, 4)["rank0_mib"] is None
    with pytest.raises(ParameterError, match="no finished run"):
        mpi_costs.fit([{"ndof": 1e5, "ranks": 2, "status": "failed"}], 200.0)


@pytest.mark.parametrize("grid", [{"ranks": [1]}, {"maxh": [0.0]}])
def test_a_grid_without_a_worker_or_with_no_mesh_size_is_refused(grid):
    with pytest.raises(ParameterError, match=next(iter(grid))):
        mpi_costs.table(**grid)


def test_a_run_on_two_ranks_records_the_peak_memory_of_each(monkeypatch):
    """A small brain on 2 ranks (10 days, 2 steps): results.json carries rank 0's and the
    worker's peak memory, each above the footprint of a rank before its mesh, and the row
    reads them; without a launcher ranks > 1 is an error naming the extra."""
    if mpi_costs.costs.parallel.launcher() is None:
        pytest.skip("no mpiexec (pip install '.[mpi]')")
    settings = {**mpi_costs.SETTINGS, "maxh": 4.0, "t_end": 2, "dt": 1}
    record, cost = costs.measure("atrophy", "default", 600, settings=settings, ranks=2)
    assert record is not None and record["status"] == "done", cost
    row = mpi_costs.row(4.0, 2, record, cost)
    base = mpi_costs.footprint()
    assert len(record["provenance"]["peak_mib"]) == 2
    assert row["rank0_mib"] > base and row["worker_mib"] > base
    assert row["ndof"] == record["mesh"]["ndof"] and math.isfinite(row["equilibrium_s"])
    assert row["cg_iterations"] != "direct"
    monkeypatch.setattr(costs.parallel, "launcher", lambda: None)
    with pytest.raises(ParameterError, match="mpi"):
        costs.measure("atrophy", "default", 600, settings=settings, ranks=2)


def test_the_command_lines_help_gives_the_studys_own_defaults(capsys):
    """The help text, written out so that ``--help`` imports no NGSolve, states MAXH, RANKS
    and TIMEOUT as the module has them."""
    from ngincompat.cli import main
    assert main(["bench", "mpi", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert f"(default: {' '.join(map(str, mpi_costs.MAXH))})" in text
    assert f"(default: {' '.join(map(str, mpi_costs.RANKS))})" in text
    assert f"(default {mpi_costs.TIMEOUT:g})" in text
