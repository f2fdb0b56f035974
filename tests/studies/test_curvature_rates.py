"""ngincompat.studies.curvature_rates: the discrete curvature's rates against the published."""

import json

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat.errors import ParameterError
from ngincompat.studies import curvature_rates as cr


def _rows(body="hemisphere", orders=(1, 2), levels=3):
    """Errors that fall by 2^(k+1) (pairing), 2^k (lift) and 2^(k-1) (element-wise) per
    refinement, listed finest first."""
    rows = []
    for k in orders:
        for level in reversed(range(levels)):
            rows.append({"body": body, "k": k, "level": level, "ne": 8 ** level,
                         "pairing": 2.0 ** (-(k + 1) * level),
                         "lift": 0.5 * 2.0 ** (-k * level),
                         "elementwise": 2.0 ** (-(k - 1) * level), "seconds": 0.1 * 8 ** level})
    return rows


def test_the_rates_are_log2_of_the_ratio_of_successive_errors():
    rows = _rows() + _rows("disc", levels=2)
    assert cr.rates(rows, "pairing") == {("hemisphere", 1): [2.0, 2.0],
                                         ("hemisphere", 2): [3.0, 3.0],
                                         ("disc", 1): [2.0], ("disc", 2): [3.0]}
    assert cr.rates(rows, "elementwise")["hemisphere", 1] == [0.0, 0.0]
    # one level: no rate
    assert cr.rates(_rows(levels=1), "lift") == {("hemisphere", 1): [], ("hemisphere", 2): []}
    # a body run at fewer degrees than another has rows for its own degrees only
    mixed = _rows(orders=(1, 2, 3)) + _rows("disc", orders=(1,))
    assert set(cr.rates(mixed, "lift")) == {("hemisphere", 1), ("hemisphere", 2),
                                             ("hemisphere", 3), ("disc", 1)}


def test_the_summary_sets_the_measured_rates_beside_the_published():
    summary = {(r["measure"], r["k"]): r for r in cr.rate_summary(_rows())}
    assert summary["pairing", 2]["rates"] == "3.00, 3.00"
    assert summary["pairing", 2]["published"] == 3                  # k + 1
    assert summary["elementwise", 2]["published"] == 1               # k - 1
    assert summary["lift", 1]["published"] == "-"                    # none published
    assert summary["lift", 1]["rates"] == "1.00, 1.00"
    assert len(summary) == 3 * 2


def test_the_test_fields_vanish_on_each_bodys_boundary():
    """The pairing is bounded by the H^-2 error only for a test field vanishing on the
    boundary: at the boundary vertices it is zero to round-off, inside it is not."""
    bodies = cr.bodies()
    assert set(bodies) == {"hemisphere", "disc"}
    for name, (ngmesh, _, bubble) in bodies.items():
        mesh = ngs.Mesh(ngmesh)
        boundary = {v.nr for el in mesh.Elements(ngs.BND) for v in el.vertices}
        on = [bubble(mesh(*mesh.vertices[k].point)) for k in boundary]
        assert max(np.abs(on)) < 1e-12, name
        inside = ngs.Integrate(bubble * bubble, mesh)
        assert inside > 1e-4, name


def test_an_unknown_body_is_refused_before_anything_runs(monkeypatch):
    monkeypatch.setattr(cr, "rate_table", lambda **grid: pytest.fail("ran"))
    with pytest.raises(ParameterError, match="^--bodies 'sphere': allowed hemisphere, disc"):
        cr.main(names=["sphere"])


def test_main_writes_the_tables_and_a_plot_per_body(monkeypatch, tmp_path):
    grids = []

    def table(**grid):
        grids.append(grid)
        return _rows() + _rows("disc", orders=(1,))

    monkeypatch.setattr(cr, "rate_table", table)
    lines = cr.main(out=tmp_path, quick=True, orders=[2])
    assert grids == [{"names": ("hemisphere",), "orders": (2,), "levels": 1}]
    assert lines[-1] == f"plots and tables written to {tmp_path}"
    rows = json.loads((tmp_path / "curvature_rates.json").read_text())
    assert rows["columns"] == list(cr.COLUMNS) and len(rows["rows"]) == 9
    summary = json.loads((tmp_path / "curvature_rate_summary.json").read_text())["rows"]
    assert {(r["body"], r["measure"], r["k"]) for r in summary} >= {("disc", "lift", 1)}
    for body in ("hemisphere", "disc"):
        assert (tmp_path / f"curvature_{body}.png").stat().st_size > 0
    assert "| body | k | level |" in lines[0] and any("published" in line for line in lines)


def test_without_refinement_there_is_no_table_of_rates(monkeypatch):
    monkeypatch.setattr(cr, "rate_table", lambda **grid: _rows(levels=1))
    lines = cr.main()
    assert len(lines) == 1 and "published" not in lines[0]
