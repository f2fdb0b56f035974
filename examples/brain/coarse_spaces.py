"""How BDDC's coarse space meets the atrophy scene's brain mesh: the shape of its tetrahedra
and the CG iterations of one Newton direction of its mixed problem, per coarse space.

    python examples/brain/coarse_spaces.py geometry=fsaverage cortex_layers=2 lam=49

Any setting of the atrophy scene (``key=value``) chooses the mesh; ``lam`` the bulk term
against mu = 1 (49: nu = 0.49, the scene's; 1: a compressible material, to tell the mesh
from the near incompressibility); ``maxiter`` CG's limit; ``coarse`` the coarse spaces
(comma list, default ``edges,vertices``). The problem is the scene's (GrowthMechanics, the
mixed pair with its bubbles), grown by theta = 0.9 in the gray matter and 1 in the white,
its direction the first Newton step's from the reference state.

The shape measure of a tetrahedron is q = 6 sqrt(2) V / l^3, l the root mean square of its
six edges: 1 for the regular tetrahedron, 0 for a flat one (0.77 for the corner of a cube).
"""

import sys
import time

import ngsolve as ngs
import numpy as np

from ngincompat.errors import ParameterError, require
from ngincompat.fem.problem import COARSE_SPACES, GrowthMechanics
from ngincompat.fem.solver import NewtonOptions, NewtonSolver, StepRecord
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.scenes.atrophy import AtrophyScene

PAIRS = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))


def shapes(mesh):
    """q of every tetrahedron of ``mesh`` (its other elements, e.g. a voxel brain's
    hexahedra, are left out)."""
    points = np.array([v.point for v in mesh.vertices])
    corners = points[np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.VOL)
                               if el.type == ngs.ET.TET], dtype=int).reshape(-1, 4)]
    edges = corners[:, 1:] - corners[:, :1]
    volume = np.abs(np.linalg.det(edges)) / 6
    rms = np.sqrt(np.mean([np.sum((corners[:, a] - corners[:, b]) ** 2, axis=1)
                           for a, b in PAIRS], axis=0))
    return 6 * np.sqrt(2) * volume / rms ** 3


def number(text, name, kind, allowed):
    """``text`` as a positive number of ``kind``, or a ParameterError naming ``name``."""
    try:
        value = kind(text)
    except ValueError:
        value = None
    require(value is not None and value > 0, name, text, allowed)
    return value


def main(args):
    """Print the shapes and, per coarse space, the CG iterations (the module's text)."""
    require(all("=" in arg for arg in args), "argument", next((a for a in args if "=" not in a),
                                                                 None), "key=value")
    settings = dict(arg.split("=", 1) for arg in args)
    lam = number(settings.pop("lam", "49"), "lam", float, "a number > 0")
    maxiter = number(settings.pop("maxiter", "3000"), "maxiter", int, "an integer >= 1")
    spaces = settings.pop("coarse", "edges,vertices").split(",")
    for coarse in spaces:
        require(coarse in COARSE_SPACES, "coarse", coarse, " or ".join(COARSE_SPACES))
    scene = AtrophyScene.from_settings(settings)
    mesh = scene.mesh()
    q = shapes(mesh)
    if len(q):
        print(f"tetrahedra {len(q)} of {mesh.ne} elements, shape q: min {q.min():.3g}, 1 % "
              f"{np.percentile(q, 1):.3g}, 10 % {np.percentile(q, 10):.3g}, median "
              f"{np.median(q):.3g}, below 0.05 {int((q < 0.05).sum())}")
    else:
        print(f"no tetrahedra among the {mesh.ne} elements: no shape q")
    ngs.SetNumThreads(1)
    for coarse in spaces:
        growth = IsotropicGrowth(mesh.MaterialCF({"gray": 0.9}, default=1))
        problem = GrowthMechanics(mesh, growth, NeoHookean(mu=1.0, lam=lam), order=scene.order,
                                  formulation="mixed", linear_solver="cg", coarse=coarse)
        solver = NewtonSolver(problem, NewtonOptions(max_iter=1, linear_solver="cg",
                                                     krylov_maxiter=maxiter, line_search=False))
        wirebasket = sum(problem.fes.CouplingType(i) == ngs.COUPLING_TYPE.WIREBASKET_DOF
                         for i in range(problem.fes.ndof))
        record = StepRecord(t=1.0, dt=1.0, converged=False)
        start = time.perf_counter()
        solver.minimise(record)
        print(f"{coarse}: {problem.ndof} unknowns, coarse space {wirebasket}, CG iterations "
              f"{record.linear_iterations}, {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except ParameterError as err:
        sys.exit(f"coarse_spaces.py: {err}")
