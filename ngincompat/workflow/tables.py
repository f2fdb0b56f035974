"""The one writer of summary tables: markdown for reading, CSV for tools, JSON with provenance.

A table is a list of rows (dicts) and an ordered list of columns; every column can carry a
unit, shown in the header as ``name [unit]`` in markdown and CSV. Floats are printed with
four significant digits in markdown and in full in CSV and JSON.
"""

from __future__ import annotations

import csv
import io as _io
from pathlib import Path

from ngincompat.atomic import atomic_path
from ngincompat.workflow import io


def columns_of(rows, first=()) -> list[str]:
    """Every key of ``rows`` in order of first appearance, ``first`` leading."""
    keys = list(first)
    for row in rows:
        keys += [k for k in row if k not in keys]
    return keys


def header(column: str, units: dict | None) -> str:
    """``column [unit]`` when the column has a unit."""
    unit = (units or {}).get(column)
    return f"{column} [{unit}]" if unit else column


def cell(value, digits: int = 4) -> str:
    """A markdown cell: floats with ``digits`` significant digits, None as empty."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def markdown(rows, columns=None, units=None, digits: int = 4) -> str:
    """The rows as a markdown table."""
    columns = columns or columns_of(rows)
    lines = ["| " + " | ".join(header(c, units) for c in columns) + " |",
             "|" + "---|" * len(columns)]
    for row in rows:
        lines.append("| " + " | ".join(cell(row.get(c), digits) for c in columns) + " |")
    return "\n".join(lines)


def csv_text(rows, columns=None, units=None) -> str:
    """The rows as CSV (header with units)."""
    columns = columns or columns_of(rows)
    buffer = _io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([header(c, units) for c in columns])
    for row in rows:
        writer.writerow(["" if row.get(c) is None else row.get(c) for c in columns])
    return buffer.getvalue()


def write(out, name: str, rows, columns=None, units=None, **record) -> list[str]:
    """Write ``name.md``, ``name.csv`` and ``name.json`` into ``out`` atomically.

    ``record`` goes into the JSON beside the rows, columns, units and provenance (e.g. the
    files a summary lists). Returns the names of the files written.
    """
    out = Path(out)
    columns = columns or columns_of(rows)
    with atomic_path(out / f"{name}.md") as tmp:
        tmp.write_text(markdown(rows, columns, units) + "\n")
    with atomic_path(out / f"{name}.csv") as tmp:
        tmp.write_text(csv_text(rows, columns, units))
    io.write_json(out / f"{name}.json", {"columns": columns, "units": units or {},
                                         "rows": rows, **record, **io.provenance()})
    return [f"{name}.md", f"{name}.csv", f"{name}.json"]
