"""An idealised adult brain: an ellipsoid of white matter inside a shell of gray matter."""

from netgen.occ import Axes, Ellipsoid, Glue, OCCGeometry, Pnt, X, Y

from ngincompat.errors import require

from ._common import check_mesh_args, mesh_shape


def brain(semi_axes=(8.5, 7.0, 6.0), gray=0.3, maxh=1.0, curve_order=2):
    """An ellipsoidal brain (cm) centred at the origin with a gray-matter shell.

    Parameters
    ----------
    semi_axes : tuple of float
        Semi-axes along e1 (front-back), e2 (left-right), e3 (up-down) in cm; the defaults
        give 17 x 14 x 12 cm, the size of an adult brain.
    gray : float
        Thickness of the gray-matter shell (cm), in (0, smallest semi-axis / 2). Default 0.3.
    maxh, curve_order
        As for every builder.

    Returns
    -------
    ngsolve.Mesh
        Materials ``gray`` and ``white``; boundaries ``surface`` and ``interface``.
    """
    geometry = brain_geometry(semi_axes, gray)
    check_mesh_args(maxh, curve_order, max(semi_axes))
    return mesh_shape(geometry.shape, maxh, curve_order)


def brain_geometry(semi_axes=(8.5, 7.0, 6.0), gray=0.3):
    """The OCC geometry of :func:`brain` (unmeshed): for a mesh generated on one MPI rank and
    curved on every rank after it is distributed."""
    a = tuple(float(v) for v in semi_axes)
    require(len(a) == 3 and min(a) > 0, "semi_axes", semi_axes, "three numbers > 0")
    require(0 < gray < min(a) / 2, "gray", gray, f"in (0, {min(a) / 2:g}) (half the smallest "
            "semi-axis)")
    axes = Axes(Pnt(0, 0, 0), n=X, h=Y)  # OCC's first semi-axis lies along n
    outer = Ellipsoid(axes, *a)
    inner = Ellipsoid(axes, *(v - gray for v in a))
    shell = outer - inner
    shell.faces.name = "surface"
    inner.faces.name = "interface"
    shell.mat("gray")
    inner.mat("white")
    return OCCGeometry(Glue([shell, inner]))
