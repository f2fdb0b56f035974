"""An anatomical brain hemisphere from the FreeSurfer fsaverage pial and white surfaces.

The fsaverage5 surfaces of both hemispheres ship inside the ``nilearn`` wheel (GIfTI, 10242
vertices each, mm in MNI305 space, ``pip install -e ".[brain]"``): nothing is downloaded.
The pial and the white surface of a hemisphere share their triangulation, vertex by vertex
(FreeSurfer grows the pial surface out of the white one). The cortex (gray matter) is the
volume between them, the white matter the volume inside the white surface.

Meshing (measured choices, see the README's atrophy section):

* **resolution**: the fsaverage triangulations are nested icosahedra (the first 2562,
  10242 vertices are those of subdivision 4, 5), so a coarser brain takes the first
  vertices and re-triangulates them as the convex hull of their points on the registration
  sphere; no decimation, and pial and white keep their vertex correspondence. At
  subdivision 3 (642 vertices, 11 mm edges) the pial and white surfaces intersect;
* **tetrahedra**: Netgen fills the two nested closed surfaces from their triangles (kept as
  they are, so the volumes are those the surfaces enclose): gray between them, white inside
  the white one. A layer of prisms between corresponding triangles (the cortex resolved by
  construction) was tried and dropped: 20 of the 5120 prisms of subdivision 4 and 25 of the
  20480 of subdivision 5 are twisted (no split into tetrahedra, not even from their
  centroid), where the pial vertices slide sideways over the white ones;
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
from netgen.meshing import Element2D, FaceDescriptor, MeshingParameters, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh

from ngincompat.errors import ParameterError, require

from .voxel_brain import cache_dir

HEMISPHERES = ("left", "right")
#: Icosahedral subdivision -> number of vertices of the fsaverage surface.
ICO_VERTICES = {4: 2562, 5: 10242}
#: Bumped whenever the meshing rule changes, so that stale cached meshes are not read.
_CACHE_VERSION = 1
#: Thickness below which a vertex is on the medial wall (fsaverage has exactly 0 there) [cm].
_MEDIAL = 1e-3
#: The thinnest cortex meshed [cm] (the medial wall's gray layer).
MIN_THICKNESS = 0.1
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


def build(hemisphere="left", ico=4, min_thickness=MIN_THICKNESS, maxh=1.0):
    """The Netgen mesh of a hemisphere (see the module): materials ``gray`` (cortex) and
    ``white``, boundaries ``surface`` (pial) and ``interface`` (white surface); ``maxh``
    bounds the tetrahedra (in the cortex the surfaces' triangles set their size)."""
    require(0 < min_thickness <= 0.2, "min_thickness", min_thickness, "in (0, 0.2] cm")
    pial, white, triangles = surfaces(hemisphere, ico)
    white, _ = cortex(pial, white, triangles, min_thickness)
    n = len(pial)
    mesh = NetgenMesh(dim=3)
    ids = [mesh.Add(MeshPoint(Pnt(*p))) for p in np.vstack([white, pial])]
    mesh.Add(FaceDescriptor(surfnr=1, domin=1, domout=0, bc=1))
    mesh.Add(FaceDescriptor(surfnr=2, domin=2, domout=1, bc=2))
    mesh.SetMaterial(1, "gray")
    mesh.SetMaterial(2, "white")
    mesh.SetBCName(0, "surface")
    mesh.SetBCName(1, "interface")
    for tri in triangles:
        mesh.Add(Element2D(1, [ids[i + n] for i in tri]))
        mesh.Add(Element2D(2, [ids[i] for i in tri]))
    try:
        mesh.GenerateVolumeMesh(mp=MeshingParameters(maxh=maxh))
    except Exception as err:     # Netgen raises its own kinds when the surfaces are bad
        raise ParameterError(f"fsaverage: Netgen could not fill the surfaces ({err})") \
            from None
    if not mesh.ne:
        raise ParameterError("fsaverage: Netgen made no tetrahedra (the surfaces intersect)")
    return mesh


def elements_across(mesh, hemisphere="left", ico=4, min_thickness=MIN_THICKNESS, samples=64):
    """How many elements the segment from each pial vertex to its white vertex crosses
    (sampled at ``samples`` points): the cortex's resolution, per vertex off the medial
    wall (where fsaverage's cortex is at least ``min_thickness`` thick)."""
    pial, white, triangles = surfaces(hemisphere, ico)
    keep = np.linalg.norm(pial - white, axis=1) >= min_thickness
    white, _ = cortex(pial, white, triangles, min_thickness)
    s = (np.arange(samples) + 0.5) / samples
    points = white[keep, None, :] + s[None, :, None] * (pial - white)[keep, None, :]
    flat = points.reshape(-1, 3)
    found = mesh(flat[:, 0], flat[:, 1], flat[:, 2])
    numbers = np.array([p[-1] for p in found]).reshape(-1, samples)
    return np.array([len(np.unique(row[row >= 0])) for row in numbers])


def fsaverage(hemisphere="left", ico=4, min_thickness=MIN_THICKNESS, maxh=1.0):
    """The hemisphere of :func:`build` as an NGSolve mesh, cached in
    :func:`~geometries.voxel_brain.cache_dir` after the first build (written atomically)."""
    path = cache_dir() / (f"fsaverage_{hemisphere}_ico{ico}_t{min_thickness:g}_"
                          f"h{maxh:g}_v{_CACHE_VERSION}.vol.gz")
    if path.is_file():
        return ngs.Mesh(str(path))
    mesh = build(hemisphere, ico, min_thickness, maxh)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.vol.gz")
    mesh.Save(str(tmp))
    os.replace(tmp, path)
    return ngs.Mesh(mesh)
