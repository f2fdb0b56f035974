"""The skin patch of section 3.6, with the expander's footprint marked on its bottom face."""

import math

from netgen.occ import Axes, Box, Cylinder, Glue, Pnt, WorkPlane, Z

from ngincompat.errors import require
from ngincompat.names import FOOTPRINTS

from ._common import check_mesh_args, mesh_shape

#: The paper's patch: 10 x 10 cm, 0.3 cm thick.
SIDE, THICKNESS = 10.0, 0.3


def skin_patch(side=SIDE, thickness=THICKNESS, footprint="rectangle", footprint_size=None,
               maxh=1.0, curve_order=2, material="skin"):
    """A square patch of skin [-side/2, side/2]^2 x [0, thickness] (cm), with the footprint of
    a tissue expander marked on its bottom face.

    Parameters
    ----------
    side : float
        Edge of the patch (cm), > 0. Default 10 (the paper's 10 x 10 cm^2).
    thickness : float
        Thickness (cm), in (0, side). Default 0.3.
    footprint : str
        Shape of the expander's base, centred on the patch: one of
        :data:`ngincompat.names.FOOTPRINTS`.
    footprint_size : float, optional
        Characteristic size (cm): the rectangle is size x size/2, the square size x size, the
        circle has diameter size, the crescent is a disc of diameter size minus a disc of the
        same diameter shifted by size/2. Default side/2; must leave a margin of at least one
        thickness to the patch's edge.
    maxh, curve_order, material
        As for every builder.

    Returns
    -------
    ngsolve.Mesh
        Boundaries ``footprint`` (the expander's base), ``bottom`` (the rest of X3 = 0),
        ``top``, ``periphery`` (the four sides) and ``footprint_wall`` (the interior surface
        above the footprint's edge, where the two glued parts meet); one material.
    """
    require(side > 0, "side", side, "> 0")
    require(0 < thickness < side, "thickness", thickness, f"in (0, side = {side:g})")
    require(footprint in FOOTPRINTS, "footprint", footprint, ", ".join(FOOTPRINTS))
    size = side / 2 if footprint_size is None else footprint_size
    limit = side - 2 * thickness
    require(0 < size <= limit, "footprint_size", size,
            f"in (0, {limit:g}] (the patch minus a margin of one thickness on each side)")
    check_mesh_args(maxh, curve_order, side)
    box = Box(Pnt(-side / 2, -side / 2, 0), Pnt(side / 2, side / 2, thickness))
    box.faces.name = "periphery"
    box.faces.Min(Z).name = "bottom"
    box.faces.Max(Z).name = "top"
    column = _footprint_column(footprint, size, thickness)
    column.faces.name = "footprint_wall"
    inner = box * column
    outer = box - column
    inner.faces.Min(Z).name = "footprint"
    for part in (inner, outer):
        part.mat(material)
    return mesh_shape(Glue([inner, outer]), maxh, curve_order)


def footprint_area(footprint, size):
    """Area of the footprint (cm^2), for checks and reports."""
    if footprint == "rectangle":
        return size * size / 2
    if footprint == "square":
        return size * size
    r = size / 2
    if footprint == "circle":
        return math.pi * r * r
    d = size / 2  # lens of two discs of radius r whose centres are d apart
    lens = 2 * r * r * math.acos(d / (2 * r)) - d / 2 * math.sqrt(4 * r * r - d * d)
    return math.pi * r * r - lens


def footprint_size(footprint, area):
    """The size parameter (cm) of ``footprint`` whose base has ``area`` (cm^2): every shape
    scales with its size, so the area is quadratic in it."""
    require(footprint in FOOTPRINTS, "footprint", footprint, ", ".join(FOOTPRINTS))
    require(area > 0, "footprint_area", area, "> 0")
    return math.sqrt(area / footprint_area(footprint, 1.0))


def _footprint_column(footprint, size, thickness):
    """A prism over the footprint, through the whole thickness."""
    h = 3 * thickness
    base = Pnt(0, 0, -thickness)
    if footprint == "circle":
        return Cylinder(Axes(base, Z), size / 2, h)
    if footprint == "crescent":
        disc = Cylinder(Axes(base, Z), size / 2, h)
        bite = Cylinder(Axes(Pnt(size / 2, 0, -thickness), Z), size / 2, h)
        return disc - bite
    width = size
    depth = size / 2 if footprint == "rectangle" else size
    face = WorkPlane(Axes(base, Z)).Rectangle(width, depth).Face()
    face = face.Move((-width / 2, -depth / 2, 0))
    return face.Extrude(h)

