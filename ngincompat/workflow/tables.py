"""The one writer of summary tables: markdown for reading, CSV for tools, JSON with provenance.

A table is a list of rows (dicts) and an ordered list of columns; every column can carry a
unit, shown in the header as ``name [unit]`` in markdown and CSV. Floats are printed with
four significant digits in markdown and in full in CSV and JSON.
"""

from __future__ import annotations

import csv
import io as _io
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ngincompat.atomic import atomic_path
from ngincompat.workflow import io


def columns_of(rows: Iterable[Mapping[str, Any]], first: Iterable[str] = ()) -> list[str]:
    """Every key of ``rows`` in order of first appearance, ``first`` leading."""
    keys = list(first)
    for row in rows:
        keys += [k for k in row if k not in keys]
    return keys


def header(column: str, units: dict | None) -> str:
    """``column [unit]`` when the column has a unit."""
    unit = (units or {}).get(column)
    return f"{column} [{unit}]" if unit else column


def cell(value: object, digits: int = 4) -> str:
    """A markdown cell: floats with ``digits`` significant digits, None as empty."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def markdown(rows: Sequence[Mapping[str, Any]], columns: Sequence[str] | None = None,
             units: dict | None = None, digits: int = 4) -> str:
    """The rows as a markdown table."""
    columns = columns or columns_of(rows)
    lines = ["| " + " | ".join(header(c, units) for c in columns) + " |",
             "|" + "---|" * len(columns)]
    for row in rows:
        lines.append("| " + " | ".join(cell(row.get(c), digits) for c in columns) + " |")
    return "\n".join(lines)


def csv_text(rows: Sequence[Mapping[str, Any]], columns: Sequence[str] | None = None,
             units: dict | None = None) -> str:
    """The rows as CSV (header with units)."""
    columns = columns or columns_of(rows)
    buffer = _io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([header(c, units) for c in columns])
    for row in rows:
        writer.writerow(["" if row.get(c) is None else row.get(c) for c in columns])
    return buffer.getvalue()


def write(out: str | os.PathLike, name: str, rows: Sequence[Mapping[str, Any]],
          columns: Sequence[str] | None = None, units: dict | None = None,
          **record: Any) -> list[str]:
    """Write ``name.md``, ``name.csv`` and ``name.json`` into ``out`` atomically.

    ``record`` goes into the JSON beside the rows, columns, units and provenance (e.g. the
    files a summary lists). Returns the names of the files written.
    """
    out = Path(out)
    columns = columns or columns_of(rows)
    write_markdown(out / f"{name}.md", markdown(rows, columns, units))
    with atomic_path(out / f"{name}.csv") as tmp:
        tmp.write_text(csv_text(rows, columns, units))
    io.write_json(out / f"{name}.json", {"columns": columns, "units": units or {},
                                         "rows": rows, **record, **io.provenance()})
    return [f"{name}.md", f"{name}.csv", f"{name}.json"]


def write_markdown(path: str | os.PathLike, text: str) -> Path:
    """Write markdown ``text`` (a table a study formats itself) to ``path`` atomically, for
    the documentation pages that include it."""
    with atomic_path(Path(path)) as tmp:
        tmp.write_text(text + "\n")
    return Path(path)


def write_made_by(out: str | os.PathLike, command: str, seconds: float, cpu_seconds: float,
                  loads: Sequence[float]) -> Path:
    """Write ``made_by.md`` into ``out``: one paragraph saying which command wrote the files
    of the folder, when, from which commit and versions, in how much wall and CPU time, and
    at which load of the machine (``loads``: the 1-minute load averages at the start and at
    the end), so that a page including the folder's tables names what made them."""
    record = io.run_record()
    git = record.get("git")
    commit = (f"commit {git['commit'][:10]}{' with local changes' if git['dirty'] else ''}"
              if git else "not from a git checkout")
    versions = io.versions()
    text = (f"Made by `{command}` on {record['date'][:16].replace('T', ' ')} UTC "
            f"({commit}; ngincompat {versions['ngincompat']}, NGSolve {versions['ngsolve']}), "
            f"in {seconds:.0f} s of wall time and {cpu_seconds:.0f} s of CPU time (user and "
            f"system, with the processes it started), NGSolve on {record['threads']} "
            f"thread(s), at a load average of {loads[0]:.1f} at the start and "
            f"{loads[1]:.1f} at the end on {os.cpu_count()} cores.")
    return write_markdown(Path(out) / "made_by.md", text)
