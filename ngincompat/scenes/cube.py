"""The cube of section 3.1: isotropic volume growth driven by a unidirectional field."""

from dataclasses import dataclass
from typing import Literal

import ngsolve as ngs

from geometries import cube, estimate
from ngincompat import parallel
from ngincompat.errors import require
from ngincompat.incompatibility.operators import lattice_normals
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.scenes import prescribed
from ngincompat.scenes.base import LENGTH_FLOOR, MAXH, ORDER, param


@dataclass(frozen=True)
class CubeScene(prescribed.PrescribedScene):
    """1 x 1 x 1 mm cube, theta = 1 + a X1 t (eq. 50, a = 1/4), t in [0, 1], neo-Hookean
    mu = 0.55 MPa, nu = 0.4, traction-free (rigid-body motions removed).

    Reports b on the planes n_i = Fg e_i / |Fg e_i| (Fig. 1d), S11, S22, S33 (Fig. 1f), Psi and
    Curl Fg : Curl Fg along the X1 centre line (Fig. 1g), and G against eq. (16).

    Body, growth and material are symmetric about the mid-planes X2 = X3 = side / 2, so
    ``model = "quarter"`` solves the quarter X2, X3 <= side / 2 with the normal displacement
    held on those planes: the same solution at a quarter of the elements (the strain energy
    is reported for the whole cube).

    Launched on several MPI ranks (``mpiexec -n N ngincompat run cube ...``), the mesh is
    distributed over ranks 1 to N - 1 (:mod:`ngincompat.parallel`).
    """

    name = "cube"
    summary = "section 3.1: isotropic growth theta = 1 + X1 t / 4 of a 1 mm cube"
    # the measurements behind them: docs/measurements/solver-costs.md, "Presets"
    presets = {"preview": dict(maxh=0.5, order=3, g_order=3),
               "paper": dict(elements="hex", maxh=0.25, order=4)}
    variant = ("model", "formulation")
    distributed = True

    # a tissue sample: bodies of at most a metre, theta = 1 + a X1 t at most 1000-fold per mm
    side: float = param(1.0, "edge length of the cube", "length",
                       range=f"[{LENGTH_FLOOR:g}, 1000]")
    a: float = param(0.25, "growth gradient a in theta = 1 + a X1 t", "1/length",
                     range="[-1000, 1000]")
    order: int = ORDER(6)
    maxh: float = MAXH(0.5)
    elements: Literal["hex", "tet"] = param("tet", "element shape: tet, or hex (the paper's "
                                            "C3D8 layout)")
    model: Literal["full", "quarter"] = param("full", "full cube, or quarter (mirror planes "
                                              "X2 = X3 = side / 2)")

    def __post_init__(self) -> None:
        super().__post_init__()
        require(self.a * self.side > -1, "a", self.a, "> -1 / side (theta stays positive)")
        require(self.quadrature != "symmetric" or self.elements == "tet", "quadrature",
                self.quadrature, "gauss or auto with elements=hex (symmetric rules are for "
                "tetrahedra: elements=tet)")

    def mesh_estimate(self) -> tuple[float, str]:
        return (estimate.cube_elements(side=self.side, maxh=self.maxh, elements=self.elements,
                                       quarter=self.model == "quarter"),
                self.elements)

    def build(self) -> prescribed.PrescribedCase:
        """The mesh and the prescribed-growth case."""
        quarter = self.model == "quarter"
        mesh = parallel.distribute(lambda: cube(side=self.side, maxh=min(self.maxh, self.side),
                                                elements=self.elements, quarter=quarter))
        time = ngs.Parameter(0.0)
        growth = IsotropicGrowth(1 + self.a * ngs.x * time)
        n = lattice_normals(growth.Fg)
        e = [fields.constant(k).cf for k in ("e1", "e2", "e3")]
        mid = self.side / 2
        return prescribed.PrescribedCase(
            scene=self,
            mesh=mesh, growth=growth, material=self.make_material(), time=time,
            planes={"n1": n[0], "n2": n[1], "n3": n[2]},
            line=((0.0, mid, mid), (self.side, mid, mid), "X1"),
            components={f"S{i}{i}": ("S", e[i - 1], e[i - 1]) for i in (1, 2, 3)},
            symmetry={"back": "y", "top": "z"} if quarter else {}, mirror=4 if quarter else 1)
