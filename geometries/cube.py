"""The cube of section 3.1."""

import math

import ngsolve as ngs
from netgen.occ import Box, OCCGeometry, Pnt, X, Y, Z
from ngsolve.meshes import MakeStructured3DMesh

from ngincompat.errors import require

from ._common import interruptible

#: Face names: the faces X1 = 0 and X1 = side are ``left`` and ``right``, X2 = 0 / side are
#: ``front`` / ``back``, X3 = 0 / side are ``bottom`` / ``top``.
FACES = ("left", "right", "front", "back", "bottom", "top")


def cube(side=1.0, maxh=0.25, elements="hex", curve_order=1, material="tissue", quarter=False):
    """A cube [0, side]^3, or its quarter [0, side] x [0, side/2]^2.

    Parameters
    ----------
    side : float
        Edge length (mm in the paper), > 0. Default 1.
    maxh : float
        Element size, in (0, side]. Hexahedral meshes use ceil(side / maxh) cells per edge.
    elements : {"hex", "tet"}
        Structured hexahedra (the paper's C3D8 layout) or an unstructured Netgen tetrahedral
        mesh.
    curve_order : int
        Order of the geometry approximation (a cube needs none; kept for a uniform interface).
    material : str
        Name of the single material region.
    quarter : bool
        Only the quarter X2, X3 <= side / 2; its faces ``back`` and ``top`` then lie on the
        cube's mid-planes (mirror planes of a body and load symmetric about them).

    Returns
    -------
    ngsolve.Mesh
        Boundaries named as in :data:`FACES`, one material ``material``.
    """
    require(side > 0, "side", side, "> 0")
    require(0 < maxh <= side, "maxh", maxh, f"in (0, side = {side}]")
    require(elements in ("hex", "tet"), "elements", elements, "hex or tet")
    require(isinstance(curve_order, int) and curve_order >= 1, "curve_order", curve_order,
            "an integer >= 1")
    if elements == "hex":
        n = max(1, math.ceil(side / maxh - 1e-9))
        m, w = (max(1, math.ceil(n / 2)), side / 2) if quarter else (n, side)
        mesh = MakeStructured3DMesh(hexes=True, nx=n, ny=m, nz=m,
                                    mapping=lambda x, y, z: (side * x, w * y, w * z))
        # MakeStructured3DMesh names X1 = 0, 1 "back", "front" and X2 = 0, 1 "left", "right".
        rename = {"back": "left", "front": "right", "left": "front", "right": "back"}
        ngmesh = mesh.ngmesh
        for i, name in enumerate(mesh.GetBoundaries()):
            ngmesh.SetBCName(i, rename.get(name, name))
        ngmesh.SetMaterial(1, material)
        return ngs.Mesh(ngmesh)
    w = side / 2 if quarter else side
    box = Box(Pnt(0, 0, 0), Pnt(side, w, w))
    box.mat(material)
    for k, axis in enumerate((X, Y, Z)):
        box.faces.Min(axis).name = FACES[2 * k]
        box.faces.Max(axis).name = FACES[2 * k + 1]
    mesh = ngs.Mesh(interruptible(lambda: OCCGeometry(box).GenerateMesh(maxh=maxh)))
    if curve_order > 1:
        mesh.Curve(curve_order)
    return mesh
