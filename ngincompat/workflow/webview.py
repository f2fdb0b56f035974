"""An interactive 3-D view of a field on the (deformed) body: NGSolve's webgui scene written as
one self-contained HTML page, which a reader opens from a folder and turns with the mouse,
without ParaView, Jupyter, a server or the network.

``ngsolve.webgui.Draw`` computes the scene (the boundary's triangles as Bernstein patches at
the drawing ``order``, the field's values on them, and with ``clipping`` the volume elements
too, so that a clipping plane shows the inside); its own HTML export loads the viewer's
JavaScript from a CDN when the page is opened. Here the page carries the viewer itself: the
webgui bundle (three.js and dat.gui included, LGPL-2.1) shipped in the
``webgui_jupyter_widgets`` package (``js/webgui.js``, read from the installed package's
folder, not imported: its Python side needs Jupyter). Its bundle of 2024-10 draws the scenes
of NGSolve 6.2.2608 (surface, deformation, colour map, clipping plane; checked in a browser
by tests/workflow/test_webview.py).

The page is the scene at the window's size (the viewer sizes itself by the parent of the
element it draws into) under a header naming the field and its unit (the
viewer's colour bar has numbers only); the viewer's "Open Controls" panel sets the clipping
plane, the colour range and the light. The colour bar spans the field's range, but where a
few peaks (a singular edge, a crease tip) would wash the rest out it leaves them beyond its
ends, as the static figures do (:func:`colour_range`; the Controls' "autoscale" restores the
whole range). The viewer reports its start-up steps with
``console.log``; the page silences those (warnings and errors still reach the console), so a
page that loads cleanly logs nothing.

The field is first projected element by element onto polynomials of degree :data:`DEGREE`
(an L2 projection, sampled at quadrature points inside the elements): the viewer evaluates
at the elements' vertices and edges, where a field with a singular direction has no value
(the hemisphere's |b| on the meridional planes is 0/0 on its axis: unprojected, it drew a
band of false zeros along the axis and a hole at the centre of the base). The degree is that
of the highest-order field drawn, the skin's growth (L2 of order 3), which the projection
keeps exactly: projected onto the drawing order 2 instead, its largest value rose from 1.59
to 1.66 (overshoot). The projection and the
deformation are evaluated on the boundary from the adjacent element (``BoundaryFromVolumeCF``),
which also draws fields defined per material region (the brain's gray and white matter).
"""

from __future__ import annotations

import html
import importlib.util
import json
import os
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat import sampling
from ngincompat.atomic import atomic_path
from ngincompat.errors import NgincompatError
from ngincompat.workflow.style import MAP_CLIP, colour_scale

#: The degree of the polynomials a field is projected onto before it is drawn.
DEGREE = 3

#: The package that ships the viewer's JavaScript, and the file inside it.
PACKAGE = "webgui_jupyter_widgets"
SCRIPT = ("js", "webgui.js")

#: The viewer's settings every view starts with: no element edges (they hide the colours of a
#: fine mesh; the Controls panel turns them on).
SETTINGS = {"Objects": {"Wireframe": False}}

#: Silences the viewer's reports of its start-up steps (console.warn and .error stay).
QUIET = "console.log = console.group = console.groupCollapsed = console.groupEnd = () => {};"

#: The page's style. The viewer draws its colour bar at a length that follows the window's
#: height and its five labels in the page's font: at the report's frame height (560 px) five
#: labels of four digits ran into each other, so their size follows the height too.
STYLE = """
html,body{margin:0;height:100%;overflow:hidden;font-family:system-ui,sans-serif}
header{position:absolute;top:0;left:0;right:0;height:2.4em;padding:.3em .6em;font-size:.9em;
box-sizing:border-box;background:#f4f4f4;border-bottom:1px solid #ccc;white-space:nowrap;
overflow:hidden;text-overflow:ellipsis}
#frame{position:absolute;top:2.4em;bottom:0;left:0;right:0}
#view{width:100%;height:100%;font-size:clamp(9px,2.2vh,14px)}
"""


@lru_cache(maxsize=1)
def viewer_script() -> str:
    """The webgui JavaScript of the installed ``webgui_jupyter_widgets`` package."""
    spec = importlib.util.find_spec(PACKAGE)
    path = (Path(next(iter(spec.submodule_search_locations)), *SCRIPT)
            if spec is not None and spec.submodule_search_locations else None)
    if path is None or not path.is_file():
        raise NgincompatError(
            f"the interactive views need the viewer's JavaScript from the package {PACKAGE} "
            f"(a dependency of ngincompat): pip install '{PACKAGE}>=0.2.37,<0.3'")
    return path.read_text(encoding="utf-8")


def scene(mesh: ngs.Mesh, field: ngs.CoefficientFunction,
          deformation: ngs.CoefficientFunction | None = None, *,
          order: int = 2, camera: Sequence[float] | None = None,
          clipping: Sequence[float] | None = None, zoom: float = 1.0) -> dict[str, Any]:
    """The webgui scene (a dict of JSON data) of the scalar ``field`` on ``mesh``.

    Parameters
    ----------
    mesh : ngsolve.Mesh
        A three-dimensional mesh.
    field : ngsolve.CoefficientFunction
        The scalar drawn as the colour map (its L2 projection, :data:`DEGREE`).
    deformation : ngsolve.CoefficientFunction, optional
        The displacement the body is drawn moved by (the deformed configuration).
    order : int
        The order of the drawn patches (2: curved faces and quadratic colour variation). A
        view with a cut is drawn at order 1: at order 2 the bundle's cut of a coarse mesh of
        two materials had holes (a brick of 0.5 mm elements; of 0.2 mm it had none).
    camera : sequence of three floats, optional
        The rotations about x, y, z [degrees] of the first view.
    clipping : sequence of four floats, optional
        A clipping plane (normal x, y, z and its offset from the body's centre): the volume is
        drawn too, the plane cuts it and shows the field on the cut (the viewer's Controls
        move it).
    zoom : float
        The first view's magnification: 1 fits the sphere around the mesh's bounding box
        (the viewer's default), which leaves a rounded body such as the brain small.
    """
    from ngsolve.webgui import Draw

    kwargs = dict(show=False, order=order, settings=dict(SETTINGS),
                  deformation=(ngs.BoundaryFromVolumeCF(deformation)
                               if deformation is not None else False),
                  draw_vol=clipping is not None)
    if camera is not None:
        kwargs["euler_angles"] = [float(a) for a in camera]
    if clipping is not None:
        kwargs["clipping"] = dict(zip(("x", "y", "z", "dist"), map(float, clipping),
                                      strict=True), function=True)
    shown = ngs.GridFunction(ngs.L2(mesh, order=DEGREE))
    shown.Set(field)
    on_boundary = ngs.BoundaryFromVolumeCF(shown)
    low, high = colour_range(mesh, on_boundary)
    if low is not None:
        kwargs.update(min=low, max=high, autoscale=False)
    data = Draw(on_boundary, mesh, **kwargs).GetData()
    data["mesh_radius"] /= zoom
    return data


def colour_range(mesh: ngs.Mesh,
                 field: ngs.CoefficientFunction) -> tuple[float, float] | tuple[None, None]:
    """(low, high) of the colour bar of ``field`` on the boundary of ``mesh`` where peaks at
    a few points (a singular edge, a crease tip) would wash the rest out
    (:func:`~ngincompat.workflow.style.colour_scale` with
    :data:`~ngincompat.workflow.style.MAP_CLIP`, on the values at the integration points and
    vertices of the boundary's elements); (None, None) where the whole range is drawn (the viewer's
    autoscale)."""
    values = np.ravel(field(sampling.element_points(mesh, 2 * DEGREE, ngs.BND)))
    values = values[np.isfinite(values)]
    norm, _ = colour_scale(values, signed=False, clip=MAP_CLIP)
    if values.size == 0 or (norm.vmin <= values.min() and norm.vmax >= values.max()):
        return None, None
    # (colour_scale gives the norm its limits)
    return float(norm.vmin), float(norm.vmax)  # type: ignore[arg-type]


def page(data: Mapping[str, Any], title: str, caption: str = "") -> str:
    """The HTML page of the scene ``data`` (:func:`scene`) with the webgui script inlined;
    ``title``: the field and its unit, ``caption``: what is shown (plain text)."""
    # "</" never closes the script inside the data
    payload = json.dumps(data).replace("</", "<\\/")
    text = html.escape(title) + (f" <small>{html.escape(caption)}</small>" if caption else "")
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width">'
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>"
        f'<header><b>{text}</b></header><div id="frame"><div id="view"></div></div>'
        f"<script>{QUIET}</script>"
        f"<script>{viewer_script()}</script>"
        f"<script>const renderData = {payload};\n"
        "const scene = new webgui.Scene();\n"
        'scene.init(document.getElementById("view"), renderData, '
        "{preserveDrawingBuffer: true});</script></body></html>")


def write(path: str | os.PathLike, data: Mapping[str, Any], title: str, caption: str = "") -> Path:
    """Write the page of the scene ``data`` to ``path``, atomically; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(page(data, title, caption), encoding="utf-8")
    return path
