"""The Fisher-KPP transport of misfolded protein (ngincompat.fem.transport) against its oracles:
the logistic solution for a uniform seed, and the front speed 2 sqrt(D alpha) on a slab."""

import ngsolve as ngs
import numpy as np
import pytest
from ngsolve.meshes import MakeStructured3DMesh

from ngincompat.errors import ParameterError
from ngincompat.fem.transport import (
    FisherKPP,
    diffusion_tensor,
    logistic,
    logistic_integral,
    minimal_front_speed,
)


def slab(length, h):
    """A slab [0, length] x [0, h] x [0, h] of tetrahedra, one element thick."""
    n = int(round(length / h))
    return MakeStructured3DMesh(hexes=False, nx=n, ny=1, nz=1,
                                mapping=lambda x, y, z: (length * x, h * y, h * z))


def test_logistic_closed_forms():
    # alpha = 0.6, c0 = 0.1: c = 1/2 at t = ln 9 / alpha; I(10) = 6.1991 (brain-scenes.md O-A1)
    assert logistic(np.log(9) / 0.6, 0.1, 0.6) == pytest.approx(0.5, rel=1e-14)
    assert logistic(5.0, 0.1, 0.6) == pytest.approx(0.690568, abs=1e-6)
    assert logistic_integral(10.0, 0.1, 0.6) == pytest.approx(6.1991, abs=1e-4)


def test_uniform_seed_follows_the_logistic_solution_first_order_in_dt():
    mesh = slab(1.0, 0.25)
    errors = []
    for dt in (0.4, 0.2, 0.1):
        p = FisherKPP(mesh, diffusion_tensor(0.015, 0.03, ngs.CF((1, 0, 0))), 0.6, 0.1)
        for _ in range(int(round(10 / dt))):
            p.step(dt)
        c = p.c.vec.FV().NumPy()
        assert np.ptp(c) < 1e-13          # uniform stays uniform: no spurious diffusion
        errors.append(c[0] - logistic(10.0, 0.1, 0.6))
        assert p.integral() == pytest.approx(c[0] * ngs.Integrate(1, mesh), rel=1e-12)
    # backward Euler lags the logistic growth (error < 0), halving with dt
    assert errors[0] == pytest.approx(-3.51e-3, abs=1e-5)
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(rates - 1) < 0.05), rates


def test_without_diffusion_every_vertex_follows_its_own_logistic_growth():
    """D = 0 (d_ext = d_axn = 0: the form is zero, which NGSolve refused to build from the
    integrand): a seed varying along the slab grows in place, each vertex as the uniform
    seed of its own c0, within the first-order lag of backward Euler (dt 0.1: 4e-4)."""
    mesh = slab(1.0, 0.25)
    p = FisherKPP(mesh, diffusion_tensor(0.0, 0.0), 0.6, 0.05 + 0.1 * ngs.x)
    c0 = p.c.vec.FV().NumPy().copy()
    for _ in range(100):
        p.step(0.1)
    c = p.c.vec.FV().NumPy()
    assert np.ptp(c0) > 0.09
    np.testing.assert_allclose(c, logistic(10.0, c0, 0.6), atol=1e-3)
    assert np.all(c < logistic(10.0, c0, 0.6))       # the lag of backward Euler


def front_speed(h, dt, length=50.0, T=20.0):
    """Speed of the c = 1/2 front on a slab (D = alpha = 1) by a linear fit over [T/2, T],
    with the smallest c seen."""
    mesh = slab(length, h)
    p = FisherKPP(mesh, diffusion_tensor(1.0), 1.0, ngs.exp(-ngs.x ** 2))
    pts = np.array([v.point for v in mesh.vertices])
    on_axis = np.flatnonzero((np.abs(pts[:, 1]) < 1e-12) & (np.abs(pts[:, 2]) < 1e-12))
    on_axis = on_axis[np.argsort(pts[on_axis, 0])]
    x = pts[on_axis, 0]
    times, fronts, c_min = [], [], 1.0
    for _ in range(int(round(T / dt))):
        p.step(dt)
        c = p.c.vec.FV().NumPy()[on_axis]    # P1: vertex k carries dof k
        i = int(np.flatnonzero(c < 0.5)[0])
        fronts.append(x[i - 1] + (0.5 - c[i - 1]) * (x[i] - x[i - 1]) / (c[i] - c[i - 1]))
        times.append(p.t)
        c_min = min(c_min, p.minimum())
    times, fronts = np.array(times), np.array(fronts)
    late = times >= T / 2
    return np.polyfit(times[late], fronts[late], 1)[0], c_min


def bramson_speed(T=20.0, D=1.0, alpha=1.0):
    """The slope over [T/2, T] of x_f = c* t - (3/2) sqrt(D/alpha) ln t (Bramson): what a
    fit of the exact front gives, below c*."""
    t = np.linspace(T / 2, T, 200)
    x = minimal_front_speed(D, alpha) * t - 1.5 * np.sqrt(D / alpha) * np.log(t)
    return np.polyfit(t, x, 1)[0]


def test_front_speed_converges_under_refinement():
    reference = bramson_speed()
    assert reference < minimal_front_speed(1.0, 1.0) == 2.0
    results = [front_speed(h, dt) for h, dt in ((1.0, 0.2), (0.5, 0.1))]
    errors = [abs(v - reference) for v, _ in results]
    assert errors[1] < 0.6 * errors[0], (results, reference)
    assert all(c_min >= 0 for _, c_min in results)


@pytest.mark.slow
def test_front_speed_approaches_the_minimal_speed_from_below():
    c_star = minimal_front_speed(1.0, 1.0)
    speeds = [front_speed(h, dt)[0] for h, dt in ((0.5, 0.1), (0.25, 0.05), (0.125, 0.025))]
    errors = np.abs(np.array(speeds) - bramson_speed())
    assert np.all(np.diff(errors) < 0), speeds
    assert speeds[-1] < c_star and errors[-1] < 0.05 * c_star, speeds


def test_bad_input():
    mesh = slab(1.0, 0.5)
    with pytest.raises(ParameterError, match="alpha"):
        FisherKPP(mesh, diffusion_tensor(1.0), -1.0, 0.1)
    with pytest.raises(ParameterError, match="dt"):
        FisherKPP(mesh, diffusion_tensor(1.0), 1.0, 0.1).step(0.0)


def test_upwinding_keeps_c_nonnegative_on_a_sheared_mesh():
    # shearing a structured mesh makes obtuse tetrahedra: K has positive off-diagonals
    mesh = MakeStructured3DMesh(hexes=False, nx=10, ny=10, nz=3,
                                mapping=lambda x, y, z: (x + 0.6 * y, y, z))
    seed = ngs.exp(-((ngs.x - 0.5) ** 2 + (ngs.y - 0.5) ** 2) / 0.005)
    minima = {}
    for monotone in (False, True):
        p = FisherKPP(mesh, diffusion_tensor(0.01), 0.6, seed, monotone=monotone)
        assert p.minimum() >= 0                   # nodal interpolation of the seed
        c_min = 1.0
        for _ in range(10):
            p.step(0.05)
            c_min = min(c_min, p.minimum())
        assert p.maximum() <= 1
        minima[monotone] = c_min
    assert minima[False] < -1e-3                  # the plain Galerkin stiffness undershoots
    assert minima[True] >= 0


def test_axonal_diffusion_acts_along_the_axons_only():
    """On a slab where c varies along X1, D = d_ext I + d_axn e1 (x) e1 acts as the isotropic
    d_ext + d_axn; with axons across the slab (e2) it acts as d_ext alone (up to the
    discretisation: the tetrahedra make c vary a little across the slab)."""
    mesh = slab(20.0, 1.0)
    seed = ngs.exp(-ngs.x ** 2)

    def run(D):
        p = FisherKPP(mesh, D, 1.0, seed)
        for _ in range(10):
            p.step(0.2)
        return p.c.vec.FV().NumPy().copy()

    along = run(diffusion_tensor(0.5, 0.5, ngs.CF((1, 0, 0))))
    across = run(diffusion_tensor(0.5, 0.5, ngs.CF((0, 1, 0))))
    spread = np.max(np.abs(along - across))
    assert spread > 0.05
    assert np.max(np.abs(along - run(diffusion_tensor(1.0)))) < 0.1 * spread
    assert np.max(np.abs(across - run(diffusion_tensor(0.5)))) < 0.1 * spread
