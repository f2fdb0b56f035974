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
X3 = inferior -> superior (MNI z): the axes of the idealized brain. The body is centred at the
middle of its bounding box. Only the largest face-connected part of the brain is kept (a
floating island would add rigid motions).
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


#: Bumped whenever the meshing rule changes, so that stale cached meshes are not read.
_CACHE_VERSION = 1


def cache_dir():
    """Where built meshes are kept: $NGINCOMPAT_CACHE, else ~/.cache/ngincompat."""
    default = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "ngincompat"
    return Path(os.environ.get("NGINCOMPAT_CACHE", default))


def mni152(maxh=1.0):
    """The adult brain of the MNI ICBM152 2009 template, meshed with hexahedra.

    The gray- and white-matter probability maps (2 mm) ship inside the ``nilearn`` wheel
    (``pip install -e ".[brain]"``): nothing is downloaded. The mesh is cached in
    :func:`cache_dir` after the first build.

    Parameters
    ----------
    maxh : float
        Voxel edge in cm, rounded to a multiple of the template's 0.2 cm, in [0.4, 2].

    Returns
    -------
    ngsolve.Mesh
        Hexahedra with materials ``gray`` and ``white``; boundaries ``surface`` and
        ``interface``.
    """
    require(0.4 <= maxh <= 2.0, "maxh", maxh, "in [0.4, 2] cm for the mni152 brain")
    try:
        from nilearn import datasets
    except ImportError:
        raise ParameterError("geometry = mni152 needs nilearn: pip install -e \".[brain]\"") \
            from None
    block = int(round(maxh / 0.2))
    path = cache_dir() / f"mni152_{block * 2}mm_v{_CACHE_VERSION}.vol.gz"
    if path.is_file():
        return ngs.Mesh(str(path))
    gray = datasets.load_mni152_gm_template(resolution=2)
    white = datasets.load_mni152_wm_template(resolution=2)
    mesh = voxel_mesh(np.asarray(gray.get_fdata()), np.asarray(white.get_fdata()),
                      gray.affine, block)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.vol.gz")
    mesh.ngmesh.Save(str(tmp))
    os.replace(tmp, path)
    return mesh


def from_nifti(path, maxh=1.0):
    """A brain from a user's NIfTI label image: 1 = gray matter, 2 = white matter, other
    values outside; coarsened to voxels of about ``maxh`` cm (an integer number of the
    image's voxels).

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
                          image.affine, block)
    except ParameterError as err:
        raise ParameterError(f"geometry = {path}: {err}") from None


def voxel_mesh(gray, white, affine, block=1):
    """Hexahedra on the voxels of a brain given as gray/white fractions or probabilities.

    Parameters
    ----------
    gray, white : ndarray
        3-D arrays of the same shape, values in [0, 1].
    affine : ndarray
        4x4 voxel -> world (mm) transform of the images.
    block : int
        Voxels per coarse voxel edge (block averages).
    """
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
    return _hex_mesh(label, np.asarray(affine, float)[:3, :3] * block)


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


def _hex_mesh(label, step):
    """The Netgen hexahedral mesh of the labelled voxels (1 gray, 2 white), in cm, centred
    (so the images' origin does not matter); ``step`` maps voxel indices to mm."""
    cells = np.argwhere(label > 0)
    corners = (cells[:, None, :] + _CORNERS[None, :, :]).reshape(-1, 3)
    nodes, index = np.unique(corners, axis=0, return_inverse=True)
    index = index.reshape(-1, 8)
    world = (nodes @ step.T) / 10.0 @ _AXES.T                  # mm -> cm, axes
    world -= (world.min(axis=0) + world.max(axis=0)) / 2
    if np.linalg.det(step @ _AXES.T) < 0:       # keep hexahedra positively oriented
        index = index[:, [0, 3, 2, 1, 4, 7, 6, 5]]
        faces = {k: v[::-1] for k, v in _FACES.items()}
    else:
        faces = _FACES
    m = NetgenMesh(dim=3)
    points = [m.Add(MeshPoint(Pnt(*p))) for p in world]
    m.SetMaterial(1, "gray")
    m.SetMaterial(2, "white")
    for (i, j, k), ids in zip(cells, index, strict=True):
        m.Add(Element3D(int(label[i, j, k]), [points[n] for n in ids]))
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
            m.Add(Element2D(fd, [points[ids[c]] for c in face]))
    return ngs.Mesh(m)

