"""ngincompat.workflow.tables: markdown, CSV and JSON tables with units, written atomically."""

import csv
import io
import json
import os

import pytest

from ngincompat.workflow import tables

ROWS = [{"case": "a", "energy": 1.23456789, "note": None},
        {"energy": 2, "case": "b", "extra": "x"}]
UNITS = {"energy": "N mm"}


def test_columns_are_in_order_of_first_appearance_with_the_given_first():
    assert tables.columns_of(ROWS) == ["case", "energy", "note", "extra"]
    assert tables.columns_of(ROWS, first=("extra", "case")) == ["extra", "case", "energy",
                                                                   "note"]
    assert tables.columns_of([]) == []


def test_a_header_carries_its_unit_and_a_cell_four_digits():
    assert tables.header("energy", UNITS) == "energy [N mm]"
    assert tables.header("case", UNITS) == tables.header("case", None) == "case"
    assert tables.cell(None) == "" and tables.cell(2) == "2" and tables.cell("x") == "x"
    assert tables.cell(1.23456789) == "1.235" and tables.cell(1.23456789, digits=2) == "1.2"
    assert tables.cell(1.5e-20) == "1.5e-20"


def test_markdown_has_a_header_with_units_a_rule_and_one_line_per_row():
    assert tables.markdown(ROWS, ["case", "energy", "note"], UNITS).splitlines() == [
        "| case | energy [N mm] | note |",
        "|---|---|---|",
        "| a | 1.235 |  |",
        "| b | 2 |  |"]
    # without columns: every key
    assert tables.markdown(ROWS).splitlines()[0] == "| case | energy | note | extra |"


def test_csv_keeps_floats_in_full_and_reads_back():
    text = tables.csv_text(ROWS, units=UNITS)
    read = list(csv.reader(io.StringIO(text)))
    assert read == [["case", "energy [N mm]", "note", "extra"],
                    ["a", "1.23456789", "", ""],
                    ["b", "2", "", "x"]]


def test_write_gives_the_three_files_and_the_json_its_record_and_provenance(tmp_path):
    names = tables.write(tmp_path / "new", "summary", ROWS, ["case", "energy"], UNITS,
                         files=["fig.png"])
    assert names == ["summary.md", "summary.csv", "summary.json"]
    folder = tmp_path / "new"                       # made on the way
    assert sorted(p.name for p in folder.iterdir()) == sorted(names)
    assert (folder / "summary.md").read_text() == tables.markdown(
        ROWS, ["case", "energy"], UNITS) + "\n"
    assert (folder / "summary.csv").read_text() == tables.csv_text(
        ROWS, ["case", "energy"], UNITS)
    record = json.loads((folder / "summary.json").read_text())
    assert record["columns"] == ["case", "energy"] and record["units"] == UNITS
    assert record["rows"][0] == {"case": "a", "energy": 1.23456789, "note": None}
    assert record["files"] == ["fig.png"]
    assert {"versions", "argv", "provenance"} <= set(record)


def test_a_table_that_cannot_be_written_leaves_the_previous_json_whole(tmp_path):
    """The JSON of a row that does not serialise fails: the previous file stays under its
    name, and no temporary file is left beside it."""
    tables.write(tmp_path, "t", ROWS)
    before = (tmp_path / "t.json").read_text()
    with pytest.raises(TypeError):
        tables.write(tmp_path, "t", [{"case": object()}])
    assert (tmp_path / "t.json").read_text() == before
    assert sorted(os.listdir(tmp_path)) == ["t.csv", "t.json", "t.md"]


def test_markdown_text_is_written_with_a_final_newline(tmp_path):
    path = tables.write_markdown(tmp_path / "sub" / "table.md", "| a |")
    assert path == tmp_path / "sub" / "table.md" and path.read_text() == "| a |\n"


def test_made_by_names_the_command_commit_versions_times_and_load(tmp_path, monkeypatch):
    monkeypatch.setattr(tables.io, "run_record", lambda: {
        "date": "2026-01-02T03:04:05+00:00", "threads": 2,
        "git": {"commit": "0123456789abcdef", "dirty": True}})
    monkeypatch.setattr(tables.io, "versions", lambda: {"ngincompat": "1.2", "ngsolve": "6.2"})
    path = tables.write_made_by(tmp_path, "ngincompat bench scenes", 12.4, 30.6, (1.25, 0.5))
    assert path == tmp_path / "made_by.md"
    assert path.read_text() == (
        "Made by `ngincompat bench scenes` on 2026-01-02 03:04 UTC (commit 0123456789 with "
        "local changes; ngincompat 1.2, NGSolve 6.2), in 12 s of wall time and 31 s of CPU "
        "time (user and system, with the processes it started), NGSolve on 2 thread(s), at a "
        f"load average of 1.2 at the start and 0.5 at the end on {os.cpu_count()} cores.\n")
    monkeypatch.setattr(tables.io, "run_record", lambda: {
        "date": "2026-01-02T03:04:05+00:00", "threads": 1, "git": None})
    text = tables.write_made_by(tmp_path, "c", 1.0, 1.0, (0.0, 0.0)).read_text()
    assert "(not from a git checkout; ngincompat 1.2" in text
