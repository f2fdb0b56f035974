"""The skin scene's figures (Fig. 6): the maps at mid-thickness and the profiles along X1."""

from collections.abc import Mapping
from typing import Any

import ngsolve as ngs
import numpy as np

from geometries.skin_patch import SIDE, THICKNESS
from ngincompat.fem import postprocess
from ngincompat.workflow.results import Figure, MapsFigure, ProfileFigure

#: The profile along X1 through the middle ends this far inside the patch's edges [cm], where
#: a point exactly on the edge may be placed outside the mesh by round-off.
LINE_INSET = 0.01

#: The fields of the maps at mid-thickness (Fig. 6 a-c and the compression after release).
MAPS = {"area growth theta [-]": "theta", "|b| on e3 [1/{L}]": "|b|",
        "max principal stress, released [{stress}]": "sigma_max_released",
        "min principal stress, released [{stress}]": "sigma_min_released"}


def mid_plane(mesh: ngs.Mesh, flds: Mapping[str, Any], n: int = 81) -> dict[str, np.ndarray]:
    """The fields of :data:`MAPS` that ``flds`` has on the patch's mid-thickness plane
    X3 = THICKNESS / 2, on an n x n grid (keys "mid_<field>")."""
    u = np.linspace(-SIDE / 2, SIDE / 2, n)
    cfs = {k: flds[k] for k in MAPS.values() if k in flds}
    sampled = postprocess.sample_plane(mesh, cfs, (0, 0, THICKNESS / 2), (1, 0, 0),
                                       (0, 1, 0), u, u)
    return {"mid_u": u, "mid_v": u, **{f"mid_{k}": v for k, v in sampled.items()}}


def figures(scene: Any, grid: Mapping[str, Any]) -> list[Figure]:
    """The profiles along X1 and the maps of the fields that ``grid`` holds."""
    L, stress = scene.units["length"], scene.units["stress"]
    title = scene.title()
    maps = {label.format(L=L, stress=stress): f"mid_{key}" for label, key in MAPS.items()
            if f"mid_{key}" in grid}
    return [
        MapsFigure("fields.png", "mid_u", f"[{L}]", maps, "",
                   f"{title}: mid-thickness (Fig. 6 a-c)", profile="map"),
        ProfileFigure("profile.png", "X1", f"X1 [{L}]", {"area growth theta": "theta"},
                      "area growth theta [-]", f"{title}: bottom face",
                      right={"|b| on e3": "|b|"}, right_label=f"|b| on e3 [1/{L}]"),
        ProfileFigure("stress.png", "X1", f"X1 [{L}]",
                      {"clamped": "sigma_max_clamped", "released": "sigma_max_released"},
                      f"max principal Cauchy stress [{stress}]",
                      f"{title}: residual stress after deflation", floor=1e-3 * scene.mu),
    ]
