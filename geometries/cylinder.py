"""The cylinder of section 3.4."""

import math

from netgen.occ import Cylinder, Pnt, X

from ngincompat.errors import require

from ._common import check_mesh_args, mesh_shape


def cylinder(area=math.pi / 4, length=1.0, maxh=0.25, curve_order=3, material="tissue"):
    """A circular cylinder along e1, X1 in [0, length], resting on the planes X2 = 0 and
    X3 = 0 (its axis is the line X2 = X3 = radius), as in the paper's Fig. 4: theta = 1 + X2 t/4
    is then 1 at the bottom and 1.25 at the top.

    Parameters
    ----------
    area : float
        Cross-section (mm^2), > 0. Default pi/4 (radius 0.5, the paper's).
    length : float
        Length (mm), > 0. Default 1.
    maxh, curve_order, material
        As for every builder.

    Returns
    -------
    ngsolve.Mesh
        Boundaries ``left`` (X1 = 0), ``right`` (X1 = length) and ``mantle``.
    """
    require(area > 0, "area", area, "> 0")
    require(length > 0, "length", length, "> 0")
    radius = math.sqrt(area / math.pi)
    check_mesh_args(maxh, curve_order, max(radius, length))
    body = Cylinder(Pnt(0, radius, radius), X, r=radius, h=length)
    body.faces.name = "mantle"
    body.faces.Min(X).name = "left"
    body.faces.Max(X).name = "right"
    body.mat(material)
    return mesh_shape(body, maxh, curve_order)
