"""Shared helpers of the geometry builders."""

import ngsolve as ngs
from netgen.meshing import MeshingParameters
from netgen.occ import OCCGeometry

from ngincompat.errors import require


def check_mesh_args(maxh, curve_order, scale):
    """Validate the arguments every builder has."""
    require(maxh > 0, "maxh", maxh, "> 0")
    require(maxh <= 10 * scale, "maxh", maxh, f"<= {10 * scale:g} (10 x the body's size)")
    require(isinstance(curve_order, int) and 1 <= curve_order <= 8, "curve_order", curve_order,
            "an integer in [1, 8]")


def mesh_shape(shape, maxh, curve_order, refine_at=()):
    """Mesh an OCC shape with tetrahedra and curve it to ``curve_order``.

    ``refine_at`` lists points (x, y, z, h) around which the element size is at most h.
    """
    params = MeshingParameters(maxh=maxh)
    for x, y, z, h in refine_at:
        params.RestrictH(x, y, z, h)
    mesh = ngs.Mesh(OCCGeometry(shape).GenerateMesh(params))
    if curve_order > 1:
        mesh.Curve(curve_order)
    return mesh
