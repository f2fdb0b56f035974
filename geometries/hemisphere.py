"""The hemisphere of section 3.2."""

from netgen.occ import Box, Pnt, Sphere, X, Y, Z

from ngincompat.errors import require

from ._common import check_mesh_args, mesh_shape


def hemisphere(R0=1.0, maxh=0.3, curve_order=3, centre_maxh=None, material="tissue",
               quarter=False):
    """The upper half ball X3 >= 0 of radius ``R0`` centred at the origin, or its quarter
    X1, X2 >= 0.

    Parameters
    ----------
    R0 : float
        Radius (mm in the paper), > 0. Default 1.
    maxh : float
        Element size.
    curve_order : int
        Order of the curved-boundary approximation (use the displacement order).
    centre_maxh : float, optional
        Element size at the centre, in (0, maxh]: growth fields of R alone are not smooth
        there (theta = 1 + R t/4 has a cone point) and a graded mesh restores accuracy.
    material : str
        Name of the material region.
    quarter : bool
        Only the quarter X1, X2 >= 0; its faces ``xmirror`` (X1 = 0) and ``ymirror`` (X2 = 0)
        then lie on the mirror planes of a body that is symmetric about them.

    Returns
    -------
    ngsolve.Mesh
        Boundaries ``flat`` (X3 = 0) and ``surface`` (the spherical cap), with ``quarter``
        also ``xmirror`` and ``ymirror``.
    """
    require(R0 > 0, "R0", R0, "> 0")
    check_mesh_args(maxh, curve_order, R0)
    refine = ()
    if centre_maxh is not None:
        require(0 < centre_maxh <= maxh, "centre_maxh", centre_maxh, f"in (0, maxh = {maxh}]")
        refine = ((0.0, 0.0, 0.0, centre_maxh),)
    ball = Sphere(Pnt(0, 0, 0), R0)
    low = 0 if quarter else -2 * R0
    half = ball * Box(Pnt(low, low, 0), Pnt(2 * R0, 2 * R0, 2 * R0))
    half.faces.name = "surface"
    half.faces.Min(Z).name = "flat"
    if quarter:
        half.faces.Min(X).name = "xmirror"
        half.faces.Min(Y).name = "ymirror"
    half.mat(material)
    return mesh_shape(half, maxh, curve_order, refine)

