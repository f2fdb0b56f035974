"""Stresses, energy density, local components and sampling of fields.

Stresses come from symbolic differentiation of the same energy that the solver minimises, so
they can never disagree with it: with W(F) = Jg Psi(F Fg^-1) per reference volume,

    P = dW/dF (first Piola-Kirchhoff),  S = F^-1 P (second Piola-Kirchhoff, eq. 32),
    sigma = P F^T / J (Cauchy).
"""

from collections.abc import Callable, Mapping, Sequence

import ngsolve as ngs
import numpy as np
from netgen.libngpy._meshing import NgException

from ngincompat import parallel
from ngincompat.mechanics import kinematics


def stresses(energy_density: Callable[[ngs.CoefficientFunction], ngs.CoefficientFunction],
             u: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
    """P, S and sigma of a displacement GridFunction.

    Parameters
    ----------
    energy_density : callable
        W(F), the strain energy per reference volume (``GrowthMechanics.energy_density``).
    u : ngsolve.GridFunction
        The displacement.

    Returns
    -------
    dict of CoefficientFunction
        ``P``, ``S``, ``sigma`` (3x3) and ``W`` (scalar).
    """
    F = kinematics.deformation_gradient(u).MakeVariable()
    W = energy_density(F)
    P = W.Diff(F)
    return {"P": P, "S": ngs.Inv(F) * P, "sigma": (1.0 / ngs.Det(F)) * P * F.trans, "W": W}


def largest_principal_value(T: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """The largest eigenvalue of a symmetric 3x3 CoefficientFunction in closed form (the
    trigonometric solution of the characteristic cubic): with q = tr T / 3,
    p = sqrt(|T - q I|^2 / 6) and r = det((T - q I) / p) / 2 in [-1, 1],

        lambda_max = q + 2 p cos(arccos(r) / 3),

    and q where p = 0 (T = q I). A few dozen flops per point against the iterative ``Eig``
    (``docs/measurements/solver-costs.md``, the prescribed scenes); the two agree to round-off
    amplified by arccos near double eigenvalues (1e-8 relative to p at worst)."""
    q = ngs.Trace(T) / 3
    D = T - q * ngs.Id(3)
    p = ngs.sqrt(ngs.InnerProduct(D, D) / 6)
    safe = ngs.IfPos(p - 1e-300, p, 1.0)
    r = ngs.Det(D / safe) / 2
    r = ngs.IfPos(r - 1, 1.0, ngs.IfPos(-1 - r, -1.0, r))
    return (q + 2 * p * ngs.cos(ngs.acos(r) / 3)).Compile()


def component(T: ngs.CoefficientFunction, a: ngs.CoefficientFunction,
              b: ngs.CoefficientFunction | None = None) -> ngs.CoefficientFunction:
    """The component a . T b of a tensor in a local basis (b defaults to a)."""
    return ngs.InnerProduct(a, T * (a if b is None else b))


def sample_line(mesh: ngs.Mesh, cfs: Mapping[str, ngs.CoefficientFunction],
                start: Sequence[float] | np.ndarray,
                end: Sequence[float] | np.ndarray,
                n: int = 101) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Values of CoefficientFunctions at ``n`` equally spaced points from ``start`` to ``end``.

    Returns
    -------
    s : ndarray
        The arc-length coordinate of the points, from 0.
    values : dict
        name -> ndarray of shape (n,) for scalars or (n, k) for vector/matrix fields; NaN at
        points the mesh does not cover. On a distributed mesh, each point's values are those
        of the lowest rank whose part holds it, on every rank.
    """
    start, end = np.asarray(start, float), np.asarray(end, float)
    s = np.linspace(0.0, 1.0, n)
    pts = start + np.outer(s, end - start)
    located = _locatable(mesh, pts)
    points = [None if q is None else mesh(*q) for q in located]
    values = {}
    for name, cf in cfs.items():
        size = int(np.prod(cf.dims))
        v = np.array([np.full(size, np.nan) if p is None else np.atleast_1d(cf(p))
                      for p in points], dtype=float).reshape(n, size)
        v = parallel.first_found(mesh, v)
        values[name] = v[:, 0] if v.shape[1] == 1 else v
    return s * np.linalg.norm(end - start), values


def sample_plane(mesh: ngs.Mesh, cfs: Mapping[str, ngs.CoefficientFunction],
                 origin: Sequence[float],
                 e_u: Sequence[float], e_v: Sequence[float], u: Sequence[float] | np.ndarray,
                 v: Sequence[float] | np.ndarray) -> dict[str, np.ndarray]:
    """Values of CoefficientFunctions on the grid of points origin + u_i e_u + v_j e_v.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    cfs : dict
        Name -> CoefficientFunction.
    origin, e_u, e_v : sequence of 3 floats
        A point of the plane and its two in-plane directions.
    u, v : 1-D arrays
        The grid's coordinates along ``e_u`` (columns) and ``e_v`` (rows).

    Returns
    -------
    dict
        Name -> array of shape (len(v), len(u)) for a scalar, (len(v), len(u), k) for a
        field of k components; NaN at points the mesh does not hold. On a distributed mesh,
        each point's values are those of the lowest rank whose part holds it, on every rank.
    """
    U, V = np.meshgrid(np.asarray(u, float), np.asarray(v, float))
    pts = (np.asarray(origin, float) + np.multiply.outer(U.ravel(), np.asarray(e_u, float))
           + np.multiply.outer(V.ravel(), np.asarray(e_v, float)))
    mips = mesh(pts[:, 0], pts[:, 1], pts[:, 2])
    inside = mips["nr"] >= 0
    out = {}
    for name, cf in cfs.items():
        size = int(np.prod(cf.dims))
        values = np.full((U.size, size), np.nan)
        if inside.any():
            values[inside] = np.asarray(cf(mips[inside])).reshape(-1, size)
        values = parallel.first_found(mesh, values)
        out[name] = values.reshape(U.shape + ((size,) if size > 1 else ()))
    return out


def _locatable(mesh: ngs.Mesh, pts: np.ndarray) -> list[np.ndarray | None]:
    """Move points that lie on or just outside a curved boundary (the mesh approximates it)
    towards the centre of the set, by at most 3 % of their distance, until the mesh finds them;
    None for a point still outside (a coarse straight-sided mesh of a curved body): its
    values are NaN. On a distributed mesh a point is moved only until some rank finds it (the
    same point on every rank); None on the ranks whose part does not hold it."""
    centre = pts.mean(axis=0)
    out: list[np.ndarray | None] = [None] * len(pts)
    todo = np.arange(len(pts))
    for shift in (1e-9, 1e-4, 1e-3, 1e-2, 3e-2):
        moved = pts[todo] + shift * (centre - pts[todo])
        here = np.array([_holds(mesh, q) for q in moved], dtype=bool)
        for i, q in zip(todo[here], moved[here], strict=True):
            out[i] = q
        anywhere = np.isfinite(parallel.first_found(mesh, np.where(here, 1.0, np.nan)))
        todo = todo[~anywhere]
    return out


def _holds(mesh: ngs.Mesh, q: np.ndarray) -> bool:
    """Whether the mesh (this rank's part) finds the point q."""
    try:
        ngs.x(mesh(*q))
    except NgException:
        return False
    return True
