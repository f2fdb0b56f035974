"""Drivers that run one scene in several variants (``ngincompat expansion``: the skin scene
per expander; ``ngincompat folding``: the folding scene per axon field), each into its own
folder, with one summary table.

Every variant's settings are checked before anything runs (a bad value stops the driver at
once, nothing computed); a variant whose run does not converge is a row with its status and
the metrics of its last converged state, and the others still run.
"""

import os
import time
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ngincompat.errors import ConvergenceError
from ngincompat.progress import SILENT, Progress
from ngincompat.workflow import output, tables
from ngincompat.workflow.results import Results

if TYPE_CHECKING:     # the scenes are the caller's (this module imports none)
    from ngincompat.scenes.base import Scene

#: The columns every summary starts with after the variant's name.
COMMON = ("status", "warnings", "ndof", "seconds")


def run_variants(scenes: "Mapping[str, Scene]", out: str | os.PathLike | None = None,
                 key: str = "variant", metrics: Sequence[str] = (),
                 progress: Progress = SILENT, overwrite: bool = False,
                 label: str = "") -> tuple[list[dict[str, Any]], dict[str, Results]]:
    """Run every scene of ``scenes`` (variant name -> scene), into ``out/<name>`` when ``out``
    is given (prepared as a run folder first).

    Returns the rows (``key``: the name, status, ndof, seconds and the ``metrics``, None
    where a run has no value) and the results by name.
    """
    if out is None:
        return _run_variants(scenes, None, key, metrics, progress, overwrite, label)
    with output.folder(out, overwrite=overwrite) as out:
        return _run_variants(scenes, out, key, metrics, progress, overwrite, label)


def _run_variants(scenes: "Mapping[str, Scene]", out: Path | None, key: str, metrics: Sequence[str],
                  progress: Progress, overwrite: bool,
                  label: str) -> tuple[list[dict[str, Any]], dict[str, Results]]:
    """:func:`run_variants` in a folder already prepared (or none)."""
    rows, results = [], {}
    for name, scene in scenes.items():
        start = time.perf_counter()
        try:
            r = scene.run(None if out is None else out / name, overwrite=overwrite,
                          progress=progress, label=f"{label} {name}".strip())
        except ConvergenceError as err:
            r = err.results
        results[name] = r
        rows.append({key: name, "status": r.status, "warnings": len(r.warnings),
                     "ndof": r.mesh.ndof,
                     "seconds": round(time.perf_counter() - start, 1),
                     **{k: r.metrics.get(k) for k in metrics}})
    return rows, results


def write_summary(out: str | os.PathLike, rows: Sequence[Mapping[str, Any]],
                  columns: Sequence[str], units: dict[str, str],
                  files: Iterable[str] = ()) -> list[str]:
    """``summary.md``, ``.csv`` and ``.json`` in ``out``; the JSON lists the variants' folders
    and ``files`` besides the summary."""
    names = [row[columns[0]] for row in rows]
    summary = ["summary.md", "summary.csv", "summary.json"]
    return tables.write(out, "summary", rows, columns, units,
                        files=[*names, *files, *summary])
