"""A scene for the user's own geometry and growth field, from the command line, without
writing code.

Example::

    ngincompat run custom --out o --set growth=isotropic --set theta="1 + 0.25*X1*t"
    ngincompat run custom --out o --set growth=fiber --set direction=e1 --set theta="1+X2*t/4"
    ngincompat run custom --out o2 --set mesh=my.msh --set theta="1 + 0.1*X3*t"
    ngincompat run custom --out o3 --set mesh=o/mesh.vol --set theta_file=o/growth.npz

A mesh file (Netgen ``.vol``/``.vol.gz``, or Gmsh ``.msh``, VTK, Abaqus or MEDIT through
meshio, :func:`ngincompat.workflow.inputs.load_mesh`) replaces the geometry builder; a growth
file (``growth.npz`` of an earlier run with ``outputs=growth``, or one value per vertex in
``.npz``/``.csv``/``.txt``) replaces the expression, ramped linearly in t:
theta(X, t) = 1 + t (theta_data(X) - 1).
"""

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import ngsolve as ngs
import numpy as np

from geometries import SOLIDS, estimate
from ngincompat.errors import require
from ngincompat.incompatibility.operators import lattice_normals
from ngincompat.mechanics import fields
from ngincompat.mechanics.expressions import parse_expression
from ngincompat.mechanics.growth import KINDS, make_growth
from ngincompat.mechanics.materials import MATERIALS, MaterialKind, make_material
from ngincompat.scenes import prescribed
from ngincompat.scenes.base import param
from ngincompat.scenes.material import Fibers
from ngincompat.workflow.inputs import (
    GROWTH_EXTENSIONS,
    MESH_EXTENSIONS,
    load_growth,
    load_mesh,
    ramped_growth,
)

_AXES = {"X1": 0, "X2": 1, "X3": 2}


@dataclass(frozen=True)
class CustomScene(Fibers, prescribed.PrescribedScene):
    """Any geometry, growth kind, theta(X1, X2, X3, t) and material.

    theta is a safe expression (see :mod:`ngincompat.mechanics.expressions`) in X1, X2, X3, t, R
    and Rxy;
    ``direction`` is N0 for area growth and f0 for fiber growth; ``fiber`` is the GOH fiber
    family a0. Burgers vectors are reported on the planes n_i = Fg e_i / |Fg e_i|; profiles
    along the ``line`` axis through the centre of the body's bounding box.
    """

    name = "custom"
    summary = "your own geometry, growth kind, theta(X, t) and material"
    variant = ("geometry", "growth", "material")
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=0.5, order=2, g_order=3), "paper": dict(order=5)}

    geometry: str = param("cube", "geometry builder: " + ", ".join(sorted(SOLIDS)),
                          choices=SOLIDS)
    growth: str = param("isotropic", "a registered growth kind: isotropic, area, fiber, ...",
                        choices=KINDS)
    theta: str = param("1 + 0.25*X1*t", "growth indicator theta(X1, X2, X3, t), t in [0, 1]")
    direction: str = param("e3", "N0 (area) or f0 (fiber growth): e1, e2, e3, radial, "
                                 "radial_xy, circumferential")
    material: str = param("neo-hookean", "a registered material: neo-hookean, goh, ...",
                          choices=MATERIALS)
    fiber: str = param("e1", "GOH fiber direction a0 (as direction)")
    line: Literal["X1", "X2", "X3"] = param("X1", "axis of the profile line: X1, X2 or X3")
    mesh: str = param("", "mesh file (.vol, .vol.gz, .msh) instead of the geometry builder")
    theta_file: str = param("", "growth field as data (.npz of a run's outputs=growth, or one "
                                "value per vertex in .npz/.csv/.txt) instead of theta")

    def __post_init__(self) -> None:
        super().__post_init__()
        self.make_material()
        parse_expression(self.theta, name="theta")
        fields.from_name(self.direction)
        fields.from_name(self.fiber, "fiber")
        default = {f.name: f.default for f in dataclasses.fields(self)}
        if self.mesh:
            _check_file("mesh", self.mesh, MESH_EXTENSIONS)
            require(self.geometry == default["geometry"], "geometry", self.geometry,
                    "left unset when a mesh file is given (mesh = file)")
        if self.theta_file:
            _check_file("theta_file", self.theta_file, GROWTH_EXTENSIONS)
            require(self.theta == default["theta"], "theta", self.theta,
                    "left unset when the growth is given as data (theta_file = file)")

    def make_material(self) -> MaterialKind:
        return make_material(self.material, self.mu, self.nu, self.k1, self.k2, self.kappa)

    def mesh_estimate(self) -> tuple[float, str] | None:
        if self.mesh:
            return None
        # the cube builder's default elements are hexahedra
        shape = "hex" if self.geometry == "cube" else "tet"
        return estimate.ESTIMATES[self.geometry](maxh=self.maxh), shape  # type: ignore[operator]

    def build(self) -> prescribed.PrescribedCase:
        mesh = (load_mesh(self.mesh) if self.mesh
                else SOLIDS[self.geometry](maxh=self.maxh))  # type: ignore[operator]
        time = ngs.Parameter(0.0)
        if self.theta_file:
            theta = ramped_growth(load_growth(self.theta_file, mesh), time)
        else:
            theta = parse_expression(self.theta, time, name="theta")
        growth = make_growth(self.growth, theta, fields.from_name(self.direction))
        normals = lattice_normals(growth.Fg)
        lo, hi = _bounding_box(mesh)
        k = _AXES[self.line]
        centre = (lo + hi) / 2
        start, end = centre.copy(), centre.copy()
        start[k], end[k] = lo[k], hi[k]
        e = [fields.constant(a).cf for a in ("e1", "e2", "e3")]
        material = self.make_material()
        return prescribed.PrescribedCase(
            scene=self,
            mesh=mesh, growth=growth, material=material, time=time,
            planes={f"n{i + 1}": n for i, n in enumerate(normals)},
            line=(tuple(start), tuple(end), self.line),
            fibers=(fields.from_name(self.fiber, "fiber"),) if material.needs_fibers else (),
            components={f"S{i}{i}": ("S", e[i - 1], e[i - 1]) for i in (1, 2, 3)},
            analytic=not self.theta_file, expression=None if self.theta_file else self.theta)


def _check_file(name: str, path: str, extensions: tuple[str, ...]) -> None:
    """A file parameter names an existing file of an allowed kind (read later, in build)."""
    try:
        exists = Path(path).is_file()
    except OSError:             # e.g. a name longer than the file system allows
        exists = False
    require(exists, name, path, "an existing file")
    require(str(path).lower().endswith(extensions), name, path,
            "a file ending in " + ", ".join(extensions))


def _bounding_box(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    pts = np.array([v.point for v in mesh.vertices])
    return pts.min(axis=0), pts.max(axis=0)
