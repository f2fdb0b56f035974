"""The cortex-subcortex bilayer of the cortical-folding scene (section 3.7): the plane section
of the paper's two-dimensional model, in the paper's axes."""

import ngsolve as ngs
from netgen.occ import Glue, OCCGeometry, WorkPlane, X, Y

from ngincompat.errors import require

from ._common import check_mesh_args, interruptible


def bilayer(length=3.0, height=1.0, cortex=0.05, maxh=0.05, curve_order=1,
            cortex_maxh=None, top_maxh=None):
    """The section of a bilayer in plane strain (cm): X1 in [0, length] along it, X2 in
    [0, height] vertical (X3 out of plane, the paper's axes); the top ``cortex`` of it is
    the cortex, the rest the subcortex. A two-dimensional mesh of triangles: the fields of a
    body in plane strain do not depend on X3.

    Parameters
    ----------
    length, height : float
        Size (cm), > 0. Defaults 3 x 1 (the paper's).
    cortex : float
        Cortical thickness (cm), in (0, height). Default 0.05.
    maxh, curve_order
        As for every builder (``curve_order`` 1: the section's edges are straight).
    cortex_maxh : float, optional
        Mesh size in the cortex and on the interface (default ``maxh``); the mesh grades
        from it to ``maxh`` below, so a fine cortex (buckling needs several elements across
        it) does not refine the whole subcortex.
    top_maxh : float, optional
        Mesh size on the top surface (default ``cortex_maxh``), graded to ``cortex_maxh``
        below it: finer where the folds crease.

    Returns
    -------
    ngsolve.Mesh
        Triangles; materials ``cortex`` and ``subcortex``; boundaries ``left`` (X1 = 0),
        ``right`` (X1 = length), ``bottom`` (X2 = 0), ``top`` (X2 = height) and
        ``interface``.
    """
    require(length > 0, "length", length, "> 0")
    require(height > 0, "height", height, "> 0")
    require(0 < cortex < height, "cortex", cortex, f"in (0, height = {height:g})")
    check_mesh_args(maxh, curve_order, max(length, height))
    cortex_maxh = maxh if cortex_maxh is None else cortex_maxh
    require(0 < cortex_maxh <= maxh, "cortex_maxh", cortex_maxh, f"in (0, maxh = {maxh:g}]")
    top_maxh = cortex_maxh if top_maxh is None else top_maxh
    require(0 < top_maxh <= cortex_maxh, "top_maxh", top_maxh,
            f"in (0, cortex_maxh = {cortex_maxh:g}]")
    split = height - cortex
    sub = WorkPlane().Rectangle(length, split).Face()
    top = WorkPlane().MoveTo(0, split).Rectangle(length, cortex).Face()
    for part, name in ((sub, "subcortex"), (top, "cortex")):
        part.edges.Min(X).name = "left"
        part.edges.Max(X).name = "right"
        part.name = name
    sub.edges.Min(Y).name = "bottom"
    sub.edges.Max(Y).name = "interface"
    top.edges.Max(Y).name = "top"
    top.edges.Min(Y).name = "interface"
    top.maxh = cortex_maxh
    sub.edges.Max(Y).maxh = cortex_maxh
    top.edges.Max(Y).maxh = top_maxh
    return ngs.Mesh(interruptible(
        lambda: OCCGeometry(Glue([sub, top]), dim=2).GenerateMesh(maxh=maxh)))
