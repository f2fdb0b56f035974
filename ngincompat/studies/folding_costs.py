"""What the folding scene costs per axon field at a preset, and where its time goes:
``ngincompat bench folding``.

Each axon field runs in a fresh process (:func:`ngincompat.studies.costs.measure`: wall and
CPU time, peak memory, the machine's load at its start), one after the other. Four tables:

* ``fields``: per axon field the program that ran (its version and git commit), the
  status, how far the growth went, ndof, Newton iterations, the failed tries (steps that
  did not converge and were retried shorter), wall and CPU time;
* ``work``: per axon field the seconds of each kind of work
  (:data:`ngincompat.fem.work.KINDS`: tangent assembly, factorisation, linear solves,
  residuals, energies, contact search, eigenpairs) summed over the stages, what else the
  stages took (Python between the calls, measurements of the march) and the time outside
  the stages (mesh, incompatibility, output, the process' start);
* ``stages``: per axon field and stage its wall time, Newton iterations, failed tries and
  tangents;
* ``metrics``: per axon field the measures of the paper's finding and of the folds
  (:data:`METRICS`), so that a change that makes a run cheaper shows what it does to them.

With a ``baseline`` (a checkout of another version, e.g. a ``git worktree`` of the commit
before a change) each field runs on it right after this version, under the same load: the
rows' ``version`` says which ("this" or "baseline"), before and after in one run.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ngincompat.errors import ParameterError
from ngincompat.fem.work import KINDS
from ngincompat.mechanics import fields
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes.folding import FoldingScene
from ngincompat.studies.costs import TIMEOUT, measure
from ngincompat.workflow import tables

FIELD_COLUMNS = ("axons", "version", "program", "preset", "threads", "status", "t_reached",
                 "ndof", "newton", "failed", "wall_s", "cpu_s", "peak_mb", "load")
WORK_COLUMNS = ("axons", "version", *KINDS, "other in the stages", "outside the stages", "wall_s")
STAGE_COLUMNS = ("axons", "version", "stage", "wall_s", "newton", "failed", "tangents")
#: The metrics of the ``metrics`` table.
METRICS = ("burgers_interface_mean", "max_principal_stress_released", "theta_a_max", "sulci",
           "sulcus_depth", "fold_amplitude", "Je_min", "self_contact_penetration_max")
METRICS_COLUMNS = ("axons", "version", *METRICS)
UNITS = {"wall_s": "s", "cpu_s": "s", "peak_mb": "MB",
         "t_reached": FoldingScene.metric_unit("t_reached"),
         **dict.fromkeys((*KINDS, "other in the stages", "outside the stages"), "s"),
         **{name: FoldingScene.metric_unit(name) for name in METRICS}}


def _failed(history: Mapping[str, Any]) -> int:
    return sum(1 for step in history["steps"] if not step["converged"])


def rows_of(axons: str, preset: str, threads: int, record: Mapping[str, Any] | None,
            cost: Mapping[str, Any], version: str = "this"
            ) -> tuple[dict[str, Any], dict[str, Any] | None, list[dict[str, Any]],
                       dict[str, Any] | None]:
    """The rows of one run in the four tables (only the first when it wrote no results)."""
    field_row = {"axons": axons, "version": version, "preset": preset, "threads": threads,
                 "status": "done", **cost}
    if record is None:
        return field_row, None, [], None
    solver = record["solver"]
    git = record.get("provenance", {}).get("git") or {}
    program = " ".join(filter(None, (record.get("versions", {}).get("ngincompat"),
                                     git.get("commit", "")[:10])))
    field_row.update(program=program, status=cost.get("status", record["status"]),
                     t_reached=record["metrics"].get("t_reached"),
                     ndof=record["mesh"]["ndof"],
                     newton=sum(h["newton_iterations"] for h in solver.values()),
                     failed=sum(_failed(h) for h in solver.values()))
    spent = {kind: sum(h.get("work", {}).get(kind, 0.0) for h in solver.values())
             for kind in KINDS}
    in_stages = sum(record["timings"].get(stage, 0.0) for stage in solver)
    work_row = {"axons": axons, "version": version, **spent,
                "other in the stages": in_stages - sum(spent.values()),
                "outside the stages": cost["wall_s"] - in_stages, "wall_s": cost["wall_s"]}
    stage_rows = [{"axons": axons, "version": version, "stage": stage,
                   "wall_s": record["timings"].get(stage),
                   "newton": h["newton_iterations"], "failed": _failed(h),
                   "tangents": h["tangent_assemblies"]} for stage, h in solver.items()]
    metric_row = {"axons": axons, "version": version,
                  **{name: record["metrics"].get(name) for name in METRICS}}
    return field_row, work_row, stage_rows, metric_row


def table(axons: Sequence[str] = fields.AXONS, preset: str = "default", threads: int = 1,
          timeout: float = TIMEOUT, settings: Mapping[str, Any] | None = None,
          progress: Progress = SILENT, baseline: str | os.PathLike | None = None
          ) -> tuple[list[dict[str, Any]], list[dict[str, Any]], list[dict[str, Any]],
                     list[dict[str, Any]]]:
    """Run the folding scene for each axon field of ``axons`` at ``preset`` (with the
    parameters ``settings``) on ``threads`` NGSolve threads, and after each on the checkout
    ``baseline`` if given; returns the rows of the four tables (fields, work, stages,
    metrics).

    Raises
    ------
    ParameterError
        An unknown axon field (before anything runs).
    """
    for name in axons:
        if name not in fields.AXONS:
            raise ParameterError(f"unknown axon field {name!r}: allowed "
                                 f"{', '.join(fields.AXONS)}")
    field_rows, work_rows, stage_rows, metric_rows = [], [], [], []
    versions = {"this": None, **({"baseline": baseline} if baseline else {})}
    for name in axons:
        for version, source in versions.items():
            record, cost = measure("folding", preset, timeout, threads=threads,
                                   settings={**(settings or {}), "axons": name},
                                   source=source)
            field_row, work_row, stages, metric_row = rows_of(name, preset, threads, record,
                                                              cost, version)
            field_rows.append(field_row)
            work_rows += [work_row] if work_row else []
            stage_rows += stages
            metric_rows += [metric_row] if metric_row else []
            progress.line(f"folding {name} ({version}): {field_row['status']}, "
                          f"{cost['wall_s']} s")
    return field_rows, work_rows, stage_rows, metric_rows


def main(axons: Sequence[str] = fields.AXONS, preset: str = "default", threads: int = 1,
         out: str | os.PathLike | None = None, timeout: float = TIMEOUT,
         settings: Mapping[str, Any] | None = None,
         baseline: str | os.PathLike | None = None) -> list[str]:
    """``ngincompat bench folding``: :func:`table`; returns the lines to print. With ``out``
    the tables are also written as ``fields``, ``work``, ``stages`` and ``metrics`` (.md,
    .csv, .json)."""
    if baseline is not None and not (Path(baseline) / "ngincompat" / "cli.py").is_file():
        raise ParameterError(f"baseline = {baseline!r} is out of range: allowed a checkout "
                             "of ngincompat (a folder with ngincompat/cli.py)")
    field_rows, work_rows, stage_rows, metric_rows = table(
        axons, preset, threads, timeout, settings, progress=Progress(), baseline=baseline)
    parts = (("fields", field_rows, FIELD_COLUMNS), ("work", work_rows, WORK_COLUMNS),
             ("stages", stage_rows, STAGE_COLUMNS), ("metrics", metric_rows, METRICS_COLUMNS))
    lines = []
    for name, rows, columns in parts:
        lines += [tables.markdown(rows, list(columns), UNITS), ""]
        if out is not None:
            tables.write(out, name, rows, list(columns), UNITS)
    lines.append(f"(one process per axon field, NGSolve on {threads} thread(s); load: the "
                 "1-minute load average at its start; failed: tries retried shorter)")
    if out is not None:
        lines.append(f"tables written to {out}: fields, work, stages, metrics (.md, .csv, "
                     ".json)")
    return lines
