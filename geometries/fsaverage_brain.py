"""An anatomical brain hemisphere from the FreeSurfer fsaverage pial and white surfaces.

The fsaverage5 surfaces of both hemispheres ship inside the ``nilearn`` wheel (GIfTI, 10242
vertices each, mm in MNI305 space, ``pip install -e ".[brain]"``): nothing is downloaded.
The pial and the white surface of a hemisphere share their triangulation, vertex by vertex
(FreeSurfer grows the pial surface out of the white one). The cortex (gray matter) is the
volume between them, the white matter the volume inside the white surface.

Meshing (measured choices: ``docs/measurements/atrophy.md``, the fsaverage brain):

* **resolution**: the fsaverage triangulations are nested icosahedra (the first 2562,
  10242 vertices are those of subdivision 4, 5), so a coarser brain takes the first
  vertices and re-triangulates them as the convex hull of their points on the registration
  sphere; no decimation, and pial and white keep their vertex correspondence. At
  subdivision 3 (642 vertices, 11 mm edges) the pial and white surfaces intersect;
* **cortex**: ``layers`` layers of prisms between corresponding white and pial triangles,
  each cut into tetrahedra (:func:`prism_tetrahedra`), so the cortex has ``layers``
  elements across by construction, at 3 ``layers`` tetrahedra per triangle. Where the pial
  vertices slide far sideways over the white ones a prism is twisted (no cut into
  tetrahedra without an inverted or flat one: 18 of the 5120 columns of subdivision 4 at
  2 layers, 197 columns with their neighbours); those are left to Netgen;
* **white matter** (and those few columns): Netgen fills the white surface from its
  triangles, kept as they are, so the mesh is conforming and the volumes are those the
  surfaces enclose. ``layers = 0`` lets Netgen fill the whole cortex from the pial and
  white triangles: at subdivision 4 about one element across it (the surfaces' triangles,
  6 mm, set the tetrahedra's size);
* **medial wall**: fsaverage closes each hemisphere over the cut through the corpus callosum
  and brainstem with pial = white (thickness 0), which Netgen cannot mesh. Where the cortex
  is thinner than ``min_thickness`` (along the pial normal) the white vertex is moved to
  that depth below the pial one, so a thin gray layer covers the medial wall;
* **one hemisphere**: the two hemispheres only touch at the midline (their pial surfaces
  overlap by less than 1e-3 mm^3) and fsaverage has no corpus callosum to join them: a body
  of both would be two bodies.

Coordinates: cm, X1 = posterior -> anterior (MNI y), X2 = right -> left (- MNI x),
X3 = inferior -> superior (MNI z), the axes of the other brains, not centred (a point in MNI
mm maps by :func:`from_mni`).
"""

import os
from pathlib import Path

import ngsolve as ngs
import numpy as np
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshingParameters, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh

from ngincompat.errors import ParameterError, require

from ._common import interruptible
from .voxel_brain import cache_dir

HEMISPHERES = ("left", "right")
#: Icosahedral subdivision -> number of vertices of the fsaverage surface.
ICO_VERTICES = {4: 2562, 5: 10242}
#: Bumped whenever the meshing rule changes, so that stale cached meshes are not read.
_CACHE_VERSION = 2
#: A tetrahedron holding less than this share of its prism's volume is flat (a sliver):
#: the elastic volume change and the stress of a run peak on such slivers.
FLAT = 0.02
#: Thickness below which a vertex is on the medial wall (fsaverage has exactly 0 there) [cm].
_MEDIAL = 1e-3
#: The thinnest cortex meshed [cm] (the medial wall's gray layer).
MIN_THICKNESS = 0.1
#: The three tetrahedra of a prism (bottom 0, 1, 2 below top 3, 4, 5) for each choice of
#: the diagonals of its sides (:data:`_SIDES`): 0 = the diagonal from the side's first
#: corner to its third, 1 = from its second to its fourth. The two cyclic choices have no
#: such split; the smallest-number rule never makes them.
_PRISM_SPLITS = {
    (1, 1, 0): ((0, 1, 2, 3), (1, 2, 3, 4), (2, 3, 4, 5)),
    (1, 0, 0): ((0, 1, 2, 3), (1, 2, 3, 5), (1, 3, 4, 5)),
    (0, 1, 0): ((0, 1, 2, 4), (0, 2, 3, 4), (2, 3, 4, 5)),
    (0, 1, 1): ((0, 1, 2, 4), (0, 2, 4, 5), (0, 3, 4, 5)),
    (1, 0, 1): ((0, 1, 2, 5), (0, 1, 3, 5), (1, 3, 4, 5)),
    (0, 0, 1): ((0, 1, 2, 5), (0, 1, 4, 5), (0, 3, 4, 5)),
}
#: The sides of a prism, each oriented out of it.
_SIDES = ((0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5))
#: The upright reference prism: bottom 0, 1, 2 at X3 = 0, top 3, 4, 5 at X3 = 1.
_UPRIGHT = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], float)
#: MNI (x, y, z) -> project (X1, X2, X3) = (y, -x, z): a rotation.
_AXES = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def from_mni(point_mm):
    """A point in MNI mm as project coordinates in cm."""
    return _AXES @ np.asarray(point_mm, dtype=float) / 10.0


def surfaces(hemisphere="left", ico=4):
    """The pial and white surfaces of a hemisphere at an icosahedral subdivision.

    Returns
    -------
    pial, white : ndarray (n, 3)
        Vertices in project coordinates (cm), pial vertex i above white vertex i.
    triangles : ndarray (m, 3)
        Shared triangles, oriented with their normal pointing out of the hemisphere.
    """
    require(hemisphere in HEMISPHERES, "hemisphere", hemisphere, " or ".join(HEMISPHERES))
    require(ico in ICO_VERTICES, "ico", ico, "one of " + ", ".join(map(str, ICO_VERTICES)))
    try:
        import nibabel
        import nilearn.datasets
    except ImportError:
        raise ParameterError("geometry = fsaverage needs nilearn: pip install -e \".[brain]\"") \
            from None
    from scipy.spatial import ConvexHull

    folder = Path(nilearn.datasets.__file__).parent / "data" / "fsaverage5"
    n = ICO_VERTICES[ico]

    def points(kind):
        return np.asarray(nibabel.load(folder / f"{kind}_{hemisphere}.gii.gz").agg_data()[0],
                          dtype=float)[:n]

    sphere = points("sphere")
    triangles = ConvexHull(sphere).simplices
    a, b, c = (sphere[triangles[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a + b + c) < 0
    triangles[inward] = triangles[inward][:, ::-1]
    pial, white = (points(kind) @ _AXES.T / 10.0 for kind in ("pial", "white"))
    return pial, white, triangles


def enclosed_volume(points, triangles):
    """The volume a closed, outward oriented triangulation encloses (divergence theorem:
    V = 1/3 oint X . N dA = sum over triangles of a . (b x c) / 6)."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


def vertex_normals(points, triangles):
    """Unit normals at the vertices: the area-weighted mean of the triangles' normals."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area_normals = np.cross(b - a, c - a)
    normals = np.zeros_like(points)
    for k in range(3):
        np.add.at(normals, triangles[:, k], area_normals)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def cortex(pial, white, triangles, min_thickness):
    """The white surface with the cortex at least ``min_thickness`` thick, and the medial
    wall (vertices where fsaverage has no cortex)."""
    thickness = np.linalg.norm(pial - white, axis=1)
    medial = thickness < _MEDIAL
    normals = vertex_normals(pial, triangles)
    depth = np.einsum("ij,ij->i", pial - white, normals)
    thin = depth < min_thickness
    white = white.copy()
    white[thin] = pial[thin] - min_thickness * normals[thin]
    return white, medial


def prism_tetrahedra(points, bottom, top):
    """Tetrahedra of the prisms with corners ``bottom`` (m, 3) below ``top`` (m, 3) (vertex
    numbers into ``points``), conforming across the prisms' sides, oriented as Netgen's.

    A prism is cut into the three tetrahedra of :data:`_PRISM_SPLITS` for the diagonals its
    sides take from their vertex of smallest number (so neighbours agree). Where the cortex
    is sheared one of these is inverted or flat (less than :data:`FLAT` of the prism's
    volume); such a prism is cut from a point added at its centroid instead: 8 tetrahedra
    over its 2 triangles and the 6 halves of its sides.

    Returns
    -------
    tets : ndarray (k, 4)
        Negatively oriented ((b - a) x (c - a) . (d - a) < 0), as Netgen's are.
    prism : ndarray (k,)
        The prism each tetrahedron belongs to.
    centroids : ndarray (j, 3)
        The added points, numbered from ``len(points)`` on.
    twisted : ndarray
        The prisms that neither cut gives without an inverted or flat tetrahedron.
    """
    corners = np.hstack([bottom, top])
    m = len(corners)
    choice = np.stack([
        np.minimum(corners[:, s[1]], corners[:, s[3]]) < np.minimum(corners[:, s[0]],
                                                                      corners[:, s[2]])
        for s in _SIDES], axis=1).astype(int)
    tets = np.empty((m, 3, 4), dtype=corners.dtype)
    upright = np.empty((m, 3))
    for key, split in _PRISM_SPLITS.items():
        rows = np.all(choice == np.array(key), axis=1)
        for t, tet in enumerate(split):
            tets[rows, t] = corners[rows][:, list(tet)]
        upright[rows] = np.sign(signed_volumes(_UPRIGHT, np.array(split)))
    volumes = signed_volumes(points, tets.reshape(-1, 4)).reshape(m, 3)
    sheared = np.any((volumes * upright <= 0) | _flat(volumes), axis=1)
    flip = (volumes > 0) & ~sheared[:, None]
    tets[flip] = tets[flip][:, [0, 2, 1, 3]]
    good = np.flatnonzero(~sheared)
    cut = corners[sheared]
    centroids = points[cut].mean(axis=1)
    centre = len(points) + np.arange(len(cut))
    faces = [cut[:, [0, 2, 1]], cut[:, [3, 4, 5]]]
    for side in _SIDES:
        faces += _halves(cut[:, list(side)])
    fan = np.stack([np.column_stack([f, centre]) for f in faces], axis=1).reshape(-1, 4)
    volumes = signed_volumes(np.vstack([points, centroids]), fan).reshape(-1, 8)
    inverted = (volumes >= 0) | _flat(volumes)
    return (np.vstack([tets[good].reshape(-1, 4), fan]),
            np.concatenate([np.repeat(good, 3), np.repeat(np.flatnonzero(sheared), 8)]),
            centroids, np.flatnonzero(sheared)[np.any(inverted, axis=1)])


def _flat(volumes):
    """Which of the tetrahedra of each prism (a row of ``volumes``) hold less than
    :data:`FLAT` of the prism's volume."""
    volumes = np.abs(volumes)
    return volumes < FLAT * volumes.sum(axis=1, keepdims=True)


def _halves(quads):
    """The two triangles of quadrilaterals (k, 4) cut along the diagonal from their corner
    of smallest number, with the quadrilaterals' orientation."""
    first = (np.minimum(quads[:, 0], quads[:, 2]) < np.minimum(quads[:, 1], quads[:, 3]))
    first = first[:, None]
    return [np.where(first, quads[:, [0, 1, 2]], quads[:, [0, 1, 3]]),
            np.where(first, quads[:, [0, 2, 3]], quads[:, [1, 2, 3]])]


def signed_volumes(points, tets):
    """(b - a) x (c - a) . (d - a) / 6 of each tetrahedron a, b, c, d."""
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6


def build(hemisphere="left", ico=4, layers=2, min_thickness=MIN_THICKNESS, maxh=1.0):
    """The Netgen mesh of a hemisphere (see the module): materials ``gray`` (cortex) and
    ``white``, boundaries ``surface`` (pial) and ``interface`` (white surface).

    The cortex is ``layers`` layers of prisms (:func:`prism_tetrahedra`), except around
    twisted prisms: those columns and their neighbours (sharing a vertex) are left to Netgen,
    which fills them with the white matter (``maxh`` bounds its tetrahedra). With
    ``layers = 0`` Netgen fills the whole cortex from the pial and white triangles."""
    require(isinstance(layers, int) and 0 <= layers <= 8, "layers", layers,
            "an integer in [0, 8]")
    require(0 < min_thickness <= 0.2, "min_thickness", min_thickness, "in (0, 0.2] cm")
    pial, white, triangles = surfaces(hemisphere, ico)
    white, _ = cortex(pial, white, triangles, min_thickness)
    n, levels = len(pial), max(layers, 1)
    points = np.vstack([white + k / levels * (pial - white) for k in range(levels + 1)])
    number = [k * n + np.arange(n) for k in range(levels + 1)]
    columns = [(number[k][triangles], number[k + 1][triangles]) for k in range(levels)]
    hole = np.full(len(triangles), layers == 0)
    for bottom, top in columns if layers else ():
        twisted = prism_tetrahedra(points, bottom, top)[3]
        hole[twisted] = True
    if hole.any() and not hole.all():
        hole = np.any(np.isin(triangles, triangles[hole]), axis=1)
    tets = []
    for bottom, top in columns if layers else ():
        layer, _, centroids, _ = prism_tetrahedra(points, bottom[~hole], top[~hole])
        tets.append(layer)
        points = np.vstack([points, centroids])
    cortex_tets = np.vstack(tets) if tets else np.empty((0, 4), dtype=int)
    faces, sides = _filled_boundary(triangles, number, hole)
    edges = np.linalg.norm(white[triangles] - white[np.roll(triangles, 1, axis=1)], axis=2)
    filled, domains, points = _fill(points, faces, sides, min(maxh, float(edges.mean())))
    tets = np.vstack([cortex_tets, filled])
    domains = np.concatenate([np.ones(len(cortex_tets), dtype=int), domains])
    used = np.unique(tets)               # not the inner levels of the columns Netgen filled
    ids = np.zeros(len(points), dtype=object)
    mesh = NetgenMesh(dim=3)
    ids[used] = [mesh.Add(MeshPoint(Pnt(*p))) for p in points[used]]
    mesh.SetMaterial(1, "gray")
    mesh.SetMaterial(2, "white")
    for tet, domain in zip(tets, domains, strict=True):
        mesh.Add(Element3D(int(domain), list(ids[tet])))
    mesh.Add(FaceDescriptor(surfnr=1, domin=1, domout=0, bc=1))
    mesh.Add(FaceDescriptor(surfnr=2, domin=2, domout=1, bc=2))
    mesh.SetBCName(0, "surface")
    mesh.SetBCName(1, "interface")
    for tri in number[levels][triangles]:
        mesh.Add(Element2D(1, list(ids[tri])))
    for tri in triangles:
        mesh.Add(Element2D(2, list(ids[tri])))
    return mesh


def _filled_boundary(triangles, number, hole):
    """The closed surface Netgen fills, with the (inside, outside) domains of each face
    (1 gray, 2 white, 0 not filled), oriented out of the inside: the white triangles, the
    pial triangles over the hole and the hole's walls towards the prisms, cut into
    triangles as the prisms' tetrahedra have them."""
    levels = len(number) - 1
    faces = [triangles, number[levels][triangles[hole]]]
    sides = [np.where(hole[:, None], (2, 1), (2, 0)), np.tile((1, 0), (hole.sum(), 1))]
    edges = {}
    for t in np.flatnonzero(~hole):
        for k in range(3):
            edges[tuple(sorted((triangles[t][k], triangles[t][(k + 1) % 3])))] = t
    walls = []
    for t in np.flatnonzero(hole):
        for k in range(3):
            a, b = triangles[t][k], triangles[t][(k + 1) % 3]
            if tuple(sorted((a, b))) in edges:
                walls += [[number[j][a], number[j][b], number[j + 1][b], number[j + 1][a]]
                          for j in range(levels)]
    if walls:
        halves = _halves(np.array(walls))
        faces += halves
        sides += [np.tile((1, 0), (len(h), 1)) for h in halves]
    return np.vstack(faces), np.vstack(sides)


def _fill(points, faces, sides, maxh):
    """Netgen's tetrahedra in the closed surface ``faces`` (vertex numbers into ``points``;
    ``sides`` the (inside, outside) domain of each): the tetrahedra, numbered as the
    returned points (``points`` and Netgen's new ones after them), and their domains."""
    used = np.unique(faces)
    local = np.full(len(points), -1)
    local[used] = np.arange(len(used))
    mesh = NetgenMesh(dim=3)
    ids = [mesh.Add(MeshPoint(Pnt(*p))) for p in points[used]]
    kinds = sorted({tuple(int(d) for d in pair) for pair in sides})
    for k, (inside, outside) in enumerate(kinds):
        mesh.Add(FaceDescriptor(surfnr=k + 1, domin=inside, domout=outside, bc=k + 1))
    for face, pair in zip(local[faces], sides, strict=True):
        mesh.Add(Element2D(kinds.index(tuple(int(d) for d in pair)) + 1,
                           [ids[i] for i in face]))
    try:
        interruptible(lambda: mesh.GenerateVolumeMesh(mp=MeshingParameters(maxh=maxh)))
    except Exception as err:     # Netgen raises its own kinds when the surface is bad
        raise ParameterError(f"fsaverage: Netgen could not fill the surfaces ({err})") \
            from None
    elements = list(mesh.Elements3D())
    if not elements:
        raise ParameterError("fsaverage: Netgen made no tetrahedra (the surfaces intersect)")
    filled = np.array([p.p for p in mesh.Points()])
    if not np.allclose(filled[:len(used)], points[used]):
        raise ParameterError("fsaverage: Netgen renumbered the surfaces' vertices")
    number = np.concatenate([used, len(points) + np.arange(len(filled) - len(used))])
    tets = number[np.array([[v.nr - 1 for v in el.vertices] for el in elements])]
    domains = np.array([el.index for el in elements])
    return tets, domains, np.vstack([points, filled[len(used):]])


def cortex_columns(hemisphere="left", ico=4, min_thickness=MIN_THICKNESS):
    """The columns of cortex between corresponding white and pial triangles, off the medial
    wall (where fsaverage's cortex is at least ``min_thickness`` thick at all three corners),
    across which the elements are counted
    (:func:`ngincompat.fem.resolution.elements_across`).

    Returns
    -------
    inner, outer : ndarray (m, 3)
        The centroids of the white and of the pial triangle of each column.
    normal : ndarray (m, 3)
        The mean N of the unit normals of the two triangles, normalised.
    thickness : ndarray (m,)
        The column's extent along N: max - min of N . X over its six corners.
    """
    pial, white, triangles = surfaces(hemisphere, ico)
    keep = np.all(np.linalg.norm(pial - white, axis=1)[triangles] >= min_thickness, axis=1)
    white, _ = cortex(pial, white, triangles, min_thickness)
    columns = triangles[keep]
    normal = sum(_unit_normals(x, columns) for x in (pial, white))
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    corners = np.concatenate([pial[columns], white[columns]], axis=1)
    thickness = np.ptp(np.einsum("kcj,kj->kc", corners, normal), axis=1)
    return white[columns].mean(axis=1), pial[columns].mean(axis=1), normal, thickness


def _unit_normals(points, triangles):
    """The unit normals of triangles."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def fsaverage(hemisphere="left", ico=4, layers=2, min_thickness=MIN_THICKNESS, maxh=1.0):
    """The hemisphere of :func:`build` as an NGSolve mesh, cached in
    :func:`~geometries.voxel_brain.cache_dir` after the first build (written atomically)."""
    path = cache_dir() / (f"fsaverage_{hemisphere}_ico{ico}_L{layers}_t{min_thickness:g}_"
                          f"h{maxh:g}_v{_CACHE_VERSION}.vol.gz")
    if path.is_file():
        return ngs.Mesh(str(path))
    mesh = build(hemisphere, ico, layers, min_thickness, maxh)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.vol.gz")
    mesh.Save(str(tmp))
    os.replace(tmp, path)
    return ngs.Mesh(mesh)
