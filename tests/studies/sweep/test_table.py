"""ngincompat.studies.sweep.table: written with units, read back, drawn with units on axes."""

# The table is made from outcomes directly (no case runs): the cube's order x nu, and the
# hemisphere's metrics for their units.

import pytest

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.studies.sweep import parse_sweep, read_table, sweep_figure
from ngincompat.studies.sweep.table import make_table, write_table

SWEEP = parse_sweep({"scene": "cube", "metrics": ["strain_energy", "max_principal_stress"],
                     "fixed": {"maxh": 1.0}, "vary": {"order": [1, 2], "a": [0.1, 0.2, 0.3]}})


def _outcome(case):
    if case.index == 5:
        return {"varied": case.varied, "status": "failed", "metrics": {}, "seconds": 0.0,
                "error": "ParameterError: a = 0.3 is out of range"}
    energy = case.varied["a"] ** 2 / case.varied["order"]
    return {"varied": case.varied, "status": "done", "seconds": 0.5, "error": None,
            "metrics": {"strain_energy": energy, "max_principal_stress": 2 * energy}}


@pytest.fixture()
def folder(tmp_path):
    table = make_table(SWEEP, {case.index: _outcome(case) for case in SWEEP.cases()})
    files = write_table(tmp_path, table, SWEEP.record())
    assert files[:3] == ["sweep.md", "sweep.csv", "sweep.json"]
    return tmp_path


def test_the_table_carries_units_and_reads_back(folder):
    table = read_table(folder)
    assert table.scene == "cube" and table.varied == ["order", "a"]
    assert table.columns == ["case", "status", "warnings", "order", "a", "strain_energy",
                             "max_principal_stress", "seconds", "error"]
    assert table.units == {"a": "1/mm", "strain_energy": "N mm", "max_principal_stress": "MPa",
                           "seconds": "s"}
    assert [r["status"] for r in table.rows] == ["done"] * 5 + ["failed"]
    assert table.rows[5]["strain_energy"] is None
    assert (folder / "sweep.md").read_text().startswith(
        "| case | status | warnings | order | a [1/mm] | strain_energy [N mm] |")
    with pytest.raises(ParameterError, match="no sweep.json"):
        read_table(folder / "nothing")


def test_parquet_table_matches_the_json(folder):
    pq = pytest.importorskip("pyarrow.parquet")
    parquet = pq.read_table(folder / "sweep.parquet")
    rows = read_table(folder).rows
    assert [r["status"] for r in parquet.to_pylist()] == [r["status"] for r in rows]
    assert [r["strain_energy"] for r in parquet.to_pylist()] == \
        [r["strain_energy"] for r in rows]
    assert parquet.schema.metadata[b"strain_energy"] == b"N mm"


def test_the_sweep_figure_has_units_on_its_axes(folder):
    fig = sweep_figure(read_table(folder), "strain_energy", "a", hue="order", logy=True)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "a [1/mm]" and ax.get_ylabel() == "strain_energy [N mm]"
    assert ax.get_yscale() == "log" and ax.get_title() == "cube: strain_energy against a"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["order = 1", "order = 2"]
    # the failed case is not drawn: order 2 has two points
    assert [len(line.get_xdata()) for line in ax.get_lines()] == [3, 2]
    # a parameter without a unit is labelled by its name
    assert sweep_figure(read_table(folder), "max_principal_stress", "order",
                        where={"a": "0.1"}).axes[0].get_xlabel() == "order"


def test_sweep_plot_writes_a_png(folder, tmp_path, capsys):
    png = tmp_path / "energy.png"
    code = main(["sweep", "plot", str(folder), "--metric", "strain_energy", "--x", "a",
                 "--hue", "order", "--logy", "--out", str(png)])
    assert code == 0
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    # without --hue the two orders share every a: refused, naming what varies
    code = main(["sweep", "plot", str(folder), "--metric", "strain_energy", "--x", "a",
                 "--out", str(tmp_path / "bad.png")])
    assert code == 2 and "order" in capsys.readouterr().err
    # ... unless --where fixes it
    code = main(["sweep", "plot", str(folder), "--metric", "strain_energy", "--x", "a",
                 "--where", "order=2", "--out", str(tmp_path / "one.png")])
    assert code == 0 and (tmp_path / "one.png").is_file()
    code = main(["sweep", "plot", str(folder), "--metric", "energy", "--x", "a",
                 "--out", str(tmp_path / "bad.png")])
    assert code == 2 and "energy" in capsys.readouterr().err
    code = main(["sweep", "plot", str(folder), "--metric", "strain_energy", "--x", "a",
                 "--where", "order", "--out", str(tmp_path / "bad.png")])
    assert code == 2 and "--where 'order' must have the form KEY=VALUE" in \
        capsys.readouterr().err
    assert not (tmp_path / "bad.png").exists()
