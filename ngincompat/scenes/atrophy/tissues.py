"""The brain's two tissues, the planes its Burgers vectors are measured on, and its
extent."""

import ngsolve as ngs
import numpy as np

from ngincompat import parallel

#: The tissues, each a material of the mesh.
TISSUES = ("gray", "white")
#: The coordinate planes of Fig. 5d: label -> normal.
PLANES = {"e1": (1, 0, 0), "e2": (0, 1, 0), "e3": (0, 0, 1)}


def bounding_box(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """The lowest and highest coordinates of the mesh's vertices (of all its ranks)."""
    points = np.array([v.point for v in mesh.vertices]).reshape(-1, 3)
    corners = (np.array([points.min(axis=0), points.max(axis=0)]) if len(points)
               else np.empty((0, 3)))
    corners = parallel.gather_rows(mesh, corners)
    return corners.min(axis=0), corners.max(axis=0)
