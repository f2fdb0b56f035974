"""Matplotlib figures in the style of the paper's profile panels (e.g. Fig. 1g).

Every figure is made without pyplot, so importing this module never changes matplotlib's
backend (notebooks keep their inline figures), and written atomically. Curves on one axis
differ in colour, line style and marker, so curves that coincide (S22 and S33 of the cube)
stay visible; a curve of few points (:data:`FEW`) carries a marker at every point, so a
single point shows; every curve is in the legend, even alone; titles are wrapped to the
figure's width instead of clipped; tick labels never use an offset or a multiplier over the
axis (three significant digits each instead); and every axis spans at least ``RELATIVE_FLOOR`` of
its largest absolute value and at least the figure's own ``floor`` (a scene sets it from its
stress scale), so round-off around a constant (Curl Fg : Curl Fg = 1/16 in the cylinder) or
the discretisation error of a stress-free body is drawn flat, not magnified into apparent
oscillation.
"""

import functools
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from itertools import cycle
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import QuadMesh
from matplotlib.figure import Figure
from matplotlib.image import AxesImage
from matplotlib.lines import Line2D

from ngincompat.atomic import atomic_path
from ngincompat.workflow import surface
from ngincompat.workflow.results import (
    DeformedFigure,
    MapsFigure,
    ProfileFigure,
    Results,
    SurfaceFigure,
)
from ngincompat.workflow.results import Figure as FigureSpec
from ngincompat.workflow.style import (
    MAP_CLIP,
    RELATIVE_FLOOR,
    colour_scale,
    extend,
    tick_format,
    wrapped,
)

#: Curves of at most this many points get a marker at every point.
FEW = 25


#: (line style, marker) per curve, in order: coinciding curves stay distinguishable.
STYLES = (("-", None), ("--", "o"), (":", "s"), ("-.", "^"), ((0, (5, 1, 1, 1)), "v"),
          ((0, (1, 1)), "D"))


def profile_figure(x: np.ndarray, curves: Mapping[str, np.ndarray], xlabel: str, ylabel: str,
                   title: str | None = None, right: Mapping[str, np.ndarray] | None = None,
                   right_label: str = "", floor: float = 0.0, right_floor: float = 0.0,
                   vlines: Mapping[str, float] | None = None) -> Figure:
    """A matplotlib Figure of curves against one coordinate.

    Parameters
    ----------
    x : array
        The coordinate.
    curves : dict
        Legend label -> values, on the left axis.
    xlabel, ylabel : str
        Axis labels with units.
    title : str, optional
    right : dict, optional
        Legend label -> values on a second axis (labelled ``right_label``).
    floor, right_floor : float
        Smallest range of the left and the right axis.
    vlines : dict, optional
        Legend label -> abscissa of a dashed vertical line.
    """
    fig = Figure(figsize=(5.4, 3.8), dpi=120)
    ax = fig.subplots()
    styles = cycle(STYLES)
    lines = _plot(ax, x, curves, styles, colours=None)
    lines += [ax.axvline(at, ls="--", lw=1, color="0.3", label=label)
              for label, at in (vlines or {}).items()]
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    _floor(ax, curves.values(), floor)
    _numbers(ax)
    if right:
        twin = ax.twinx()
        lines += _plot(twin, x, right, styles, colours=["tab:red", "tab:purple", "tab:brown"])
        twin.set_ylabel(right_label)
        _floor(twin, right.values(), right_floor)
        _numbers(twin)
    if lines:
        ax.legend(lines, [line.get_label() for line in lines],  # type: ignore[misc]
                  fontsize="small")
    if title:
        ax.set_title(wrapped(title, fig.get_figwidth()), fontsize="medium")
    fig.tight_layout()
    return fig


def _plot(ax: Axes, x: np.ndarray, curves: Mapping[str, np.ndarray],
          styles: Iterator[tuple[Any, str | None]],
          colours: Sequence[str] | None) -> list[Line2D]:
    lines = []
    n = len(np.atleast_1d(x))
    for i, (label, values) in enumerate(curves.items()):
        style, marker = next(styles)
        kwargs: dict[str, Any] = {"color": colours[i % len(colours)]} if colours else {}
        if n <= FEW:
            marker = marker or "o"
        (line,) = ax.plot(x, values, lw=2, ls=style, marker=marker,
                          markevery=1 if n <= FEW else max(1, n // 10), markersize=4,
                          label=label, **kwargs)
        lines.append(line)
    return lines


def _numbers(ax: Axes) -> None:
    """Tick labels of :func:`tick_format` on both linear axes (of the limits the data set
    now; :func:`_floor` may widen them later, which only lowers the digits needed)."""
    for axis, limits in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if axis.get_scale() == "linear":
            axis.set_major_formatter(tick_format(*limits))


def _floor(ax: Axes, values: Iterable[np.ndarray], floor: float) -> None:
    """Widen the y range of ``ax`` to at least ``floor`` and ``RELATIVE_FLOOR`` of the largest
    absolute value, around the data's middle."""
    values = list(values)
    data = np.concatenate([np.ravel(v) for v in values]) if values else np.zeros(0)
    data = data[np.isfinite(data)]
    if data.size == 0:
        return
    floor = max(floor, RELATIVE_FLOOR * float(np.max(np.abs(data))))
    if floor <= 0:
        return
    lo, hi = float(data.min()), float(data.max())
    if hi - lo < floor:
        mid = (hi + lo) / 2
        ax.set_ylim(mid - floor / 2, mid + floor / 2)


def draw(results: Results, spec: FigureSpec, path: str | os.PathLike) -> None:
    """Write the figure ``spec`` (a :class:`~ngincompat.workflow.results.Figure`) of ``results``."""
    save(figure(results, spec), path)


def figure(results: Results, spec: FigureSpec) -> Figure:
    """The matplotlib Figure of ``spec`` drawn from the profiles of ``results``: by the
    drawing registered for its kind (:func:`drawn`)."""
    return drawn(spec, results.profiles[spec.profile], results.metrics)


@functools.singledispatch
def drawn(spec: FigureSpec, profile: Mapping[str, np.ndarray],
          metrics: Mapping[str, float]) -> Figure:
    """The matplotlib Figure of ``spec`` from its ``profile`` (and the run's ``metrics``),
    one drawing per kind of :class:`~ngincompat.workflow.results.Figure`."""
    raise TypeError(f"no drawing for a figure of kind {type(spec).__name__}")


@drawn.register
def _(spec: ProfileFigure, p: Mapping[str, np.ndarray], metrics: Mapping[str, float]) -> Figure:
    return profile_figure(p[spec.x], {label: p[k] for label, k in spec.curves.items()},
                          spec.xlabel, spec.ylabel, spec.title,
                          right={label: p[k] for label, k in spec.right.items()},
                          right_label=spec.right_label, floor=spec.floor,
                          right_floor=spec.right_floor,
                          vlines={label.format(value=metrics[k]): metrics[k]
                                  for label, k in spec.marks.items()
                                  if np.isfinite(metrics.get(k, np.nan))})


@drawn.register
def _(spec: MapsFigure, p: Mapping[str, np.ndarray], metrics: Mapping[str, float]) -> Figure:
    return maps_figure(p, spec.curves, spec.xlabel, spec.title,
                       {label: p[key] for label, key in spec.arrows.items()})


@drawn.register
def _(spec: DeformedFigure, p: Mapping[str, np.ndarray], metrics: Mapping[str, float]) -> Figure:
    panels = {label: (key, spec.deform[label]) for label, key in spec.curves.items()}
    return deformed_figure({"": p}, panels, (spec.x, spec.y), spec.xlabel, spec.ylabel,
                           spec.title, floor=spec.floor)


@drawn.register
def _(spec: SurfaceFigure, p: Mapping[str, np.ndarray], metrics: Mapping[str, float]) -> Figure:
    panels = [surface.Panel(label, p[key], signed=None, clip=MAP_CLIP,
                            u=p[spec.deform[label]] if label in spec.deform else None)
              for label, key in spec.curves.items()]
    return surface.triangulated_figure(p["points"], p["triangles"], panels, spec.title,
                                       spec.xlabel, view=spec.view)


def maps_figure(profile: Mapping[str, np.ndarray], maps: Mapping[str, str], label: str,
                title: str | None = None, arrows: Mapping[str, np.ndarray] | None = None) -> Figure:
    """Colour maps of 2-D fields on planar sections, each with its colour bar.

    Parameters
    ----------
    profile : dict
        Holds, for every key "<plane>_<field>" of ``maps``, a 2-D array of values (NaN
        outside the body) and the grid's axes "<plane>_u" (columns) and "<plane>_v" (rows).
    maps : dict
        Panel title -> key; one row per plane, one column per field, in order.
    label : str
        Unit of the in-plane coordinates, for the axes.
    arrows : dict, optional
        Panel title -> array of the grid's shape with 2 components along its axes: a vector
        field in the plane, drawn over the panel's map as arrows (:func:`_quiver`).
    """
    keys = list(maps.values())
    planes = list(dict.fromkeys(k.split("_", 1)[0] for k in keys))
    ncols = len(keys) // len(planes)
    fig = Figure(figsize=(4.2 * ncols, 3.4 * len(planes)), dpi=110)
    axes = np.atleast_2d(fig.subplots(len(planes), ncols, squeeze=False))
    for ax, (panel, key) in zip(axes.ravel(), maps.items(), strict=True):
        plane = key.split("_", 1)[0]
        u, v = profile[f"{plane}_u"], profile[f"{plane}_v"]
        values = np.ma.masked_invalid(profile[key])
        norm, cmap = colour_scale(values, clip=MAP_CLIP)
        image = ax.imshow(values, origin="lower", extent=(u[0], u[-1], v[0], v[-1]),
                          interpolation="nearest", norm=norm, cmap=cmap)
        if arrows and panel in arrows:
            _quiver(ax, u, v, np.asarray(arrows[panel], dtype=float))
        _panel(fig, ax, image, wrapped(panel, 3.6, 11), label)
    if title:
        fig.suptitle(wrapped(title, fig.get_figwidth(), 12), fontsize="large")
    fig.tight_layout()
    return fig


#: Arrows per side of a map's grid (:func:`_quiver`).
QUIVER = 20
#: Arrows shorter than this share of the longest are left out: no dots where the field is
#: small.
QUIVER_FLOOR = 0.2


def _quiver(ax: Axes, u: np.ndarray, v: np.ndarray, vectors: np.ndarray) -> None:
    """The in-plane vector field ``vectors`` (rows, columns, 2) on the grid ``u`` x ``v``
    as arrows on :data:`QUIVER` x :data:`QUIVER` of its points, all scaled by one factor
    (the longest 7 % of the wider axis), those below :data:`QUIVER_FLOOR` of the
    longest left out."""
    rows = np.linspace(0, len(v) - 1, QUIVER).round().astype(int)
    cols = np.linspace(0, len(u) - 1, QUIVER).round().astype(int)
    picked = vectors[np.ix_(rows, cols)]
    length = np.linalg.norm(picked, axis=-1)
    longest = np.nanmax(length, initial=0.0)
    if not longest > 0:
        return
    keep = np.isfinite(length) & (length >= QUIVER_FLOOR * longest)
    U, V = np.meshgrid(u[cols], v[rows])
    scale = 0.07 * max(u[-1] - u[0], v[-1] - v[0]) / longest
    ax.quiver(U[keep], V[keep], scale * picked[..., 0][keep], scale * picked[..., 1][keep],
              angles="xy", scale_units="xy", scale=1.0, color="black", width=0.004,
              headwidth=3.5, pivot="middle")


def deformed_figure(rows: Mapping[str, Mapping[str, np.ndarray]],
                    panels: Mapping[str, tuple[str, str]], axes: tuple[str, str], xlabel: str,
                    ylabel: str, title: str | None = None, floor: float = 0.0) -> Figure:
    """Fields on the deformed shape: one row per body, one column per field (Fig. 7 a-c).

    Parameters
    ----------
    rows : dict
        Row label (e.g. the axon field; "" for none) -> profile holding the reference grid's
        axes, the 2-D arrays of the fields and the displacements.
    panels : dict
        Column label (field and unit) -> (field key, displacement key). A field of shape
        (rows, columns) is drawn on the grid moved by the displacement, an array of shape
        (rows, columns, 2) of its components along the grid's two axes. A column is left out
        when a row's profile lacks one of its keys (e.g. a run without the release).
    axes : (str, str)
        Keys of the grid's axes in the profile: the reference coordinates along the columns
        and the rows of the arrays.
    xlabel, ylabel : str
        Axis labels with units.
    floor : float
        Smallest range of a colour scale (as for the profiles' axes, besides
        ``RELATIVE_FLOOR`` of the largest value): round-off is drawn flat.

    Every column has one colour scale for all rows (so the rows compare); a field of both
    signs (a stress) gets a diverging scale centred on zero, which leaves :data:`MAP_CLIP`
    per cent of the values beyond its ends where they are peaks (a crease tip's stress would
    wash out the rest; the colour bar's arrows say so). A field of one sign spans its range:
    one row's larger growth is not a peak to clip.
    """
    panels = {label: keys for label, keys in panels.items()
              if all(k in p for p in rows.values() for k in keys)}
    ncols = max(len(panels), 1)
    aspect = max((_deformed_aspect(p, axes, disp) for p in rows.values()
                  for _, disp in panels.values()), default=1.0)
    fig = Figure(figsize=(4.6 * ncols, 0.5 + len(rows) * (1.0 + 3.4 * aspect)), dpi=110)
    grid = np.atleast_2d(fig.subplots(len(rows), ncols, squeeze=False))
    for col, (label, (key, disp)) in enumerate(panels.items()):
        values = np.concatenate([np.ravel(p[key]) for p in rows.values()])
        signed = np.nanmin(values) < 0 < np.nanmax(values)
        norm, cmap = colour_scale(values, floor=floor, clip=MAP_CLIP if signed else 0.0)
        for row, (name, p) in enumerate(rows.items()):
            ax = grid[row, col]
            U, V = np.meshgrid(p[axes[0]], p[axes[1]])
            d = np.asarray(p[disp])
            image = ax.pcolormesh(U + d[..., 0], V + d[..., 1],
                                  np.ma.masked_invalid(p[key]), shading="gouraud",
                                  cmap=cmap, norm=norm)
            ax.set_aspect("equal")
            _panel(fig, ax, image, f"{name}: {label}" if name else label, xlabel, ylabel)
    if title:
        fig.suptitle(wrapped(title, fig.get_figwidth(), 12), fontsize="large")
    fig.tight_layout(h_pad=1.5)    # a row's axis label clear of the next row's title
    return fig


def _deformed_aspect(profile: Mapping[str, np.ndarray], axes: tuple[str, str], disp: str) -> float:
    """Height over width of the grid of ``profile`` moved by its displacement ``disp``: the
    deformed body (a fold, a released bilayer) can be taller than the reference one."""
    U, V = np.meshgrid(profile[axes[0]], profile[axes[1]])
    d = np.asarray(profile[disp])
    x, y = U + d[..., 0], V + d[..., 1]
    return (np.nanmax(y) - np.nanmin(y)) / max(np.nanmax(x) - np.nanmin(x), 1e-300)


def _panel(fig: Figure, ax: Axes, image: AxesImage | QuadMesh, title: str, xlabel: str,
           ylabel: str | None = None) -> None:
    """A colour map's colour bar (three-digit ticks; an arrow at an end beyond which values
    lie), title (broken into lines as wide as the axes, clear of the colour bar's arrow) and
    axis labels."""
    fig.colorbar(image, ax=ax, shrink=0.85, format=tick_format(*image.get_clim()),
                 extend=extend(image.get_array(), image.norm))  # type: ignore[arg-type]
    ax.set_title(wrapped(title, ax.get_position().width * fig.get_figwidth(), 10),
                 fontsize="medium")
    ax.set_xlabel(xlabel, fontsize="small")
    if ylabel:
        ax.set_ylabel(ylabel, fontsize="small")
    ax.tick_params(labelsize="small")


def profiles(path: str | os.PathLike, s: np.ndarray, curves: Mapping[str, np.ndarray],
             xlabel: str, ylabel: str, title: str | None = None, floor: float = 0.0) -> None:
    """Several curves against one coordinate on one axis; ``curves`` maps label -> values."""
    save(profile_figure(s, curves, xlabel, ylabel, title, floor=floor), path)


def curves_figure(curves: Mapping[str, Sequence[Sequence[float] | np.ndarray]], xlabel: str,
                  ylabel: str, title: str | None = None, logx: bool = False,
                  logy: bool = False, markevery: int = 1,
                  vlines: Mapping[str, float] | None = None,
                  colours: Sequence[str] | None = None) -> Figure:
    """A matplotlib Figure of curves with their own abscissae, each with markers.

    Parameters
    ----------
    curves : dict
        Legend label -> (x values, y values); an empty label is left out of the legend.
    xlabel, ylabel : str
        Axis labels with units.
    title : str, optional
    logx, logy : bool
        Logarithmic axes.
    markevery : int
        A marker on every this many points.
    vlines : dict, optional
        Label -> abscissa of a vertical dashed line (e.g. the onset of an instability).
    colours : list, optional
        A colour per curve (e.g. one per quantity, computed and reference alike).
    """
    fig = Figure(figsize=(5.4, 3.8), dpi=120)
    ax = fig.subplots()
    x: Sequence[float] | np.ndarray | float     # a curve's abscissae, then a line's
    for i, ((label, (x, y)), (style, marker)) in enumerate(zip(curves.items(), cycle(STYLES))):
        kwargs: dict[str, Any] = {"color": colours[i]} if colours else {}
        ax.plot(x, y, ls=style, marker=marker or "o", lw=2, label=label or None,
                markevery=markevery, markersize=4, **kwargs)
    for (label, x), colour in zip((vlines or {}).items(), cycle(("0.3", "tab:red"))):
        ax.axvline(x, ls="--", lw=1, color=colour, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    _numbers(ax)
    if any(curves) or vlines:
        ax.legend(fontsize="small")
    if title:
        ax.set_title(wrapped(title, fig.get_figwidth()), fontsize="medium")
    fig.tight_layout()
    return fig


def error_against_time(path: str | os.PathLike, curves: Mapping[str, Sequence[Sequence[float]]],
                       title: str | None = None) -> None:
    """Error against run time on log-log axes; ``curves`` maps a label to (time, error) pairs."""
    curves = {label: ([p[0] for p in pts], [max(p[1], 1e-16) for p in pts])
              for label, pts in curves.items()}
    save(curves_figure(curves, "solve time [s]", "relative error [-]", title, logx=True,
                       logy=True), path)


def save(fig: Figure, path: str | os.PathLike) -> None:
    """Write a figure as PNG, atomically."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
