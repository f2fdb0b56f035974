"""A real brain from voxel images: the MNI ICBM152 template or a user's own segmentation.

The surfaces of a segmented brain are folded at the scale of the voxels; surfacing them
robustly (smoothing, self-intersections, thin gyri) is a project of its own. Here the
segmentation is instead *coarsened* to voxels of edge ``maxh`` (block averages of the
probability maps) and every brain voxel becomes one hexahedron, labelled ``gray`` where the
gray-matter probability exceeds the white, else ``white``: the mesh is conforming by
construction, its element quality is perfect, and the gray/white interface is a staircase
of voxel faces (|b| at the interface then depends on the voxel size, as it depends on h for
the idealized brain).

Coordinates are in cm with X1 = posterior -> anterior (MNI y), X2 = right -> left (- MNI x),
X3 = inferior -> superior (MNI z): the axes of the idealized brain. The points are the images'
world coordinates (their affine, origin included), so a point given in MNI coordinates, such
as a named seed of the atrophy scene, lies where the template has it. Only the largest
face-connected part of the brain is kept (a floating island would add rigid motions).
"""

import os
from pathlib import Path

import ngsolve as ngs
import numpy as np
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NetgenMesh

from ngincompat.errors import ParameterError, require

#: MNI (x, y, z) -> project (X1, X2, X3) = (y, -x, z): a rotation, so orientation is kept.
_AXES = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])

#: The eight corners of a voxel in Netgen's hexahedron order, and its six faces.
_CORNERS = np.array([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                     (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)])
_FACES = {(-1, 0, 0): (0, 4, 7, 3), (1, 0, 0): (1, 2, 6, 5), (0, -1, 0): (0, 1, 5, 4),
          (0, 1, 0): (3, 7, 6, 2), (0, 0, -1): (0, 3, 2, 1), (0, 0, 1): (4, 5, 6, 7)}
#: The six tetrahedra of a voxel (Kuhn): the paths from corner 0 = (0,0,0) to 6 = (1,1,1)
#: along the axes in every order. Every voxel is split alike, so the split is conforming: on
#: each voxel face the diagonal runs from its lowest to its highest corner.
_KUHN = ((0, 1, 2, 6), (0, 1, 5, 6), (0, 3, 2, 6), (0, 3, 7, 6), (0, 4, 5, 6), (0, 4, 7, 6))
#: Element shapes of a voxel mesh.
ELEMENTS = ("hex", "tet")


#: Bumped whenever the meshing rule changes, so that stale cached meshes are not read.
_CACHE_VERSION = 2


def cache_dir():
    """Where built meshes are kept: $NGINCOMPAT_CACHE, else ~/.cache/ngincompat."""
    default = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "ngincompat"
    return Path(os.environ.get("NGINCOMPAT_CACHE", default))


#: The voxel edges of the mni152 brain [cm]: from the template's own 1 mm voxels to 2 cm.
MNI152_MAXH = (0.1, 2.0)
#: The volume of the mni152 brain's voxels [cm^3] (gray + white >= 1/2 in a voxel, the
#: largest part), nearly the same at every edge (docs/measurements/atrophy.md).
MNI152_VOLUME = 1750.0


def mni152_edge(maxh):
    """The voxel edge of the mni152 brain in mm for ``maxh`` in cm (:data:`MNI152_MAXH`,
    else a ParameterError naming it): rounded to the template's 1 mm."""
    low, high = MNI152_MAXH
    require(low <= maxh <= high, "maxh", maxh, f"in [{low:g}, {high:g}] cm for the mni152 brain")
    return int(round(maxh / 0.1))


def mni152_elements(maxh=1.0, elements="hex"):
    """About how many elements :func:`mni152` makes at ``maxh`` (without loading the
    maps): :data:`MNI152_VOLUME` / edge^3 voxels (within 2 % from 1 mm to 1 cm), six
    tetrahedra each with ``elements`` = tet."""
    edge = mni152_edge(maxh) / 10.0
    return MNI152_VOLUME / edge ** 3 * (6 if elements == "tet" else 1)


def mni152(maxh=1.0, elements="hex"):
    """The adult brain of the MNI ICBM152 2009 template, meshed with hexahedra (or each
    voxel split into six tetrahedra).

    The gray- and white-matter probability maps ship inside the ``nilearn`` wheel at the
    template's 1 mm (``pip install -e ".[brain]"``): nothing is downloaded. nilearn also
    gives them resampled to 2 mm: a voxel edge of an even number of mm is made of blocks of
    those (the meshes this brain had before the 1 mm maps were read), an odd one of blocks
    of the 1 mm maps. The mesh is cached in :func:`cache_dir` after the first build.

    Parameters
    ----------
    maxh : float
        Voxel edge in cm, rounded to a multiple of the template's 0.1 cm, in [0.1, 2]
        (:data:`MNI152_MAXH`); about :data:`MNI152_VOLUME` / maxh^3 hexahedra
        (:func:`mni152_elements`).
    elements : str
        ``hex`` or ``tet`` (:data:`ELEMENTS`).

    Returns
    -------
    ngsolve.Mesh
        Hexahedra (tetrahedra) with materials ``gray`` and ``white``; boundaries
        ``surface`` and ``interface``.
    """
    edge = mni152_edge(maxh)                        # mm
    require(elements in ELEMENTS, "elements", elements, " or ".join(ELEMENTS))
    try:
        from nilearn import datasets
    except ImportError:
        raise ParameterError("geometry = mni152 needs nilearn: pip install -e \".[brain]\"") \
            from None
    resolution = 2 if edge % 2 == 0 else 1          # mm: the maps the blocks are made of
    block = edge // resolution
    path = cache_dir() / f"mni152_{edge}mm_{elements}_v{_CACHE_VERSION}.vol.gz"
    if path.is_file():
        return ngs.Mesh(str(path))
    gray = datasets.load_mni152_gm_template(resolution=resolution)
    white = datasets.load_mni152_wm_template(resolution=resolution)
    mesh = voxel_mesh(np.asarray(gray.get_fdata()), np.asarray(white.get_fdata()),
                      gray.affine, block, elements)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.vol.gz")
    mesh.ngmesh.Save(str(tmp))
    os.replace(tmp, path)
    return mesh


def from_nifti(path, maxh=1.0, elements="hex"):
    """A brain from a user's NIfTI label image: 1 = gray matter, 2 = white matter, other
    values outside; coarsened to voxels of about ``maxh`` cm (an integer number of the
    image's voxels), each a hexahedron or six tetrahedra (``elements``).

    Raises
    ------
    ParameterError
        The file cannot be read as NIfTI, or holds no gray and white voxels.
    """
    try:
        import nibabel
    except ImportError:
        raise ParameterError(f"geometry = {path} needs nibabel: pip install -e \".[brain]\"") \
            from None
    if not Path(path).is_file():
        raise ParameterError(f"geometry = {path}: no such file")
    try:
        image = nibabel.load(str(path))
        labels = np.asarray(image.get_fdata())
    except Exception as err:   # nibabel raises many kinds for files it cannot read
        raise ParameterError(f"geometry = {path}: not a readable NIfTI label image "
                             f"({type(err).__name__}: {err})") from None
    if labels.ndim > 3 and all(n == 1 for n in labels.shape[3:]):
        labels = labels.reshape(labels.shape[:3])          # (x, y, z, 1): one volume
    require(labels.ndim == 3, "geometry", path, "a 3-D NIfTI label image")
    labels = np.rint(labels)                               # labels stored as floats
    size = float(np.mean(np.linalg.norm(image.affine[:3, :3], axis=0))) / 10.0   # mm -> cm
    block = max(1, int(round(maxh / size)))
    try:
        return voxel_mesh((labels == 1).astype(float), (labels == 2).astype(float),
                          image.affine, block, elements)
    except ParameterError as err:
        raise ParameterError(f"geometry = {path}: {err}") from None


def voxel_mesh(gray, white, affine, block=1, elements="hex"):
    """Hexahedra (or six tetrahedra each) on the voxels of a brain given as gray/white
    fractions or probabilities.

    Parameters
    ----------
    gray, white : ndarray
        3-D arrays of the same shape, values in [0, 1].
    affine : ndarray
        4x4 voxel -> world (mm) transform of the images.
    block : int
        Voxels per coarse voxel edge (block averages).
    elements : str
        ``hex`` or ``tet`` (:data:`ELEMENTS`).
    """
    require(elements in ELEMENTS, "elements", elements, " or ".join(ELEMENTS))
    require(gray.shape == white.shape, "segmentation", gray.shape, "gray and white images "
            "of one shape")
    g, w = _coarsen(gray, block), _coarsen(white, block)
    inside = _largest_part(g + w >= 0.5)
    if not inside.any():
        raise ParameterError("the segmentation has no brain voxels (gray + white >= 1/2)")
    label = np.where(inside, np.where(g >= w, 1, 2), 0)
    for value, tissue in ((1, "gray"), (2, "white")):
        if not (label == value).any():
            raise ParameterError(f"the segmentation has no {tissue} voxels after coarsening "
                                 f"to blocks of {block}")
    return _voxel_ngmesh(label, np.asarray(affine, float), block, elements)


def _coarsen(a, block):
    """Block averages of a 3-D array (the shape cut to a multiple of ``block``)."""
    n = [s // block for s in a.shape]
    a = a[:n[0] * block, :n[1] * block, :n[2] * block]
    return a.reshape(n[0], block, n[1], block, n[2], block).mean(axis=(1, 3, 5))


def _largest_part(mask):
    from scipy import ndimage

    parts, count = ndimage.label(mask)
    if count <= 1:
        return mask
    sizes = np.bincount(parts.ravel())[1:]
    return parts == 1 + int(np.argmax(sizes))


def _voxel_ngmesh(label, affine, block, elements):
    """The Netgen mesh of the labelled blocks (1 gray, 2 white) of ``block`` voxels a side,
    in the world coordinates of the images' ``affine`` (voxel centres -> mm, so a voxel
    spans its index +- 1/2) in cm on the project's axes. Hexahedra are kept positively
    oriented, tetrahedra (:data:`_KUHN`) negatively, as Netgen has them; the boundary faces
    point out of the tissue they bound (triangles: split along the same diagonal as the
    tetrahedra)."""
    cells = np.argwhere(label > 0)
    corners = (cells[:, None, :] + _CORNERS[None, :, :]).reshape(-1, 3)
    nodes, index = np.unique(corners, axis=0, return_inverse=True)
    index = index.reshape(-1, 8)
    mm = (nodes * block - 0.5) @ affine[:3, :3].T + affine[:3, 3]
    world = mm / 10.0 @ _AXES.T                                 # mm -> cm, axes
    mirrored = np.linalg.det(affine[:3, :3] @ _AXES.T) < 0
    faces = {k: v[::-1] for k, v in _FACES.items()} if mirrored else _FACES
    if elements == "hex":
        volumes = [[0, 3, 2, 1, 4, 7, 6, 5] if mirrored else list(range(8))]
    else:
        volumes = [_oriented(tet, negative=not mirrored) for tet in _KUHN]
    m = NetgenMesh(dim=3)
    points = [m.Add(MeshPoint(Pnt(*p))) for p in world]
    m.SetMaterial(1, "gray")
    m.SetMaterial(2, "white")
    for (i, j, k), ids in zip(cells, index, strict=True):
        for local in volumes:
            m.Add(Element3D(int(label[i, j, k]), [points[ids[c]] for c in local]))
    m.Add(FaceDescriptor(surfnr=1, domin=1, domout=0, bc=1))
    m.Add(FaceDescriptor(surfnr=2, domin=2, domout=0, bc=1))
    m.Add(FaceDescriptor(surfnr=3, domin=1, domout=2, bc=2))
    m.SetBCName(0, "surface")
    m.SetBCName(1, "surface")
    m.SetBCName(2, "interface")
    padded = np.pad(label, 1)
    for (i, j, k), ids in zip(cells, index, strict=True):
        own = label[i, j, k]
        for (di, dj, dk), face in faces.items():
            other = padded[i + 1 + di, j + 1 + dj, k + 1 + dk]
            if other == own or (own == 2 and other == 1):
                continue                       # inner face, or the gray side's copy
            fd = 1 + (own - 1) if other == 0 else 3
            for part in (_triangles(face) if elements == "tet" else [face]):
                m.Add(Element2D(fd, [points[ids[c]] for c in part]))
    return ngs.Mesh(m)


def _oriented(tet, negative):
    """The tetrahedron's local corners ordered so that its volume in voxel coordinates has
    the sign asked for."""
    a, b, c, d = (_CORNERS[v] for v in tet)
    if (np.linalg.det(np.array([b - a, c - a, d - a])) < 0) == negative:
        return list(tet)
    return [tet[0], tet[2], tet[1], tet[3]]


def _triangles(face):
    """A voxel face (corners in cyclic order) as two triangles of the same orientation, cut
    along the diagonal from its lowest to its highest corner (that of :data:`_KUHN`)."""
    low = min(range(4), key=lambda k: _CORNERS[face[k]].sum())
    a, b, c, d = (face[(low + k) % 4] for k in range(4))
    return [(a, b, c), (a, c, d)]
