"""The checks against closed forms and independent solutions that no other benchmark
tabulates: ``ngincompat bench validation``.

Four tables, each of runs of the library's scenes against a solution built apart from them:

* ``closed_forms``: the paper's sections 3.1-3.4 as ``ngincompat paper`` runs them
  (:func:`ngincompat.studies.paper.run_all`, nothing written), with the verification metrics
  of its summary (:data:`ngincompat.studies.paper.CHECKS`: G against eqs. (16), (19)-(20),
  (24)-(25), b against eqs. (17), (22), (27), the hemisphere's stresses against the 1-D
  radial solution, the disc's sigma_r at the rim, the cylinder's Fe against the rotation of
  eqs. (54)-(56)) and the cube's energy against :data:`ngincompat.studies.bench.CUBE_ENERGY`;
* ``onset``: the folding bilayer's onset of buckling (its perfect branch, ``buckle=false``)
  under refinement of the mesh, against the Stroh analysis of the same bilayer with roller
  ends (:func:`ngincompat.references.bifurcation.onset`): growth, wavelength, mode;
* ``atrophy_logistic``: atrophy of a small brain under a uniform seed with equal gray and
  white rates, which is compatible (G = 0, no stress) and whose volume loss has a closed
  form: c follows the logistic solution (:func:`ngincompat.fem.transport.logistic`), theta
  the atrophy law of its exposure int_0^t c ds
  (:meth:`ngincompat.mechanics.atrophy.AtrophyLaw.theta`), and 1 - int J dV / V0 = 1 - theta;
  under refinement of the time step (backward Euler: first order);
* ``atrophy_balance``: the same brain seeded at its basal pole with the default rates (gray
  30 times faster than white) under refinement of the mesh: the released body's
  self-equilibrium (|int sigma dv| / int |sigma| dv), the volume bookkeeping
  |int J dV - int theta dV| / V0 against its bound max |Je - 1|.

With ``out``: the tables (markdown, CSV, JSON) and two convergence plots, ``onset.png`` (the
onset's error against the dofs) and ``atrophy_logistic.png`` (the volume loss's error against
the time step). ``quick`` runs coarse settings (:data:`QUICK`).
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from ngincompat.fem.transport import logistic_integral
from ngincompat.mechanics.atrophy import AtrophyLaw
from ngincompat.progress import SILENT, Progress
from ngincompat.references.bifurcation import onset
from ngincompat.scenes import AtrophyScene, FoldingScene
from ngincompat.studies import paper
from ngincompat.studies.bench import CUBE_ENERGY
from ngincompat.workflow import plots, tables

#: The idealized sections of the paper (those with closed forms and 1-D references).
SECTIONS = ("3.1", "3.2", "3.3", "3.4")
CLOSED_FORM_COLUMNS = ("case", "ndof", "energy_error", *paper.CHECKS)

#: The small bilayer of the onset study (1 x 0.5 cm; its substrate is still ten cortical
#: thicknesses deep) on its perfect branch only, without axons (they do not grow on the flat
#: branch: lambda_e = 1 along any axon field there).
BILAYER: dict[str, Any] = dict(length=1.0, height=0.5, axons="none", buckle=False,
                               release=False, outputs="none")
ONSET_COLUMNS = ("cortex_maxh", "maxh", "ndof", "onset_growth", "stroh_growth",
                 "growth_error", "onset_wavelength", "stroh_wavelength", "mode", "stroh_mode",
                 "seconds")

#: The small brain of the atrophy studies (3 x 2.5 x 2 cm, gray shell 0.5 cm, ten years).
BRAIN: dict[str, Any] = dict(semi_axes="3,2.5,2", gray_thickness=0.5, t_end=10.0, snapshots=1,
                             g_order=2, outputs="none")
#: The uniform seed with equal rates: compatible atrophy with a closed-form volume loss.
UNIFORM: dict[str, Any] = dict(seed="uniform", rate_gray=0.03, rate_white=0.03)
#: The seed at the basal pole with the default rates.
SEEDED: dict[str, Any] = dict(seed="0,0,-2", seed_radius=1.0, d_ext=0.05, dt=1.0)
LOGISTIC_COLUMNS = ("dt", "volume_loss", "closed_form", "error", "order", "burgers_max",
                    "G_norm_L2", "Je_deviation_max", "seconds")
BALANCE_COLUMNS = ("maxh", "ndof", "volume_loss", "volume_loss_theta",
                   "volume_bookkeeping_error", "Je_deviation_max", "equilibrium_residual_rel",
                   "seconds")

#: The grids: (cortex_maxh, maxh) of the bilayer, the time steps of the uniform atrophy
#: (on maxh 2), the mesh sizes of the seeded brain, the resolution of sections 3.1-3.4.
FULL: dict[str, Any] = {"resolution": "paper",
        "onset": ((0.025, 0.1), (0.016667, 0.066667), (0.0125, 0.05)),
        "dts": (1.0, 0.5, 0.25, 0.125), "maxhs": (1.0, 0.5, 0.35)}
#: What ``--quick`` runs (a few minutes): the previews of sections 3.1-3.4, a bilayer with
#: a cortex twice as thick on two coarse meshes, two time steps, the two coarser brains.
QUICK: dict[str, Any] = {"resolution": "preview", "onset": ((0.05, 0.3), (0.033333, 0.2)),
         "dts": (1.0, 0.5), "maxhs": (1.0, 0.5), "bilayer": dict(cortex_thickness=0.1)}

UNITS = {"seconds": "s", "cortex_maxh": "cm", "maxh": "cm", "onset_wavelength": "cm",
         "stroh_wavelength": "cm", "dt": "yr", "burgers_max": "1/cm"}


def closed_forms(resolution: str = "paper", progress: Progress = SILENT) -> list[dict[str, Any]]:
    """Sections 3.1-3.4 at ``resolution`` (``ngincompat paper``'s settings): one row per
    case with its ndof, the cube's energy error and the verification metrics."""
    rows = []
    for row in paper.run_all(None, progress=progress, resolution=resolution,
                             only=SECTIONS):
        if row["case"] == "cube":
            row["energy_error"] = abs(row["strain_energy"] - CUBE_ENERGY) / CUBE_ENERGY
        rows.append(row)
    return rows


def onset_table(meshes: Iterable[tuple[float, float]], progress: Progress = SILENT,
                **bilayer: Any) -> list[dict[str, Any]]:
    """The bilayer's onset on every (cortex_maxh, maxh) of ``meshes`` against the Stroh
    analysis of the same bilayer; ``bilayer``: settings over :data:`BILAYER`."""
    rows = []
    for cortex_maxh, maxh in meshes:
        scene = FoldingScene(**{**BILAYER, **bilayer}, cortex_maxh=cortex_maxh, maxh=maxh)
        start = time.perf_counter()
        results = scene.run()
        seconds = time.perf_counter() - start
        oracle = onset(scene.bifurcation_bilayer(), length=scene.length)
        m = results.metrics
        row = {"cortex_maxh": cortex_maxh, "maxh": maxh, "ndof": results.mesh.ndof,
               "stroh_growth": oracle.growth, "stroh_wavelength": oracle.wavelength,
               "stroh_mode": oracle.mode, "seconds": round(seconds, 1)}
        if "onset_growth" in m:
            row.update(onset_growth=m["onset_growth"], onset_wavelength=m["onset_wavelength"],
                       growth_error=(m["onset_growth"] - oracle.growth) / oracle.growth,
                       mode=round(2 * scene.length / m["onset_wavelength"]))
        rows.append(row)
        progress.line(f"onset on {cortex_maxh:g} / {maxh:g}: {row.get('onset_growth')} "
                      f"against {oracle.growth:.6g}")
    return rows


def logistic_table(dts: Iterable[float], maxh: float = 2.0,
                   progress: Progress = SILENT) -> list[dict[str, Any]]:
    """Uniform atrophy with equal rates for every time step of ``dts``: the volume loss
    against its closed form 1 - theta(int_0^t c ds), with the observed order between
    successive steps and the measures of compatibility."""
    rows: list[dict[str, Any]] = []
    for dt in dts:
        scene = AtrophyScene(maxh=maxh, dt=dt, **BRAIN, **UNIFORM)
        start = time.perf_counter()
        m = scene.run().metrics
        exact = 1 - AtrophyLaw(scene.rate_gray, scene.theta_min).theta(
            logistic_integral(scene.t_end, scene.c0, scene.alpha))
        row = {"dt": dt, "volume_loss": m["volume_loss"], "closed_form": exact,
               "error": abs(m["volume_loss"] - exact) / exact,
               **{k: m[k] for k in ("burgers_max", "G_norm_L2", "Je_deviation_max")},
               "seconds": round(time.perf_counter() - start, 1)}
        if rows:
            row["order"] = float(np.log(rows[-1]["error"] / row["error"])
                                 / np.log(rows[-1]["dt"] / dt))
        rows.append(row)
        progress.line(f"uniform atrophy, dt {dt:g}: error {row['error']:.3g}")
    return rows


def balance_table(maxhs: Iterable[float], progress: Progress = SILENT) -> list[dict[str, Any]]:
    """The seeded small brain on every mesh size of ``maxhs``: self-equilibrium and volume
    bookkeeping."""
    rows = []
    for maxh in maxhs:
        start = time.perf_counter()
        results = AtrophyScene(maxh=maxh, **BRAIN, **SEEDED).run()
        m = results.metrics
        rows.append({"maxh": maxh, "ndof": results.mesh.ndof,
                     **{k: m[k] for k in BALANCE_COLUMNS[2:-1]},
                     "seconds": round(time.perf_counter() - start, 1)})
        progress.line(f"seeded atrophy, maxh {maxh:g}: residual "
                      f"{m['equilibrium_residual_rel']:.3g}")
    return rows


def main(out: str | os.PathLike | None = None, quick: bool = False,
         progress: Progress = SILENT) -> list[str]:
    """``ngincompat bench validation``: the four tables (``quick``: :data:`QUICK`, else
    :data:`FULL`); returns the lines to print. With ``out`` the tables ``closed_forms``,
    ``onset``, ``atrophy_logistic`` and ``atrophy_balance`` (markdown, CSV, JSON) and the plots
    ``onset.png`` and ``atrophy_logistic.png``."""
    grid = QUICK if quick else FULL
    results = {
        "closed_forms": (closed_forms(grid["resolution"], progress), CLOSED_FORM_COLUMNS),
        "onset": (onset_table(grid["onset"], progress, **grid.get("bilayer", {})),
                  ONSET_COLUMNS),
        "atrophy_logistic": (logistic_table(grid["dts"], progress=progress), LOGISTIC_COLUMNS),
        "atrophy_balance": (balance_table(grid["maxhs"], progress), BALANCE_COLUMNS),
    }
    lines = []
    for name, (rows, columns) in results.items():
        lines += [f"{name}:", tables.markdown(rows, list(columns), UNITS), ""]
    if out is not None:
        for name, (rows, columns) in results.items():
            tables.write(out, name, rows, list(columns), UNITS, quick=quick)
        onset_rows = [r for r in results["onset"][0] if "growth_error" in r]
        plots.save(plots.curves_figure(
            {"|onset - Stroh| / Stroh": ([r["ndof"] for r in onset_rows],
                                         [max(abs(r["growth_error"]), 1e-16)
                                          for r in onset_rows])},
            "dofs", "relative error of the onset growth [-]",
            "folding onset against the Stroh analysis", logx=True, logy=True),
            Path(out) / "onset.png")
        logistic = results["atrophy_logistic"][0]
        plots.save(plots.curves_figure(
            {"volume loss": ([r["dt"] for r in logistic],
                             [max(r["error"], 1e-16) for r in logistic])},
            "time step [yr]", "relative error against the closed form [-]",
            "uniform atrophy against the logistic closed form", logx=True, logy=True),
            Path(out) / "atrophy_logistic.png")
        lines.append(f"tables and plots written to {out}")
    return lines
