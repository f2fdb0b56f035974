"""Points at which fields are checked or maximised: integration points and vertices, and the
largest value of a field over them (over all ranks of a distributed mesh)."""

from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat import parallel

_VERTICES: dict[Any, list[tuple[int, ...]]] = {
    ngs.ET.TET: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
    ngs.ET.HEX: [(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)],
    ngs.ET.PRISM: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)],
    ngs.ET.PYRAMID: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1)],
    ngs.ET.TRIG: [(0, 0), (1, 0), (0, 1)],
    ngs.ET.QUAD: [(0, 0), (1, 0), (1, 1), (0, 1)],
}


def element_points(mesh: ngs.Mesh, order: int = 4, vb: ngs.comp.VorB = ngs.VOL) -> Any:
    """The points of an integration rule of ``order`` plus the vertices, in every volume element
    (``vb`` = ``ngs.BND``: every boundary element).

    Returns the mapped points (evaluate a CoefficientFunction ``cf`` there with ``cf(points)``).
    """
    rules = {}
    for et in {el.type for el in mesh.Elements(vb)}:
        ir = ngs.IntegrationRule(et, order)
        verts = _VERTICES[et]
        rules[et] = ngs.IntegrationRule([tuple(p) for p in ir.points] + verts,
                                        list(ir.weights) + [0.0] * len(verts))
    return mesh.MapToAllElements(rules, vb)


def element_boxes(mesh: ngs.Mesh, order: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, hi)``, each (n, 3): a box around every volume element, the bounding box of the
    points of :func:`element_points`: the vertices and an integration rule of ``order``. It
    holds a straight-sided element exactly; of a curved one it misses the bulge of its faces
    between those points (not widened: a box reaching out of the body would be checked where
    the growth need not be defined, e.g. sqrt(X1) left of X1 = 0)."""
    xyz = ngs.CF((ngs.x, ngs.y, ngs.z))
    lows, highs = [], []
    for et in {el.type for el in mesh.Elements(ngs.VOL)}:
        ir = ngs.IntegrationRule(et, order)
        rule = ngs.IntegrationRule([tuple(p) for p in ir.points] + _VERTICES[et],
                                   [0.0] * (len(ir.points) + len(_VERTICES[et])))
        points = np.asarray(xyz(mesh.MapToAllElements({et: rule}, ngs.VOL)))
        points = points.reshape(-1, len(rule.points), 3)
        lows.append(points.min(axis=1))
        highs.append(points.max(axis=1))
    return np.concatenate(lows), np.concatenate(highs)


def argmax(cf: ngs.CoefficientFunction, mesh: ngs.Mesh,
           order: int = 4) -> tuple[float, tuple[float, ...]]:
    """The largest value of a scalar CF over the integration points and vertices of a serial
    mesh (see :func:`maximum`) and the point (X1, X2, X3) where it is."""
    points = element_points(mesh, order)
    values = np.asarray(cf(points)).ravel()
    i = int(np.nanargmax(values))
    where = np.asarray(ngs.CF((ngs.x, ngs.y, ngs.z))(points)).reshape(-1, 3)[i]
    return float(values[i]), tuple(float(c) for c in where)


def maximum(cf: ngs.CoefficientFunction, mesh: ngs.Mesh, order: int = 4) -> float:
    """Largest value of a scalar CF over the integration points and vertices of the mesh
    (of all ranks of a distributed mesh).

    Points where the CF is undefined (NaN) are left out: a vertex can sit on a cone point of
    an analytic growth field, e.g. the centre of theta = 1 + R t / 4, a vertex of the quarter
    hemisphere. NaN only if the CF is undefined at every point."""
    values = np.asarray(cf(element_points(mesh, order))) if mesh.ne else np.empty(0)
    defined = values[~np.isnan(values)]
    local = np.nan if values.size and not defined.size else np.max(defined, initial=-np.inf)
    return parallel.maximum(mesh, local)
