"""The numerical stress-test matrix: every cell converges or fails cleanly, never otherwise."""

import json
import math

import pytest

from ngincompat.studies import stability
from ngincompat.studies.stability import Cell


@pytest.fixture(scope="module")
def quick_rows():
    """The quick corner, on one NGSolve thread (a few seconds)."""
    return stability.run_matrix(stability.matrix(quick=True), threads=1)


def _by_label(rows):
    return {r["label"]: r for r in rows}


def test_quick_corner_cells_converge_or_fail_cleanly(quick_rows):
    assert len(quick_rows) >= 8
    assert [r for r in quick_rows if r["status"] == stability.UNEXPECTED] == []
    for r in quick_rows:
        assert r["status"] in ("converged", "error"), r
        if r["status"] == "error":
            assert r["message"] and "\n" not in r["message"], r
            assert r["message"].split(":")[0] in ("ParameterError", "ConvergenceError"), r
        else:
            assert r["message"] == ""
            assert math.isfinite(r["strain_energy"]) and r["strain_energy"] >= 0, r
            assert r["t_reached"] == pytest.approx(1.0)
            assert 1 <= r["steps_converged"] <= r["steps_attempted"]
            assert math.isfinite(r["seconds"])


def test_hard_cells_converge(quick_rows):
    rows = _by_label(quick_rows)
    iso = rows["isotropic, theta -> 3"]
    assert iso["status"] == "converged"
    assert iso["steps_attempted"] == 1        # the full growth to theta = 3 in one step
    assert rows["nu = 0.499"]["status"] == "converged"
    goh = rows["k2 = 50, shrink to 0.5, fibers e1"]
    assert goh["status"] == "converged"
    assert 0.2 < goh["fiber_compressed"] < 0.9   # the Macaulay bracket is active in the body
    assert goh["fiber_strain_min"] < 0 < goh["fiber_strain_max"]


def test_one_step_and_eight_steps_reach_the_same_state(quick_rows):
    rows = _by_label(quick_rows)
    one, eight = rows["theta -> 3, order 3, steps = 1"], rows["theta -> 3, order 3, steps = 8"]
    assert one["strain_energy"] == pytest.approx(eight["strain_energy"], rel=1e-8)
    assert one["steps_attempted"] == 1 and eight["steps_converged"] >= 8
    assert one["newton"] < eight["newton"]


def test_designed_errors_are_clean(quick_rows):
    rows = _by_label(quick_rows)
    bad_theta = rows["theta <= 0 (rejected before the solve)"]
    assert bad_theta["status"] == "error"
    assert bad_theta["message"].startswith("ParameterError: theta = 0")
    gave_up = rows["max_iter = 1, min_step = 0.25 (must give up)"]
    assert gave_up["status"] == "error"
    assert gave_up["message"].startswith("ConvergenceError:")
    assert gave_up["steps_attempted"] >= 2 and gave_up["steps_converged"] == 0
    assert gave_up["strain_energy"] is None


def test_format_table_has_one_line_per_cell(quick_rows):
    table = stability.format_table(quick_rows).splitlines()
    assert len(table) == len(quick_rows) + 2
    assert table[1] == "|" + "---|" * 10
    rows = [table[0], *table[2:]]
    assert all(line.startswith("| ") and line.endswith(" |") for line in rows)
    assert all(line.count(" | ") == table[0].count(" | ") for line in rows)


def test_unexpected_exceptions_become_rows(monkeypatch):
    """Anything but an ngincompat error is caught, reported as 'unexpected' with its type,
    message and traceback, and never raised."""
    def boom(self):
        raise RuntimeError("Local Heap overflow\nin AssembleLinearization")
    monkeypatch.setattr(Cell, "build", boom)
    row = stability.run_cell(Cell("x", "boom"))
    assert row["status"] == stability.UNEXPECTED
    assert row["message"] == "RuntimeError: Local Heap overflow in AssembleLinearization"
    assert "Traceback" in row["traceback"]


def test_locking_quick():
    """nu = 0.499 on 2 x 2 x 2 hexahedra: order 1 is off by three orders of magnitude, the
    order-2 error is several times that of the compressible nu = 0.3 (volumetric locking),
    and the mixed formulation removes it: its order 2 is closer to its order 3 than the
    displacement order 2 by a factor > 4, in a few Newton iterations. Measured (against the
    mixed order 3): displacement order 2 1.5, order 3 0.11 (nu = 0.3 against its order 3:
    0.35), mixed order 2 0.13; mixed 4 Newton iterations per order against 71 and 140."""
    rows = stability.locking(orders=(1, 2, 3), threads=1)
    assert all(r["status"] == "converged" for r in rows)
    assert all(r["reference"]["status"] == "converged" for r in rows)
    assert rows[0]["mixed"] is None
    assert all(r["mixed"]["status"] == "converged" for r in rows[1:])
    e1, e2, e3 = (r["strain_energy"] for r in rows)
    assert abs(e1 - e3) / e3 > 100
    assert abs(e2 - e3) < 0.01 * abs(e1 - e2)
    assert rows[1]["vs_highest"] > 2 * rows[1]["reference"]["vs_highest"]
    assert rows[1]["mixed"]["vs_highest"] < 0.25 * rows[1]["vs_highest"]
    assert all(r["mixed"]["newton"] <= 6 for r in rows[1:])
    table = stability.locking_table(rows)
    assert "nu = 0.499" in table and len(table.splitlines()) == 5


@pytest.mark.slow
def test_locking_converges_under_p_refinement():
    """Orders 3, 4, 5 at nu = 0.499 (about 6 minutes on one thread, 5.5 of them at order 5 in
    the displacement formulation: 244 Newton iterations). Both formulations converge to the
    same energy. Measured: displacement changes 11.4 % (3 to 4) and 0.69 % (4 to 5); mixed
    and displacement agree at order 5 to 3e-4."""
    rows = stability.locking(orders=(3, 4, 5), reference_nu=None, threads=1)
    e3, e4, e5 = (r["strain_energy"] for r in rows)
    assert abs(e3 - e4) / e4 > 0.05
    assert abs(e4 - e5) / e5 < 0.015
    assert abs(e4 - e5) < 0.2 * abs(e3 - e4)
    m3, m4, m5 = (r["mixed"]["strain_energy"] for r in rows)
    assert abs(m4 - m5) < 0.2 * abs(m3 - m4)
    assert abs(m5 - e5) / m5 < 2e-3


@pytest.mark.slow
def test_orders_7_and_8_fit_the_local_heap():
    """One hexahedron at orders 7 and 8 overflowed NGSolve's 200 MB local heap in the
    linearisation; GrowthMechanics now raises the heap for the order it is built with."""
    for order in (7, 8):
        row = stability.run_cell(Cell("order", f"order {order}", order=order, maxh=1.0))
        assert row["status"] == "converged", row["message"]


def test_main_writes_stability_json(tmp_path, monkeypatch):
    monkeypatch.setattr(stability, "matrix", lambda quick: [
        Cell("order", "order 1, one hex", order=1, maxh=1.0),
        Cell("errors", "theta <= 0", theta="1 - 2*X1*t", maxh=1.0)])
    monkeypatch.setattr(stability, "LOCKING_ORDERS_QUICK", (1, 2))
    lines = stability.main(quick=True, out=str(tmp_path))
    assert "2 cells: 1 converged, 1 error, 0 unexpected" in "\n".join(lines)
    data = json.loads((tmp_path / "stability.json").read_text())
    assert [r["status"] for r in data["rows"]] == ["converged", "error"]
    assert [r["order"] for r in data["locking"]] == [1, 2]
    # the two tables as markdown too, for the validation page
    assert sorted(p.name for p in tmp_path.iterdir()) == ["locking.md", "stability.json",
                                                         "stability.md"]
    matrix = (tmp_path / "stability.md").read_text()
    assert "| order | order 1, one hex | converged |" in matrix
    assert "2 cells: 1 converged, 1 error, 0 unexpected" in matrix
    assert (tmp_path / "locking.md").read_text().startswith("| order | ndof |")
