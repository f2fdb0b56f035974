"""The cortex-subcortex bilayer of the cortical-folding scene (section 3.7): a plane section
extruded to a slab one element thick, as the paper's two-dimensional model."""

import ngsolve as ngs
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshPoint, Pnt, PointId
from netgen.meshing import Mesh as NetgenMesh
from netgen.occ import Glue, OCCGeometry, WorkPlane, X, Y

from ngincompat.errors import require

from ._common import check_mesh_args, interruptible


def bilayer(length=3.0, height=1.0, depth=0.05, cortex=0.05, maxh=0.05, curve_order=1,
            cortex_maxh=None, top_maxh=None):
    """A thin bilayer slab (cm): X1 in [0, length], X2 in [0, depth] (out of plane),
    X3 in [0, height]; the top ``cortex`` of it is the cortex, the rest the subcortex.

    The section X2 = 0 is meshed with triangles and extruded through the depth to one layer
    of prisms (:func:`extrude`): a body in plane strain (u2 = 0 on both faces) has fields
    independent of X2, which one layer holds exactly, so the mesh refines the section
    without multiplying the elements through the depth (a mesh of tetrahedra of size h has
    about depth / h layers of them).

    Parameters
    ----------
    length, height : float
        In-plane size (cm), > 0. Defaults 3 x 1 (the paper's).
    depth : float
        Out-of-plane thickness (cm), > 0. Default 0.05.
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
        Prisms; materials ``cortex`` and ``subcortex``; boundaries ``left`` (X1 = 0),
        ``right`` (X1 = length), ``bottom``, ``top``, ``sides`` (X2 = 0, depth) and
        ``interface``.
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
    section = ngs.Mesh(interruptible(
        lambda: OCCGeometry(Glue([sub, top]), dim=2).GenerateMesh(maxh=maxh)))
    return extrude(section, depth, sides="sides")


def extrude(section, depth, sides):
    """The two-dimensional mesh ``section`` (points (x, y)) as a slab of one layer of prisms,
    the point (x, y) at (x, Y, y) for Y in [0, depth]: its materials those of the section,
    its boundaries the section's edges extruded (same names), the two faces Y = 0 and
    Y = depth the boundary ``sides``, and an edge between two materials an interior face
    between them."""
    mesh = NetgenMesh(dim=3)
    points = [vertex.point for vertex in section.vertices]
    n = len(points)
    for y in (0.0, depth):
        for x, z in points:
            mesh.Add(MeshPoint(Pnt(x, y, z)))
    materials = list(section.GetMaterials())
    for index, name in enumerate(materials, start=1):
        mesh.SetMaterial(index, name)
    faces = {}

    def face(name, inside, outside=0):
        if name not in faces:
            faces[name] = mesh.Add(FaceDescriptor(bc=len(faces) + 1, domin=inside,
                                                  domout=outside, surfnr=len(faces) + 1))
            mesh.SetBCName(faces[name] - 1, name)
        return faces[name]

    def point(vertex, layer):
        return PointId(vertex.nr + 1 + layer * n)

    neighbours = {}     # edge -> the materials of the triangles beside it
    for element in section.Elements(ngs.VOL):
        a, b, c = element.vertices
        index = materials.index(element.mat) + 1
        # (x, y) -> (x, z) reverses the orientation of the section's triangles
        mesh.Add(Element3D(index, [point(a, 0), point(c, 0), point(b, 0),
                                   point(a, 1), point(c, 1), point(b, 1)]))
        mesh.Add(Element2D(face(sides, index), [point(a, 0), point(b, 0), point(c, 0)]))
        mesh.Add(Element2D(face(sides, index), [point(a, 1), point(c, 1), point(b, 1)]))
        for edge in element.edges:
            neighbours.setdefault(edge.nr, []).append(index)
    for element in section.Elements(ngs.BND):
        a, b = element.vertices
        inside, *outside = neighbours[element.edges[0].nr]
        mesh.Add(Element2D(face(element.mat, inside, *outside),
                           [point(a, 0), point(a, 1), point(b, 1), point(b, 0)]))
    return ngs.Mesh(mesh)
