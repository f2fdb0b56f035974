"""Benchmarks of accuracy against cost: ``ngincompat bench cube`` and ``ngincompat bench
accuracy``. (``bench stability`` is :mod:`.stability`, ``bench scaling`` :mod:`.scaling`.)

``cube``: for every (maxh, order) the cube scene is solved and the table reports ndof, Newton
iterations, solve time, the strain energy, its relative error against the converged energy
:data:`CUBE_ENERGY`, and the relative L2 error of G (projected path) against eq. (16).

``accuracy``: the same for the cube (also as the fast quarter model), the hemisphere in
symmetry mode and the cylinder, each against its own reference (:func:`error`), with the
cheapest setting that meets each target error and a plot of error against solve time.

The runs write only results.json (``outputs = "none"``) and only when a folder is given, into
its subfolder ``runs`` (apart from the tables and plots, which the documentation includes), so
the times are those of the computation. Every table is written by
:func:`ngincompat.workflow.tables.write`
(markdown, CSV, JSON) with units.
"""

import itertools
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

from ngincompat.scenes import CubeScene, get_scene
from ngincompat.scenes.base import Scene
from ngincompat.workflow import plots, tables
from ngincompat.workflow.results import Results

#: Converged strain energy of the cube [N mm]: order 6 on 4^3 hexahedra, 2.195334e-7, which
#: agrees with the independent reference 2.19533e-7.
CUBE_ENERGY = 2.195334e-7

#: Columns of ``bench cube``.
CUBE_COLUMNS = ("maxh", "order", "ndof", "newton", "solve_s", "strain_energy", "energy_error",
                "G_error")
#: Units of the columns of every bench table (the scenes' units: mm, N mm).
UNITS = {"maxh": CubeScene.units["length"], "solve_s": "s",
         "strain_energy": CubeScene.units["energy"], "energy_error": "-", "G_error": "-",
         "error": "-", "target": "-"}


#: The subfolder of a benchmark's ``out`` that holds its runs' results.json.
RUNS = "runs"


def _run(scene: Scene, out: str | os.PathLike | None, label: str) -> Results:
    """Run ``scene`` into ``out/runs/label`` (nowhere without ``out``); returns its Results."""
    return scene.run(None if out is None else Path(out) / RUNS / label, overwrite=True)


def cube_table(maxhs: Iterable[float], orders: Iterable[int],
               out: str | os.PathLike | None = None,
               elements: Literal["hex", "tet"] = "hex") -> list[dict[str, Any]]:
    """Run the cube for every (maxh, order), coarsest mesh first, on ``elements`` (the
    paper's hexahedra by default; the scene's default is tetrahedra).

    Parameters
    ----------
    maxhs : sequence of float
        Mesh sizes [mm].
    orders : sequence of int
        Polynomial orders.
    out : path-like, optional
        Folder whose ``runs`` subfolder takes the runs' results.json
        (``cube_h<maxh>_p<order>``), replaced if present.

    Returns
    -------
    list of dict
        One row per run with the columns :data:`CUBE_COLUMNS`; ``energy_error`` is
        ``|W - CUBE_ENERGY| / CUBE_ENERGY``.
    """
    rows = []
    for maxh, order in itertools.product(sorted(maxhs, reverse=True), sorted(orders)):
        r = _run(CubeScene(maxh=maxh, order=order, elements=elements,
                           outputs="none"),  # type: ignore[arg-type]  # the scene converts it
                 out, f"cube_h{maxh:g}_p{order}")
        rows.append({"maxh": maxh, "order": order, "ndof": r.mesh.ndof,
                     "newton": r.newton_iterations, "solve_s": r.solve_seconds,
                     "strain_energy": r.metrics["strain_energy"],
                     "energy_error": error("cube", r),
                     "G_error": r.metrics["G_error_L2_rel"]})
    return rows


def cube_main(maxhs: Iterable[float] = (0.5, 0.25), orders: Iterable[int] = (2, 3, 4, 5),
              out: str | os.PathLike | None = None,
              elements: Literal["hex", "tet"] = "hex") -> list[str]:
    """``ngincompat bench cube``: run :func:`cube_table`; returns the lines to print.

    With ``out`` the table is written as ``bench.md``, ``bench.csv`` and ``bench.json``.
    """
    rows = cube_table(maxhs, orders, out, elements)
    lines = [tables.markdown(rows, list(CUBE_COLUMNS), UNITS),
             f"(energy error against the converged energy {CUBE_ENERGY:.7g} N mm)"]
    if out is not None:
        tables.write(out, "bench", rows, list(CUBE_COLUMNS), UNITS, case="cube",
                     elements=elements, reference_energy=CUBE_ENERGY)
        lines.append(f"table written to {Path(out) / 'bench.md'} (.csv, .json)")
    return lines


#: (scene, settings grid) of the accuracy study; errors as documented in :func:`error`.
#: "cube" (hexahedra) takes a fresh tangent every Newton iteration; "cube-fast" is the
#: hexahedral cube with every lever for speed: a quarter model (two mirror planes) and the
#: factorised tangent reused (the scenes' default); "cube-tet" the cube's default family,
#: tetrahedra on the symmetric rule from order 6 (``quadrature=auto``), tangent reused.
ACCURACY: dict[str, tuple[str, list[dict[str, Any]]]] = {
    "cube": ("cube", [dict(maxh=h, order=p, elements="hex", reuse_tangent=False)
                      for h in (1.0, 0.5, 0.25) for p in (2, 3, 4, 5)]),
    "cube-fast": ("cube", [dict(maxh=h, order=p, elements="hex", model="quarter",
                                reuse_tangent=True)
                           for h in (1.0, 0.5, 0.25) for p in (3, 4, 5)]),
    "cube-tet": ("cube", [dict(maxh=h, order=p) for h in (1.0, 0.5) for p in (4, 5, 6, 7)]),
    "hemisphere": ("hemisphere", [dict(maxh=h, centre_maxh=c, order=p, flat_face="symmetry")
                                  for h, c in ((0.4, 0.1), (0.3, 0.02)) for p in (2, 3, 4)]),
    "cylinder": ("cylinder", [dict(maxh=h, order=p) for h in (0.5, 0.25) for p in (2, 3, 4)]),
}
#: The corner of :data:`ACCURACY` that ``--quick`` runs (seconds; what the tests run).
QUICK_ACCURACY: dict[str, tuple[str, list[dict[str, Any]]]] = {
    "cube": ("cube", [dict(maxh=1.0, order=2, elements="hex", reuse_tangent=False),
                      dict(maxh=1.0, order=3, elements="hex", reuse_tangent=False)]),
    "cube-fast": ("cube", [dict(maxh=0.5, order=3, elements="hex", model="quarter",
                                reuse_tangent=True)]),
    "cylinder": ("cylinder", [dict(maxh=0.5, order=2)]),
}
#: Relative errors of the accuracy study's targets: the cheapest setting meeting each.
TARGETS = (1e-2, 1e-4, 1e-6)
#: Columns of the accuracy study and of its cheapest settings.
ACCURACY_COLUMNS = ("case", "maxh", "order", "ndof", "newton", "tangents", "solve_s", "error")
CHEAPEST_COLUMNS = ("case", "target", "setting", "solve_s")


def error(scene: str, results: Results) -> float:
    """The error measure of a scene's :class:`~ngincompat.workflow.results.Results`: relative energy
    error against :data:`CUBE_ENERGY` (cube), largest Cauchy-stress error against the 1-D
    radial solution relative to the largest stress (hemisphere), strain energy over
    mu |B| (a L)^2, which must vanish (cylinder)."""
    m = results.metrics
    if scene == "cube":
        return abs(m["strain_energy"] - CUBE_ENERGY) / CUBE_ENERGY
    if scene == "hemisphere":
        return max(m["radial_sigma_rr_error"], m["radial_sigma_thetatheta_error"])
    p = results.params
    return m["strain_energy"] / (p["mu"] * p["area"] * p["length"] * (p["a"] * p["length"]) ** 2)


def accuracy_table(out: str | os.PathLike | None = None,
                   study: Mapping[str, tuple[str, list[dict[str, Any]]]] | None = None
                   ) -> list[dict[str, Any]]:
    """Run every setting of the accuracy ``study`` (default :data:`ACCURACY`); returns rows
    with the columns :data:`ACCURACY_COLUMNS`. With ``out`` each run writes its results.json
    into ``out/runs/<case>_<settings>``."""
    rows = []
    for case, (name, grid) in (ACCURACY if study is None else study).items():
        for settings in grid:
            label = "_".join(f"{k}{v}" for k, v in settings.items()
                             if k in ("maxh", "centre_maxh", "order"))
            r = _run(get_scene(name)(outputs="none",  # type: ignore[arg-type]  # converted
                                     **settings), out, f"{case}_{label}")
            rows.append({"case": case, "maxh": settings["maxh"], "order": settings["order"],
                         "ndof": r.mesh.ndof, "newton": r.newton_iterations,
                         "tangents": sum(h.tangent_assemblies for h in r.solver.values()),
                         "solve_s": r.solve_seconds, "error": error(name, r)})
    return rows


def cheapest(rows: Sequence[dict[str, Any]], case: str,
             target: float) -> dict[str, Any] | None:
    """The fastest row of ``case`` whose error is at most ``target``, or None."""
    ok = [r for r in rows if r["case"] == case and r["error"] <= target]
    return min(ok, key=lambda r: r["solve_s"]) if ok else None


def cheapest_rows(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """For every case and target of :data:`TARGETS`: the cheapest setting that meets it."""
    table = []
    for case in dict.fromkeys(r["case"] for r in rows):
        for target in TARGETS:
            best = cheapest(rows, case, target)
            table.append({"case": case, "target": target,
                          "setting": (f"maxh {best['maxh']:g}, order {best['order']}" if best
                                      else "none in the grid"),
                          "solve_s": best["solve_s"] if best else None})
    return table


def accuracy_main(out: str | os.PathLike | None = None, quick: bool = False) -> list[str]:
    """``ngincompat bench accuracy``: run the study (``quick``: :data:`QUICK_ACCURACY`);
    returns the lines to print.

    With ``out``: the runs' results, the tables ``accuracy`` and ``accuracy_cheapest``
    (markdown, CSV, JSON) and one plot of error against solve time per case.
    """
    rows = accuracy_table(out, QUICK_ACCURACY if quick else None)
    best = cheapest_rows(rows)
    lines = [tables.markdown(rows, list(ACCURACY_COLUMNS), UNITS), "",
             tables.markdown(best, list(CHEAPEST_COLUMNS), UNITS)]
    if out is not None:
        tables.write(out, "accuracy", rows, list(ACCURACY_COLUMNS), UNITS)
        tables.write(out, "accuracy_cheapest", best, list(CHEAPEST_COLUMNS), UNITS)
        for case in dict.fromkeys(r["case"] for r in rows):
            curves = {}
            for order in sorted({r["order"] for r in rows if r["case"] == case}):
                curves[f"order {order}"] = sorted((r["solve_s"], r["error"]) for r in rows
                                                  if r["case"] == case and r["order"] == order)
            plots.error_against_time(Path(out) / f"accuracy_{case}.png", curves,
                                     title=f"{case}: error against solve time")
        lines.append(f"plots and tables written to {out}")
    return lines
