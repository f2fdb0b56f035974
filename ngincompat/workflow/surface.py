"""Colour maps of fields on the (deformed) surface of a body, drawn headless with matplotlib
(the paper's contour plots, Figs. 1a-f, 2a-e, 3a-d, 4a-e, 5, 6): the one surface renderer
of the package, fed in either of two ways.

* From a mesh and its fields (:func:`surface_figure`, the paper job's field figures): the
  boundary is triangulated (a quadrilateral face in two triangles), every triangle
  subdivided so that high-order fields show their variation inside an element, and each
  field and displacement evaluated at the corners of the small triangles.
* From a triangulated surface and values at its points (:func:`triangulated_figure`, the
  brain's Fig. 5 a-c from results.json, gathered over the ranks of a distributed run).

A triangle is coloured by the mean of its corners, and drawn at its corners moved by the
panel's displacement (the deformed configuration of the paper's figures). A panel may also
draw a vector field as arrows (the paper's Burgers vectors, Figs. 2b-c, 3b, 6b): at
:data:`ARROWS` points spread over the part of the surface that faces the camera, each arrow
scaled by the same factor, the longest :data:`ARROW_LENGTH` of the body's size. Matplotlib's 3-D
axes sort the triangles by depth, which draws convex bodies (cube, hemisphere, disc,
cylinder, the brain seen from outside) correctly. Colour scales:
:func:`ngincompat.workflow.style.colour_scale`; every panel has its own colour bar with the
field's unit, and axes in the length unit.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from matplotlib import cm
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from mpl_toolkits.mplot3d.axes3d import Axes3D

from ngincompat.workflow.style import colour_scale, extend, tick_format, wrapped

#: Triangles per panel the subdivision aims at (finer looks no different at the figure's size).
TRIANGLES = 12000
#: Arrows per panel that draws a vector field, at most.
ARROWS = 120
#: The longest arrow, as a fraction of the body's largest extent.
ARROW_LENGTH = 0.12
#: A triangle carries an arrow where its outward unit normal has at least this component
#: toward the camera (a face seen edge-on carries none).
FACING = 0.2


@dataclass
class Panel:
    """One colour map: ``title`` (the quantity and its unit), the ``field`` (a
    CoefficientFunction for :func:`surface_figure`, values at the points for
    :func:`triangulated_figure`), whether it is a signed quantity (a stress component: a
    diverging map centred at zero whatever its values; None: if its values take both
    signs), the smallest range of its scale, the per cent of values left beyond each end
    of the scale, the displacement it is drawn on (as ``field``; None: the figure's for
    :func:`surface_figure`, the reference surface for :func:`triangulated_figure`), and a
    vector field drawn over the map as arrows (a CoefficientFunction with three components;
    :func:`surface_figure` only)."""

    title: str
    field: object
    signed: bool | None = False
    floor: float = 0.0
    u: object = None
    clip: float = 0.0
    arrows: object = None


def boundary_triangles(mesh: ngs.Mesh, subdivision: int) -> np.ndarray:
    """Corners of the boundary's triangles, each face cut into ``subdivision**2`` triangles.

    Returns an array of shape (n, 3, 3): n triangles, three corners, three coordinates."""
    k = subdivision
    # barycentric corners of the k^2 small triangles of the unit triangle
    corners = []
    for i in range(k):
        for j in range(k - i):
            corners.append(((i, j), (i + 1, j), (i, j + 1)))
            if i + j + 1 < k:
                corners.append(((i + 1, j), (i + 1, j + 1), (i, j + 1)))
    small = np.asarray(corners, float) / k                   # (m, 3, 2): (l1, l2) per corner
    out = []
    for el in mesh.Elements(ngs.BND):
        p = np.array([mesh[v].point for v in el.vertices])
        faces = [p[[0, 1, 2]]] if len(p) == 3 else [p[[0, 1, 2]], p[[0, 2, 3]]]
        for a, b, c in faces:
            out.append(a + small[..., :1] * (b - a) + small[..., 1:] * (c - a))
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def evaluate(mesh: ngs.Mesh, cfs: Sequence[ngs.CoefficientFunction],
             points: np.ndarray) -> list[np.ndarray]:
    """Values of ``cfs`` (a list of CoefficientFunctions) at ``points`` (n, 3); NaN where the
    mesh does not hold the point. A point on the boundary is found from inside: moved by
    1e-7 of the body's size towards the centre of the points."""
    centre = points.mean(axis=0)
    size = np.ptp(points, axis=0).max()
    inward = points + 1e-7 * size * (centre - points) / np.maximum(
        np.linalg.norm(centre - points, axis=1, keepdims=True), 1e-300)
    mips = mesh(inward[:, 0], inward[:, 1], inward[:, 2])
    inside = mips["nr"] >= 0
    values = []
    for cf in cfs:
        n = int(np.prod(cf.dims))
        v = np.full((len(points), n), np.nan)
        if inside.any():
            v[inside] = np.asarray(cf(mips[inside])).reshape(-1, n)
        values.append(v[:, 0] if n == 1 else v)
    return values


def surface_figure(mesh: ngs.Mesh, u: ngs.CoefficientFunction | None, panels: Sequence[Panel],
                   title: str, unit: str, view: tuple[float, float] = (25, -60),
                   ncols: int | None = None,
                   subdivision: int | None = None, scale: float = 1.0) -> Figure:
    """A figure of colour maps on the deformed boundary, one panel per field.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    u : CoefficientFunction or None
        The displacement (None: the reference configuration).
    panels : list of Panel
    title : str
        The figure's title (the scene and the paper's figure).
    unit : str
        Length unit of the axes.
    view : (float, float)
        Elevation and azimuth of the camera [degrees].
    ncols : int, optional
        Most panels per row (default four); the rows are balanced.
    subdivision : int, optional
        Triangles per face edge (default: enough for :data:`TRIANGLES`).
    scale : float
        Factor on the displacement.
    """
    nface = sum(1 if len(el.vertices) == 3 else 2 for el in mesh.Elements(ngs.BND))
    k = subdivision or int(np.clip(np.sqrt(TRIANGLES / max(nface, 1)), 1, 8))
    tri = boundary_triangles(mesh, k)
    points = tri.reshape(-1, 3)
    shifts = list(dict.fromkeys(p.u if p.u is not None else u for p in panels))
    values = evaluate(mesh, [p.field for p in panels], points)
    real = [d for d in shifts if d is not None]
    moved: dict[object, np.ndarray] = {None: tri}
    for d, v in zip(real, evaluate(mesh, real, points) if real else [], strict=True):
        moved[d] = np.where(np.isfinite(v), points + scale * v, points).reshape(tri.shape)
    shapes = [moved[p.u if p.u is not None else u] for p in panels]
    arrows = [None if p.arrows is None else _arrows(mesh, tri, shape, p.arrows, view)
              for p, shape in zip(panels, shapes, strict=True)]
    return _figure(panels, [v.reshape(tri.shape[:2]) for v in values], shapes, title, unit,
                   view, ncols, arrows)


def _arrows(mesh: ngs.Mesh, tri: np.ndarray, shape: np.ndarray, vectors: ngs.CoefficientFunction,
            view: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Where and which arrows a panel draws: the vector field ``vectors`` at the centres of
    up to :data:`ARROWS` of the triangles ``tri`` (reference, (m, 3, 3)) whose deformed
    ``shape`` faces the camera at ``view`` (:data:`FACING`; outward: away from the body's
    centre), spread
    evenly over them; returns the deformed centres (k, 3) and the vectors (k, 3)."""
    elevation, azimuth = np.radians(view)
    eye = np.array([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                    np.sin(elevation)])
    centres = shape.mean(axis=1)
    normal = np.cross(shape[:, 1] - shape[:, 0], shape[:, 2] - shape[:, 0])
    normal *= np.sign(np.einsum("ij,ij->i", normal, centres - centres.mean(axis=0)))[:, None]
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    seen = np.flatnonzero(normal @ eye > FACING)
    chosen = seen[np.linspace(0, len(seen) - 1, min(ARROWS, len(seen))).astype(int)] \
        if len(seen) else seen
    (values,) = evaluate(mesh, [vectors], tri[chosen].mean(axis=1))
    keep = np.all(np.isfinite(values), axis=1)
    return centres[chosen][keep], values[keep]


def triangulated_figure(points: np.ndarray, triangles: np.ndarray, panels: Sequence[Panel],
                        title: str, unit: str, view: tuple[float, float] = (10, 90),
                        ncols: int | None = None) -> Figure:
    """A figure of colour maps on a triangulated surface, one panel per field.

    Parameters
    ----------
    points : ndarray (n, 3)
    triangles : ndarray (m, 3)
        Vertex numbers into ``points``.
    panels : list of Panel
        Each ``field`` (n,) and ``u`` (n, 3) or None, at the points.
    title, unit, view, ncols
        As for :func:`surface_figure`.
    """
    points = np.asarray(points, dtype=float)
    triangles = np.asarray(triangles).astype(int)
    shapes = [points[triangles] + (np.asarray(p.u, dtype=float)[triangles]
                                   if p.u is not None else 0.0) for p in panels]
    values = [np.asarray(p.field, dtype=float)[triangles] for p in panels]
    return _figure(panels, values, shapes, title, unit, view, ncols)


def _figure(panels: Sequence[Panel], values: Sequence[np.ndarray], shapes: Sequence[np.ndarray],
            title: str, unit: str, view: tuple[float, float], ncols: int | None,
            arrows: Sequence[tuple[np.ndarray, np.ndarray] | None] | None = None) -> Figure:
    """The panels' maps: ``values`` (m, 3) at the corners of the triangles ``shapes``
    (m, 3, 3) of each panel, in balanced rows of at most ``ncols`` (default four); each
    panel's ``arrows`` (positions and vectors, or None) drawn over its map."""
    ncols = ncols or 4
    nrows = -(-len(panels) // ncols)
    ncols = -(-len(panels) // nrows)            # balanced rows: 5 panels as 3 + 2
    fig = Figure(figsize=(3.6 * ncols, 3.0 * nrows + 0.6), dpi=110)
    every = np.concatenate([shape.reshape(-1, 3) for shape in shapes])
    lo, hi = every.min(axis=0), every.max(axis=0)
    span = hi - lo
    arrows = arrows or [None] * len(panels)
    for i, (panel, v, shape, arrow) in enumerate(zip(panels, values, shapes, arrows,
                                                     strict=True)):
        ax = fig.add_subplot(nrows, ncols, i + 1, projection="3d")
        face = np.nanmean(v, axis=1)
        norm, cmap = colour_scale(face, panel.signed, panel.floor, panel.clip)
        mappable = cm.ScalarMappable(norm=norm, cmap=cmap)
        rgba = mappable.to_rgba(np.ma.masked_invalid(face))
        # edges in the face's colour: no hairline seams between the small triangles
        ax.add_collection3d(Poly3DCollection(shape, facecolors=rgba, edgecolors=rgba,
                                             linewidths=0.25))
        if arrow is not None and len(arrow[0]):
            _draw_arrows(ax, *arrow, ARROW_LENGTH * span.max())
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(np.maximum(span, 1e-3 * span.max()))
        for axis, extent in zip((ax.xaxis, ax.yaxis, ax.zaxis), span, strict=True):
            # a thin direction (the disc's, the skin's thickness) gets two ticks, not a pile
            axis.set_major_locator(MaxNLocator(2 if extent < 0.5 * span.max() else 5))
        ax.view_init(*view)
        ax.set_xlabel(f"X1 [{unit}]", fontsize="small", labelpad=-2)
        ax.set_ylabel(f"X2 [{unit}]", fontsize="small", labelpad=-2)
        ax.set_zlabel(f"X3 [{unit}]", fontsize="small", labelpad=-2)
        ax.tick_params(labelsize="x-small", pad=0)
        ax.set_title(wrapped(panel.title, 3.2), fontsize="medium")
        bar = fig.colorbar(mappable, ax=ax, shrink=0.7, pad=0.16,
                           format=tick_format(norm.vmin, norm.vmax),  # type: ignore[arg-type]
                           extend=extend(face, norm))
        bar.ax.tick_params(labelsize="small")
    fig.suptitle(title, fontsize="large")
    fig.subplots_adjust(left=0.05, right=0.95, bottom=0.03, top=0.86 if nrows == 1 else 0.92,
                        wspace=0.25, hspace=0.25)
    return fig


def _draw_arrows(ax: Axes3D, at: np.ndarray, vectors: np.ndarray, longest: float) -> None:
    """Arrows of ``vectors`` at the points ``at`` on the 3-D axes ``ax``, all scaled by one
    factor, the longest ``longest`` long; drawn over the surface (the points face the
    camera)."""
    size = np.linalg.norm(vectors, axis=1).max()
    if not size > 0:
        return
    ax.computed_zorder = False
    d = vectors * (longest / size)
    ax.quiver(at[:, 0], at[:, 1], at[:, 2], d[:, 0], d[:, 1], d[:, 2], color="black",
              linewidth=0.6, arrow_length_ratio=0.3, zorder=10)
