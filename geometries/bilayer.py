"""The cortex-subcortex bilayer of the cortical-folding scene (section 3.7)."""

from netgen.occ import Box, Glue, Pnt, X, Z

from ngincompat.errors import require

from ._common import check_mesh_args, mesh_shape


def bilayer(length=3.0, height=1.0, depth=0.05, cortex=0.05, maxh=0.05, curve_order=1,
            cortex_maxh=None, top_maxh=None):
    """A thin bilayer slab (cm): X1 in [0, length], X2 in [0, depth] (out of plane),
    X3 in [0, height]; the top ``cortex`` of it is the cortex, the rest the subcortex.

    Parameters
    ----------
    length, height : float
        In-plane size (cm), > 0. Defaults 3 x 1 (the paper's).
    depth : float
        Out-of-plane thickness (cm), > 0. Default 0.05.
    cortex : float
        Cortical thickness (cm), in (0, height). Default 0.05.
    maxh, curve_order
        As for every builder.
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
        Materials ``cortex`` and ``subcortex``; boundaries ``left`` (X1 = 0), ``right``
        (X1 = length), ``bottom``, ``top``, ``sides`` (X2 = 0, depth) and ``interface``.
    """
    require(length > 0, "length", length, "> 0")
    require(height > 0, "height", height, "> 0")
    require(depth > 0, "depth", depth, "> 0")
    require(0 < cortex < height, "cortex", cortex, f"in (0, height = {height:g})")
    check_mesh_args(maxh, curve_order, max(length, height))
    cortex_maxh = maxh if cortex_maxh is None else cortex_maxh
    require(0 < cortex_maxh <= maxh, "cortex_maxh", cortex_maxh, f"in (0, maxh = {maxh:g}]")
    top_maxh = cortex_maxh if top_maxh is None else top_maxh
    require(0 < top_maxh <= cortex_maxh, "top_maxh", top_maxh,
            f"in (0, cortex_maxh = {cortex_maxh:g}]")
    split = height - cortex
    sub = Box(Pnt(0, 0, 0), Pnt(length, depth, split))
    top = Box(Pnt(0, 0, split), Pnt(length, depth, height))
    for part, name in ((sub, "subcortex"), (top, "cortex")):
        part.faces.name = "sides"
        part.faces.Min(X).name = "left"
        part.faces.Max(X).name = "right"
        part.mat(name)
    sub.faces.Min(Z).name = "bottom"
    sub.faces.Max(Z).name = "interface"
    top.faces.Max(Z).name = "top"
    top.faces.Min(Z).name = "interface"
    top.solids.maxh = cortex_maxh
    sub.faces.Max(Z).maxh = cortex_maxh
    top.faces.Max(Z).maxh = top_maxh
    return mesh_shape(Glue([sub, top]), maxh, curve_order)
