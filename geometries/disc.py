"""The disc of section 3.3."""

from netgen.occ import Axes, Cylinder, Pnt, Z

from ngincompat.errors import require

from ._common import check_mesh_args, mesh_shape


def disc(R0=1.0, height=0.5, maxh=0.25, curve_order=3, material="tissue"):
    """A flat disc of radius ``R0`` and thickness ``height``, axis e3, X3 in [0, height].

    Parameters
    ----------
    R0 : float
        Radius (mm), > 0. Default 1 (the paper's).
    height : float
        Thickness (mm), > 0. Default 0.5 (the paper's).
    maxh, curve_order, material
        As for every builder.

    Returns
    -------
    ngsolve.Mesh
        Boundaries ``bottom`` (X3 = 0), ``top`` (X3 = height) and ``rim``.
    """
    require(R0 > 0, "R0", R0, "> 0")
    require(height > 0, "height", height, "> 0")
    check_mesh_args(maxh, curve_order, max(R0, height))
    body = Cylinder(Axes(Pnt(0, 0, 0), Z), R0, height)
    body.faces.name = "rim"
    body.faces.Min(Z).name = "bottom"
    body.faces.Max(Z).name = "top"
    body.mat(material)
    return mesh_shape(body, maxh, curve_order)
