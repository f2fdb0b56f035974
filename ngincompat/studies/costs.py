"""What each scene costs at each of its presets: ``ngincompat bench scenes``.

Every (scene, preset) runs in a fresh process, ``ngincompat run SCENE --preset P --set
outputs=none``, one after the other, so that its wall time, its CPU time (user + system of
that process) and its peak memory (largest resident set, from ``wait4``) are its own. The
table gives per run: ndof, Newton iterations (all stages), wall and CPU time, peak memory, the
machine's load when it started (1-minute average: times on a shared machine are only
comparable at a stated load), and the error of the scene's accuracy metric
(:data:`ACCURACY_METRIC`) against the finest: its closed form where there is one
(:data:`CLOSED_FORMS`: the cube's converged energy, the cylinder's stress-free rotation rate),
else the run of the finest preset in the table (``paper`` when it ran; its own row then
shows 0).
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Collection, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ngincompat import parallel
from ngincompat.errors import ParameterError
from ngincompat.parameters import PRESETS
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes import SCENES
from ngincompat.studies.bench import CUBE_ENERGY
from ngincompat.workflow import io, tables

if TYPE_CHECKING:     # the resource usage os.wait4 returns
    import resource

#: The metric whose error against the finest run measures a preset's accuracy, per scene:
#: the strain energy of the prescribed-growth scenes, the rotation rate the cylinder's growth
#: is relieved by, the mean growth under the skin expander's footprint, the atrophied brain's
#: volume loss, the growth at the folding bilayer's onset of buckling.
ACCURACY_METRIC = {"cube": "strain_energy", "hemisphere": "strain_energy",
                   "disc": "strain_energy", "cylinder": "rotation_rate",
                   "skin": "theta_mean_footprint", "atrophy": "volume_loss",
                   "folding": "onset_growth", "custom": "strain_energy"}
#: Exact values of a scene's accuracy metric, from the run's metrics.
CLOSED_FORMS = {"cube": lambda metrics: CUBE_ENERGY,
                "cylinder": lambda metrics: metrics.get("rotation_rate_expected")}
#: Columns of the cost table, one row per scene and preset.
COLUMNS = ("scene", "preset", "status", "ndof", "newton", "wall_s", "cpu_s", "peak_mb",
           "load", "metric", "value", "error", "reference")
UNITS = {"wall_s": "s", "cpu_s": "s", "peak_mb": "MB"}
#: Seconds a single run may take before it is stopped (and reported as such).
TIMEOUT = 3600.0


def measure(scene: str, preset: str, timeout: float = TIMEOUT, threads: int = 1,
            settings: Mapping[str, Any] | None = None, source: str | os.PathLike | None = None,
            ranks: int = 1) -> tuple[dict[str, Any] | None, dict[str, Any]]:
    """Run ``scene`` at ``preset`` (and the parameters ``settings``, name -> value) in a
    fresh process; returns its results.json as a dict (None when the run wrote none) and the
    row's cost columns (with ``status`` when the run failed or was stopped after ``timeout``
    seconds).

    ``threads``: NGSolve threads of the run (``NGS_NUM_THREADS``; 1, every run's default,
    keeps times on a shared machine comparable). ``source``: a checkout of another version
    of the program (the folder holding its ``ngincompat`` package), run instead of this one
    in the same environment: from that folder, which ``python -m`` puts first on the
    module path (relative paths in ``settings`` are then relative to it). ``ranks`` > 1:
    launched on that many MPI ranks (:func:`ngincompat.parallel.launcher`); the CPU time is
    then that of every rank, the peak memory the launcher's own (each rank's is in the
    results' ``provenance["peak_mib"]``).

    Raises
    ------
    ParameterError
        ``ranks`` > 1 without an MPI launcher."""
    mpi: list[str] = []
    if ranks > 1:
        mpiexec = parallel.launcher()
        if mpiexec is None:
            raise ParameterError(f"ranks = {ranks} needs mpiexec beside this Python or on "
                                 "PATH: pip install 'ngincompat[mpi]'")
        mpi = [mpiexec, "-n", str(ranks)]
    with tempfile.TemporaryDirectory(prefix="ngincompat-cost-") as tmp:
        out, log = Path(tmp) / "run", Path(tmp) / "log"
        command = [*mpi, sys.executable, "-m", "ngincompat.cli", "run", scene, "--out",
                   str(out), "--preset", preset, "--set", "outputs=none", "-q",
                   *(f"--set={key}={value}" for key, value in (settings or {}).items())]
        load = os.getloadavg()[0]
        start = time.perf_counter()
        with open(log, "w") as stream:
            proc = subprocess.Popen(command, stdout=stream, stderr=subprocess.STDOUT,
                                    env={**os.environ, "NGS_NUM_THREADS": str(threads)},
                                    cwd=source)
            code, usage = _wait(proc, start + timeout)
        cost: dict[str, Any] = {"wall_s": round(time.perf_counter() - start, 2),
                "cpu_s": round(usage.ru_utime + usage.ru_stime, 2),
                "peak_mb": round(usage.ru_maxrss / 1024), "load": round(load, 1)}
        record = io.read_json(out / "results.json") if (out / "results.json").is_file() else None
        if code is None:
            cost["status"] = f"stopped after {timeout:g} s"
        elif record is None:
            last = log.read_text().strip().splitlines()[-1:] or [f"exit {code}"]
            cost["status"] = f"failed: {last[0][:160]}"
        return record, cost


def _wait(proc: subprocess.Popen, deadline: float) -> tuple[int | None, resource.struct_rusage]:
    """Wait for ``proc`` until the ``deadline`` (perf_counter); returns its exit code (None
    when it was killed at the deadline) and its resource usage (``os.wait4``: that process
    alone, with its peak resident set)."""
    while True:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
        if pid:
            proc.returncode = os.waitstatus_to_exitcode(status)
            return proc.returncode, usage
        if time.perf_counter() > deadline:
            proc.kill()
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = os.waitstatus_to_exitcode(status)
            return None, usage
        time.sleep(0.05)


def table(scenes: Iterable[str] | None = None, presets: Collection[str] | None = None,
          timeout: float = TIMEOUT, progress: Progress = SILENT) -> list[dict[str, Any]]:
    """Measure every scene of ``scenes`` (default: all) at each of its presets among
    ``presets`` (default: all of the scene's), cheapest preset first; returns the rows
    (columns :data:`COLUMNS`).

    Raises
    ------
    ParameterError
        An unknown scene or preset name (before anything runs).
    """
    scenes = list(scenes or SCENES)
    for name in scenes:
        if name not in SCENES:
            raise ParameterError(f"unknown scene {name!r}: allowed {', '.join(SCENES)}")
    for name in presets or ():
        if name not in PRESETS:
            raise ParameterError(f"unknown preset {name!r}: allowed {', '.join(PRESETS)}")
    rows = []
    for name in scenes:
        cls = SCENES[name]
        runs = [p for p in cls.preset_names() if presets is None or p in presets]
        records = {}
        for preset in runs:
            record, cost = measure(name, preset, timeout)
            records[preset] = record
            rows.append(_row(name, preset, record, cost))
            progress.line(f"{name} {preset}: {rows[-1]['status']}, {cost['wall_s']} s")
        _errors([r for r in rows if r["scene"] == name], records)
    return rows


def _row(scene: str, preset: str, record: Mapping[str, Any] | None,
         cost: Mapping[str, Any]) -> dict[str, Any]:
    """The row of one run (its error is filled in by :func:`_errors`)."""
    metric = ACCURACY_METRIC[scene]
    row = {"scene": scene, "preset": preset, "status": "done", **cost, "metric": metric}
    if record is not None:
        row.update(status=cost.get("status", record["status"]), ndof=record["mesh"]["ndof"],
                   newton=sum(h["newton_iterations"] for h in record["solver"].values()),
                   value=record["metrics"].get(metric))
    return row


def _errors(rows: Sequence[dict[str, Any]], records: Mapping[str, Any] | None) -> None:
    """|value - reference| / |reference| of each row of one scene: the closed form of its
    metric (from ``records``, preset -> results.json), else the value of the finest preset
    that ran (the last)."""
    scene = rows[0]["scene"]
    finest = next((r for r in reversed(rows) if r.get("value") is not None), None)
    for row in rows:
        if row.get("value") is None:
            continue
        if scene in CLOSED_FORMS:
            # records: given for a scene with a closed form (main passes None for the others)
            reference = CLOSED_FORMS[scene](
                records[row["preset"]]["metrics"])  # type: ignore[index]
            row["reference"] = "closed form"
        else:
            # finest: a row with a value, as this one is
            reference, row["reference"] = finest["value"], finest["preset"]  # type: ignore[index]
        if reference:
            row["error"] = abs(row["value"] - reference) / abs(reference)


def merged(old: Iterable[dict[str, Any]], new: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows of an earlier table ``old`` with those of ``new`` in place of the same
    (scene, preset), in the order of the scenes and presets."""
    measured = {(r["scene"], r["preset"]) for r in new}
    rows = [r for r in old if (r["scene"], r["preset"]) not in measured] + list(new)
    scenes = list(SCENES)
    return sorted(rows, key=lambda r: (scenes.index(r["scene"]), PRESETS.index(r["preset"])))


def main(scenes: Iterable[str] | None = None, presets: Collection[str] | None = None,
         out: str | os.PathLike | None = None, timeout: float = TIMEOUT) -> list[str]:
    """``ngincompat bench scenes``: :func:`table`; returns the lines to print. With ``out``
    the table is also written as ``scenes.md``, ``.csv``, ``.json``, keeping the rows of an
    earlier table there that this run did not measure (so one scene can be measured again
    after a change)."""
    rows = table(scenes, presets, timeout, progress=Progress())
    if out is not None and (Path(out) / "scenes.json").is_file():
        rows = merged(io.read_json(Path(out) / "scenes.json")["rows"], rows)
        # the finest run of a scene may be one of the earlier table's
        for name in dict.fromkeys(r["scene"] for r in rows):
            if name not in CLOSED_FORMS:
                _errors([r for r in rows if r["scene"] == name], None)
    lines = [tables.markdown(rows, list(COLUMNS), UNITS),
             "(one process per run, NGSolve on 1 thread; load: the 1-minute load average at "
             "its start; error: of the metric against the reference)"]
    if out is not None:
        tables.write(out, "scenes", rows, list(COLUMNS), UNITS)
        lines.append(f"table written to {Path(out) / 'scenes.md'} (.csv, .json)")
    return lines
