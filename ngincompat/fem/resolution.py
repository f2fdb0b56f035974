"""How many elements a mesh stacks across a layer: the resolution of a thin tissue such as
the cortex (issue: at least 2 quadratic elements across its thickness).

The layer is given by segments from its inner side to its outer one (e.g. from the centroid
of a white-surface triangle to that of the pial triangle above it) with a direction N each.
For a segment, with T the layer's extent along N there (given), P_1 .. P_s the ``samples``
points (k - 1/2) / s of the way along the segment and E(P) the element of ``material`` that
contains P,

    across = T / median_k (extent of E(P_k) along N),

where the extent of a set of points along N is max N . X - min N . X. A layer of elements
cut from prisms counts once, however the prisms are cut into tetrahedra.

On a distributed mesh every rank measures the points in its own elements and the ranks'
values are merged (:func:`ngincompat.parallel.first_found`), so the measure is that of the
whole mesh on every rank.
"""

import ngsolve as ngs
import numpy as np

from ngincompat import parallel


def elements_across(mesh: ngs.Mesh, inner: np.ndarray, outer: np.ndarray, normal: np.ndarray,
                    thickness: np.ndarray, material: str = "gray",
                    samples: int = 16) -> np.ndarray:
    """The number of elements across the layer at each segment (see the module).

    Parameters
    ----------
    mesh : ngsolve.Mesh
        Whole or one rank's part of a distributed mesh.
    inner, outer : ndarray (m, 3)
        The segments' ends.
    normal : ndarray (m, 3)
        Unit directions across the layer.
    thickness : ndarray (m,)
        The layer's extent along ``normal`` at each segment.
    material : str
        The elements counted; points in others (or outside the mesh) are skipped.

    Returns
    -------
    ndarray (m,)
        NaN where no sample point is in an element of ``material``.
    """
    s = (np.arange(samples) + 0.5) / samples
    flat = (inner[:, None, :] + s[None, :, None] * (outer - inner)[:, None, :]).reshape(-1, 3)
    extent: np.ndarray = np.full(len(flat), np.nan)
    if mesh.ne:
        found = np.asarray(mesh(flat[:, 0], flat[:, 1], flat[:, 2])["nr"])
        elements = list(mesh.Elements(ngs.VOL))
        corners: list[list[int]] | np.ndarray = [[v.nr for v in el.vertices] for el in elements]
        most = max(map(len, corners))       # repeating a vertex leaves the extent alone
        corners = np.array([c + c[:1] * (most - len(c)) for c in corners], dtype=int)
        counted = np.array([el.mat == material for el in elements])
        points = np.array([v.point for v in mesh.vertices]).reshape(-1, 3)
        hit = np.flatnonzero(found >= 0)
        hit = hit[counted[found[hit]]]
        directions = np.repeat(normal, samples, axis=0)[hit]
        along = np.einsum("kvj,kj->kv", points[corners[found[hit]]], directions)
        extent[hit] = np.ptp(along, axis=1)
    extent = parallel.first_found(mesh, extent).reshape(-1, samples)
    with np.errstate(invalid="ignore"):
        median = np.full(len(inner), np.nan)
        some = np.any(np.isfinite(extent), axis=1)
        median[some] = np.nanmedian(extent[some], axis=1)
    return np.asarray(thickness, dtype=float) / median
