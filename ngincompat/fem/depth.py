"""Depth below a body's surface and averages over depth bands: the profile of a field against
the depth from the outer (pial) surface, averaged over the cortex (Fig. 5e of the paper).

The distance from a named boundary is that to points spread over its faces (a barycentric
grid of ``per_edge`` intervals per edge, so at most half a face's edge / ``per_edge`` off),
interpolated linearly between the mesh's vertices. With d_s the distance from the outer
surface, d_i that from the gray/white interface and T the mean cortical thickness (gray
volume over the mean of the surface's and the interface's areas: exact to O((T/R)^2) for a
spherical shell of outer radius R), the depth coordinate is

    xi = d_s / (d_s + d_i)     in gray matter (0 at the surface, 1 at the interface)
    xi = 1 + d_i / T           in white matter,

so a profile against xi averages the cortex over its local thickness.
"""

from collections.abc import Mapping, Sequence

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree

from ngincompat import parallel


def boundary_points(mesh: ngs.Mesh, name: str, per_edge: int = 8) -> np.ndarray:
    """Points spread over the faces of boundary ``name`` (triangles; quadrilaterals cut in
    two): a barycentric grid of ``per_edge`` intervals per edge on each (of every rank's faces
    on a distributed mesh)."""
    points = np.array([v.point for v in mesh.vertices])
    triangles = []
    for el in mesh.Elements(ngs.BND):
        if el.mat != name:
            continue
        corners = [v.nr for v in el.vertices]
        triangles.append(corners[:3])
        if len(corners) == 4:
            triangles.append([corners[0], corners[2], corners[3]])
    k = per_edge
    grid = np.array([(i, j, k - i - j) for i in range(k + 1) for j in range(k + 1 - i)]) / k
    corners = points.reshape(-1, 3)[np.array(triangles, dtype=int).reshape(-1, 3)]  # (m, 3, 3)
    return parallel.gather_rows(mesh, np.einsum("gc,mcx->mgx", grid, corners).reshape(-1, 3))


def distance(mesh: ngs.Mesh, name: str, per_edge: int = 8) -> ngs.GridFunction:
    """The distance from boundary ``name`` as a piecewise linear GridFunction."""
    tree = cKDTree(boundary_points(mesh, name, per_edge))
    gf = ngs.GridFunction(ngs.H1(mesh, order=1))
    if mesh.nv:
        gf.vec.FV().NumPy()[:] = tree.query(np.array([v.point for v in mesh.vertices]))[0]
    return gf


def depth_coordinate(mesh: ngs.Mesh, surface: str = "surface", interface: str = "interface",
                     gray: str = "gray") -> tuple[ngs.CoefficientFunction, ngs.GridFunction, float]:
    """xi of the module's docstring, and the mean cortical thickness T."""
    d_s, d_i = distance(mesh, surface), distance(mesh, interface)
    area = sum(ngs.Integrate(1.0, mesh, ngs.BND, definedon=mesh.Boundaries(name))
               for name in (surface, interface)) / 2
    thickness = ngs.Integrate(1.0, mesh, definedon=mesh.Materials(gray)) / area
    in_gray = mesh.MaterialCF({gray: 1.0}, default=0.0)
    xi = ngs.IfPos(in_gray - 0.5, d_s / (d_s + d_i + 1e-12 * thickness),
                   1.0 + d_i / thickness)
    return xi, d_i, thickness


def band_means(cfs: Mapping[str, ngs.CoefficientFunction], xi: ngs.CoefficientFunction,
               edges: Sequence[float] | np.ndarray, mesh: ngs.Mesh,
               order: int = 4) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The mean of each CoefficientFunction of ``cfs`` over the bands edges[k] <= xi <
    edges[k + 1] (NaN where a band is empty), and the bands' volumes; one integration per
    field, all bands at once."""
    bands = ngs.CF(tuple(ngs.IfPos(xi - low, 1.0, 0.0) * ngs.IfPos(high - xi, 1.0, 0.0)
                         for low, high in zip(edges[:-1], edges[1:], strict=True)))
    volumes = np.atleast_1d(ngs.Integrate(bands, mesh, order=order))
    means = {}
    for key, cf in cfs.items():
        totals = np.atleast_1d(ngs.Integrate(bands * cf, mesh, order=order))
        means[key] = np.where(volumes > 0, totals / np.where(volumes > 0, volumes, 1.0), np.nan)
    return means, volumes
