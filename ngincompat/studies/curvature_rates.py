"""Convergence of the discrete curvature (Regge path) to the exact one, with cost.

For the hemisphere and the disc geometries of the paper, with smooth versions of their
growth fields (isotropic theta = 1 + R^2/4, area growth theta = 1 + (X1^2 + X2^2)/4 about e3:
the scenes' linear profiles have a cone point or a cone line where Ein ~ 1/R, which caps
every rate near 1), the Regge interpolant of degree k of Cg is compared with the exact
curvature (:func:`ngincompat.incompatibility.curvature.growth_curvature`) in three measures:

* ``pairing``: |G~(phi) - G(phi)| / |G(phi)| for a fixed smooth test field phi vanishing on
  the boundary; bounded by the H^-2 error, so it converges at least as h^(k+1) (Gawlik &
  Neunteufel 2025);
* ``lift``: relative L2 error of the lifted Einstein tensor (Lagrange degree k);
* ``elementwise``: relative L2 error of the element-wise Einstein tensor, h^(k-1).

Meshes are refined uniformly (every tetrahedron split in eight, new boundary points on the
geometry), so h halves exactly; rates are log2 of the ratio of successive errors.

``ngincompat bench curvature [--quick] [--out DIR]`` runs the study (:func:`main`).
"""

import os
import time
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import netgen.meshing
import ngsolve as ngs
import numpy as np

from geometries import disc, hemisphere
from ngincompat import config
from ngincompat.errors import ParameterError
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility import regge
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import AreaGrowth, IsotropicGrowth
from ngincompat.workflow import plots, tables

#: Columns of :func:`rate_table` and their units.
COLUMNS = ("body", "k", "level", "ne", "pairing", "lift", "elementwise", "seconds")
UNITS = {"pairing": "-", "lift": "-", "elementwise": "-",
         "seconds": "s"}
#: What ``--quick`` runs (seconds): the coarse hemisphere for k = 1, 2, no refinement.
QUICK: dict[str, Any] = {"names": ("hemisphere",), "orders": (1, 2), "levels": 1}
#: Published rates in h for Regge degree k (distributional Einstein in H^-2, element-wise
#: curvature in L2).
PUBLISHED = {"pairing": lambda k: k + 1, "elementwise": lambda k: k - 1}


def bodies() -> dict[str, tuple[netgen.meshing.Mesh, ngs.CoefficientFunction,
                                ngs.CoefficientFunction]]:
    """name -> (netgen mesh of the body, growth tensor Fg, test-field bubble vanishing on the
    boundary)."""
    X = ngs.CF((ngs.x, ngs.y, ngs.z))
    r2 = ngs.x * ngs.x + ngs.y * ngs.y
    return {
        "hemisphere": (hemisphere(maxh=0.5, curve_order=1, centre_maxh=0.5).ngmesh,
                       IsotropicGrowth(1 + ngs.InnerProduct(X, X) / 4).Fg,
                       (1 - ngs.InnerProduct(X, X)) * ngs.z),
        "disc": (disc(maxh=0.5, curve_order=1).ngmesh,
                 AreaGrowth(1 + r2 / 4, fields.constant("e3")).Fg,
                 (1 - r2) * ngs.z * (0.5 - ngs.z)),
    }


def errors(mesh: ngs.Mesh, Fg: ngs.CoefficientFunction, bubble: ngs.CoefficientFunction,
           k: int) -> dict[str, float]:
    """The three relative errors of the Regge path of degree k against the exact path."""
    exact = cv.growth_curvature(Fg)
    g = exact.metric
    g_inv = ngs.Inv(g)
    phi = bubble * ngs.CF((1, 0.3, 0.2, 0.3, 2, 0.1, 0.2, 0.1, 1), dims=(3, 3))
    density = ngs.sqrt(ngs.Det(g)) * g_inv * exact.einstein * g_inv
    reference = ngs.Integrate(ngs.InnerProduct(density, phi), mesh, order=2 * k + 6)
    gh = regge.regge_interpolant(g, mesh, k)
    pairing = abs(regge.DistributionalEinstein.of(gh).apply(phi) - reference) / abs(reference)
    discrete = regge.discrete_curvature(g, mesh, k)

    def rel(a: ngs.CoefficientFunction) -> float:
        d = a - exact.einstein
        return (ngs.Integrate(ngs.InnerProduct(d, d), mesh, order=2 * k + 4)
                / ngs.Integrate(ngs.InnerProduct(exact.einstein, exact.einstein), mesh,
                                order=2 * k + 4)) ** 0.5

    return {"pairing": float(pairing), "lift": float(rel(discrete.einstein)),
            "elementwise": float(rel(discrete.einstein_elementwise))}


def rate_table(names: Iterable[str] = ("hemisphere", "disc"), orders: Sequence[int] = (1, 2, 3),
               levels: int = 2) -> list[dict[str, Any]]:
    """One row per (body, k, refinement level), coarsest first, with the columns
    :data:`COLUMNS`; the meshes are curved to degree 2."""
    config.ensure_heap(10**8)
    rows = []
    for name in names:
        ngmesh, Fg, bubble = bodies()[name]
        for level in range(levels):
            if level:
                ngmesh.Refine()
            mesh = ngs.Mesh(ngmesh)
            mesh.Curve(2)
            for k in orders:
                start = time.perf_counter()
                with config.task_manager():
                    row = errors(mesh, Fg, bubble, k)
                rows.append({"body": name, "k": k, "level": level, "ne": mesh.ne,
                             **row, "seconds": time.perf_counter() - start})
    return rows


def rates(rows: Sequence[Mapping[str, Any]],
          measure: str) -> dict[tuple[str, int], list[float]]:
    """(body, k) -> the rates of ``measure`` between successive meshes, for the degrees k
    each body was run at."""
    out = {}
    for body in dict.fromkeys(r["body"] for r in rows):
        for k in sorted({r["k"] for r in rows if r["body"] == body}):
            sel = sorted((r for r in rows if r["body"] == body and r["k"] == k),
                         key=lambda r: r["level"])
            out[body, k] = [float(np.log2(a[measure] / b[measure]))
                            for a, b in zip(sel[:-1], sel[1:], strict=True)]
    return out


def rate_summary(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Rows (body, k, measure, measured rates, published rate) for the table of rates
    (``docs/measurements/curvature.md``)."""
    summary = []
    for measure in ("pairing", "lift", "elementwise"):
        for (body, k), values in rates(rows, measure).items():
            published = PUBLISHED.get(measure)
            summary.append({"body": body, "k": k, "measure": measure,
                            "rates": ", ".join(f"{v:.2f}" for v in values),
                            "published": "-" if published is None else published(k)})
    return summary


def main(out: str | os.PathLike | None = None, quick: bool = False,
         names: Iterable[str] | None = None, orders: Iterable[int] | None = None) -> list[str]:
    """``ngincompat bench curvature``: the error of the discrete path against its cost, and
    the rates against the published ones; returns the lines to print. With ``out``: the
    tables ``curvature_rates`` and ``curvature_rate_summary`` (markdown, CSV, JSON) and one
    plot per body of the lifted Einstein tensor's error against computing time per k.

    ``names``, ``orders``: the bodies (of :func:`bodies`) and Regge degrees k of
    :func:`rate_table` (default: all of them, or those of :data:`QUICK`)."""
    grid = dict(QUICK) if quick else {}
    grid.update({key: tuple(value) for key, value in (("names", names), ("orders", orders))
                 if value})
    for name in grid.get("names", ()):
        if name not in bodies():
            raise ParameterError(f"--bodies {name!r}: allowed {', '.join(bodies())}")
    rows = rate_table(**grid)
    summary = rate_summary(rows)
    lines = [tables.markdown(rows, list(COLUMNS), UNITS)]
    if any(row["rates"] for row in summary):
        lines += ["", tables.markdown(summary)]
    if out is not None:
        tables.write(out, "curvature_rates", rows, list(COLUMNS), UNITS)
        tables.write(out, "curvature_rate_summary", summary)
        for body in dict.fromkeys(row["body"] for row in rows):
            curves = {f"k = {k}": sorted((row["seconds"], row["lift"]) for row in rows
                                         if row["body"] == body and row["k"] == k)
                      for k in sorted({row["k"] for row in rows})}
            plots.error_against_time(Path(out) / f"curvature_{body}.png", curves,
                                     title=f"{body}: lifted Einstein tensor, error against "
                                           "time")
        lines.append(f"plots and tables written to {out}")
    return lines
