"""What a distributed run costs per rank, and a model of it for larger brains:
``ngincompat bench mpi``.

The atrophy scene on its idealized brain at the mesh sizes ``maxh``, one equilibrium at its
end (``snapshots`` 1), each size launched on each number of ``ranks`` (rank 0 owns no
elements: ``ranks - 1`` workers) in a fresh launch (:func:`ngincompat.studies.costs.measure`),
one after the other. Per run: the unknowns N, the ranks, the wall time of the run and of
its stage (``equilibrium_s``: the transport and the atrophy to ``t_end``, 200 steps of a
scalar problem at the defaults, and the equilibrium there), the CPU time of all ranks,
each rank's peak memory (results.json's ``provenance["peak_mib"]``: rank 0, then the
heaviest worker), the Newton and CG iterations, and the machine's load at the start.

The cost model (:func:`fit`), fitted to the rows by least squares:

    worker memory   M_w = B + m N / W,
    rank 0 memory   M_0 = B + c N^alpha,
    the stage       T = t (N / W)^beta,

B the footprint of a rank before it holds a mesh (Python, NGSolve, the package:
:func:`footprint`), W = ranks - 1 the workers. Rank 0 holds BDDC's coarse problem, which it
gathers and factorises (the pip wheels have no distributed direct solver): its memory does not
fall with W. T is fitted to the runs with one worker only: on a machine with fewer cores
than ranks the others share cores, and their times are reported but not fitted.
:func:`predict` evaluates the model at other N and W, e.g. a brain several times larger on a
cluster's workers; what the model leaves out (CG iterations that grow with N or W, the
coarse solve's share of the time, the network) is said where it is shown
(``docs/guide/mpi.md``).
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ngincompat.errors import ParameterError, require
from ngincompat.progress import SILENT, Progress
from ngincompat.studies import costs
from ngincompat.workflow import tables

#: The default grid's mesh sizes of the idealized brain.
MAXH = (1.4, 1.0, 0.8)
#: The default grid's numbers of ranks, each run at every mesh size.
RANKS = (2, 3)
#: Every run's settings besides its mesh size: one equilibrium, no files but results.json.
SETTINGS = {"snapshots": 1}
#: Columns of the table, one row per run, and their units.
COLUMNS = ("maxh", "ndof", "ranks", "status", "wall_s", "equilibrium_s", "cpu_s",
           "rank0_mib", "worker_mib", "newton", "cg_iterations", "load")
UNITS = {"wall_s": "s", "equilibrium_s": "s", "cpu_s": "s", "rank0_mib": "MiB",
         "worker_mib": "MiB"}
#: Units of the projection's columns.
PROJECTED_UNITS = {"worker_mib": "MiB", "rank0_mib": "MiB", "equilibrium_s": "s"}
#: Seconds one run may take before it is stopped.
TIMEOUT = 3600.0


def footprint() -> float:
    """The peak memory [MiB] of a fresh process that has imported NGSolve and the package's
    scenes, as every rank does before it holds a mesh."""
    code = ("import ngsolve, ngincompat.scenes.atrophy; "
            "from ngincompat.resources import peak_mib; print(peak_mib())")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, env={**os.environ, "NGS_NUM_THREADS": "1"})
    return float(done.stdout.split()[-1])


def row(maxh: float, ranks: int, record: Mapping[str, Any] | None,
        cost: Mapping[str, Any]) -> dict[str, Any]:
    """The table's row of one run, from its results.json (``record``, None if it wrote none)
    and its costs (:func:`ngincompat.studies.costs.measure`)."""
    line: dict[str, Any] = {"maxh": maxh, "ranks": ranks, "status": "done",
                            **{k: cost[k] for k in ("wall_s", "cpu_s", "load")}}
    if record is None:
        line["status"] = cost.get("status", "failed")
        return line
    peaks = record.get("provenance", {}).get("peak_mib", [])
    steps = [s for h in record["solver"].values() for s in h["steps"]]
    krylov = [n for s in steps for n in s.get("linear_iterations", [])]
    line.update(status=cost.get("status", record["status"]), ndof=record["mesh"]["ndof"],
                equilibrium_s=round(sum(t for k, t in record["timings"].items()
                                        if k in record["solver"]), 2),
                rank0_mib=peaks[0] if peaks else None,
                worker_mib=max(peaks[1:]) if len(peaks) > 1 else None,
                newton=sum(h["newton_iterations"] for h in record["solver"].values()),
                cg_iterations=f"{min(krylov)}-{max(krylov)}" if krylov else "direct")
    return line


def table(maxh: Sequence[float] = MAXH, ranks: Sequence[int] = RANKS,
          settings: Mapping[str, Any] | None = None, timeout: float = TIMEOUT,
          progress: Progress = SILENT) -> list[dict[str, Any]]:
    """Run every mesh size of ``maxh`` on every number of ``ranks`` (>= 2) with
    :data:`SETTINGS` and ``settings``; returns the rows (:data:`COLUMNS`).

    Raises
    ------
    ParameterError
        A number of ranks below 2, a mesh size <= 0, or no MPI launcher."""
    for r in ranks:
        require(isinstance(r, int) and r >= 2, "ranks", r, "integers >= 2 (rank 0 and at "
                "least one worker)")
    for h in maxh:
        require(h > 0, "maxh", h, "> 0")
    rows = []
    for h in maxh:
        for r in ranks:
            record, cost = costs.measure("atrophy", "default", timeout,
                                         settings={**SETTINGS, **(settings or {}), "maxh": h},
                                         ranks=r)
            rows.append(row(h, r, record, cost))
            progress.line(f"maxh {h:g} on {r} ranks: {rows[-1]['status']}, "
                          f"{cost['wall_s']} s")
    return rows


def fit(rows: Sequence[Mapping[str, Any]], base: float) -> dict[str, float]:
    """The cost model of the module's docstring fitted to the finished ``rows`` with the
    footprint ``base`` (B, MiB): ``m`` (MiB per unknown and worker), ``c`` and ``alpha``
    (rank 0), ``t`` and ``beta`` (the stage's seconds, from the rows with one worker),
    each None where fewer than two rows carry it.

    Raises
    ------
    ParameterError
        No finished row."""
    done = [r for r in rows if r.get("status") == "done" and r.get("ndof")]
    if not done:
        raise ParameterError("no finished run to fit the cost model to")
    model: dict[str, Any] = {"base_mib": base, "m": None, "c": None, "alpha": None,
                             "t": None, "beta": None}
    workers = [(r["ndof"] / (r["ranks"] - 1), r["worker_mib"] - base) for r in done
               if r.get("worker_mib") is not None]
    if workers:
        x, y = np.array(workers).T
        model["m"] = float(x @ y / (x @ x))         # through the origin: M_w - B = m N / W
    rank0 = [(r["ndof"], r["rank0_mib"] - base) for r in done
             if r.get("rank0_mib") is not None and r["rank0_mib"] > base]
    if len({n for n, _ in rank0}) >= 2:
        model["alpha"], model["c"] = _power_law(rank0)
    single = [(r["ndof"], r["equilibrium_s"]) for r in done if r["ranks"] == 2]
    if len({n for n, _ in single}) >= 2:
        model["beta"], model["t"] = _power_law(single)
    return model


def _power_law(points: Sequence[tuple[float, float]]) -> tuple[float, float]:
    """(exponent, coefficient) of y = coefficient x^exponent, least squares in log-log."""
    x, y = np.log(np.array(points, dtype=float)).T
    exponent, log_coefficient = np.polyfit(x, y, 1)
    return float(exponent), float(np.exp(log_coefficient))


def predict(model: Mapping[str, Any], ndof: float, workers: int) -> dict[str, float | None]:
    """The model at ``ndof`` unknowns on ``workers`` workers: the memory of a worker and of
    rank 0 [MiB] and the stage's wall time [s] (None where the model lacks the
    constant)."""
    require(workers >= 1, "workers", workers, ">= 1")
    base = model["base_mib"]
    return {
        "worker_mib": None if model["m"] is None else base + model["m"] * ndof / workers,
        "rank0_mib": (None if model["c"] is None
                      else base + model["c"] * ndof ** model["alpha"]),
        "equilibrium_s": (None if model["t"] is None
                          else model["t"] * (ndof / workers) ** model["beta"]),
    }


#: Where :func:`main` evaluates the model, on 1 to 64 workers: 334,194 unknowns (the fsaverage
#: hemisphere at ico 4 with 2 layers before the mixed pair's face bubbles; with them it has
#: 700,299, ``docs/measurements/atrophy.md``) and ten times that.
PROJECTIONS = ((334_194, (1, 2)), (3_341_940, (1, 8, 16, 32, 64)))


def main(maxh: Sequence[float] | None = None, ranks: Sequence[int] | None = None,
         settings: Mapping[str, Any] | None = None, timeout: float | None = None,
         out: str | os.PathLike | None = None) -> list[str]:
    """``ngincompat bench mpi``: :func:`table` (None: :data:`MAXH`, :data:`RANKS`,
    :data:`TIMEOUT`), :func:`fit` and :func:`predict` at :data:`PROJECTIONS`; returns the
    lines to print, and with ``out`` writes ``mpi``, ``model`` and ``projection`` (.md, .csv,
    .json)."""
    rows = table(maxh or MAXH, ranks or RANKS, settings, timeout or TIMEOUT,
                 progress=Progress())
    model = fit(rows, footprint())
    projection = [{"ndof": n, "workers": w, **{k: None if v is None else round(v, 1)
                                               for k, v in predict(model, n, w).items()}}
                  for n, counts in PROJECTIONS for w in counts]
    constants = [{"constant": k, "value": v} for k, v in model.items()]
    lines = [tables.markdown(rows, list(COLUMNS), UNITS), tables.markdown(constants),
             tables.markdown(projection, None, PROJECTED_UNITS)]
    if out is not None:
        tables.write(out, "mpi", rows, list(COLUMNS), UNITS)
        tables.write(out, "model", constants)
        tables.write(out, "projection", projection, None, PROJECTED_UNITS)
    return lines
