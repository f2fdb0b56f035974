"""The interactive 3-D views of ``ngincompat paper``: per section whose body a still image does
not show whole, one field of the paper's figure on the deformed body as a self-contained
webgui page (:mod:`ngincompat.workflow.webview`), ``view_<case>.html`` beside report.html,
which the report embeds next to the static figure.

* 3.1, the cube: |b| on the planes normal to n2 (Fig. 1e), whose faces the still figure shows
  three of.
* 3.2, the hemisphere (linear profile): |b| on the meridional planes (Fig. 2b), inside the
  quarter that was solved (its two mirror planes are faces of the view).
* 3.5, the brain: |b| (the largest of the planes normal to e1, e2, e3; Fig. 5d) on a cut
  through the centre, normal e2, seen from the side it removes, which the viewer's Controls
  move through the brain (the paper's sections, Fig. 5c-e, as one movable cut); the volume is
  drawn at order 1 (the brain's elements are small, and the volume is most of the page's
  data).
* 3.6, the skin over the crescent expander (the least symmetric footprint): the area growth
  at the end of the hold on the inflated skin (Fig. 6a).

Not for the disc (3.3) and the cylinder (3.4), whose fields are axisymmetric: the still maps
show them whole; nor for cortical folding (3.7), a two-dimensional model.

A view is drawn from the run's NGSolve fields as it ends, like the field figures; a job that
resumes a finished case keeps the view it wrote then.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ngincompat.workflow import webview

if TYPE_CHECKING:     # a run's record (its module imports NGSolve)
    from ngincompat.workflow.results import Results


@dataclass(frozen=True)
class View:
    """One view: the ``field`` (a key of the run's fields), its ``title`` ({L}: the length
    unit), the ``deformation`` field it is drawn on, the first ``camera`` rotations (degrees
    about x, y, z) and ``zoom``, a ``clipping`` plane (normal and offset; None: the surface
    only) and the drawing ``order``."""

    field: str
    title: str
    deformation: str = "u"
    camera: tuple = (-65.0, 0.0, 30.0)
    clipping: tuple | None = None
    order: int = 2
    zoom: float = 1.0


#: The case of each section that has a view, and its view.
VIEWS = {
    "cube": View("|b_n2|", "Fig. 1e: |b| on the planes normal to n2 [1/{L}]"),
    "hemisphere-linear": View("|b_meridional|",
                              "Fig. 2b: |b| on the meridional planes [1/{L}]",
                              camera=(-65.0, 0.0, 45.0)),
    "atrophy": View("|b|", "Fig. 5d: |b|, the largest over the planes normal to e1, e2, e3 "
                    "[1/{L}]", camera=(-75.0, 0.0, 25.0), clipping=(0.0, 1.0, 0.0, 0.0),
                    order=1, zoom=1.5),
    "skin-crescent": View("theta", "Fig. 6a: area growth at the end of the hold [-]",
                          deformation="u_end_of_hold", camera=(-55.0, 0.0, 20.0)),
}


def case_files(label: str) -> list[str]:
    """The view file of the case ``label`` (none for a case without a view)."""
    return [f"view_{label}.html"] if label in VIEWS else []


def case_view(out: str | os.PathLike, label: str, results: Results, resolution: str) -> None:
    """Write the view of the case ``label`` from its fields into ``out`` (nothing for a case
    without a view, nor for a run without its fields)."""
    view = VIEWS.get(label)
    f = results.fields
    if view is None or results.domain is None or view.field not in f:
        return
    data = webview.scene(results.domain, f[view.field], f.get(view.deformation),
                         order=view.order, camera=view.camera, clipping=view.clipping,
                         zoom=view.zoom)
    caption = f"{label}, deformed, {resolution} resolution; drag to turn, wheel to zoom"
    webview.write(Path(out) / case_files(label)[0],
                  data, view.title.format(L=results.units["length"]), caption)
