"""Stresses from the energy, principal values, local components and line sampling."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from ngincompat import sampling
from ngincompat.fem import postprocess
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.materials import NeoHookean


def test_stresses_are_consistent_with_eq37_and_each_other(unit_cube_hex):
    """For a given u: S = Jg Fg^-1 Se Fg^-T with Se from eq. (37), sigma = F S F^T / J."""
    mesh = unit_cube_hex
    theta = 1 + 0.25 * ngs.x
    material = NeoHookean(0.55, 1.1)
    problem = GrowthMechanics(mesh, IsotropicGrowth(theta), material, order=2)
    problem.u.Set((0.05 * ngs.x * ngs.y, 0.02 * ngs.z, 0.03 * ngs.x))
    st = postprocess.stresses(problem.energy_density, problem.u)
    pts = random_points(8)
    F = np.eye(3) + values_at(ngs.Grad(problem.u), mesh, pts).reshape(-1, 3, 3)
    th = 1 + 0.25 * pts[:, 0]
    S = values_at(st["S"], mesh, pts).reshape(-1, 3, 3)
    sigma = values_at(st["sigma"], mesh, pts).reshape(-1, 3, 3)
    for k in range(len(pts)):
        Fg_inv = th[k] ** (-1 / 3) * np.eye(3)
        Fe = F[k] @ Fg_inv
        Ce, Je = Fe.T @ Fe, np.linalg.det(Fe)
        Se = (1.1 * np.log(Je) - 0.55) * np.linalg.inv(Ce) + 0.55 * np.eye(3)
        np.testing.assert_allclose(S[k], th[k] * Fg_inv @ Se @ Fg_inv.T, rtol=1e-10,
                                   atol=1e-12)
        J = np.linalg.det(F[k])
        np.testing.assert_allclose(sigma[k], F[k] @ S[k] @ F[k].T / J, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(S[k], S[k].T, atol=1e-12)


def test_components_in_a_local_basis(unit_cube_hex):
    T = np.array([[2.0, 0.5, 0.0], [0.5, -1.0, 0.3], [0.0, 0.3, 0.5]])
    cf = ngs.CF(tuple(T.ravel()), dims=(3, 3))
    a = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    b = np.array([0.0, 0.0, 1.0])
    comp = postprocess.component(cf, ngs.CF(tuple(a)), ngs.CF(tuple(b)))
    assert values_at(comp, unit_cube_hex, random_points(1))[0, 0] == pytest.approx(a @ T @ b)


def test_largest_principal_value_in_closed_form(unit_cube_hex):
    """Against numpy's eigvalsh at every element point of a field that is diagonal in its
    first row on X1 = 0, where ``Eig`` does not sort its values, and on repeated and
    isotropic ones (q I, p = 0)."""
    x, y, z = ngs.x, ngs.y, ngs.z
    cf = ngs.CF((1 + x, y * z, 0.3 * x, y * z, 2 * y, 0.1, 0.3 * x, 0.1, z * z), dims=(3, 3))
    pts = sampling.element_points(unit_cube_hex, 4)
    T = np.asarray(cf(pts)).reshape(-1, 3, 3)
    got = np.asarray(postprocess.largest_principal_value(cf)(pts)).ravel()
    np.testing.assert_allclose(got, np.linalg.eigvalsh(T)[:, 2], atol=1e-13)
    p = random_points(1)
    for diagonal, largest in (((2, 2, 2), 2), ((-1, -1, -3), -1), ((1, 1, 3), 3)):
        cf = ngs.CF((diagonal[0], 0, 0, 0, diagonal[1], 0, 0, 0, diagonal[2]), dims=(3, 3))
        got = values_at(postprocess.largest_principal_value(cf), unit_cube_hex, p)[0, 0]
        assert got == pytest.approx(largest, rel=1e-7)


def test_sample_line_includes_boundary_points(unit_cube_hex):
    s, values = postprocess.sample_line(unit_cube_hex, {"x": ngs.x, "v": ngs.CF((ngs.x, 1, 2))},
                                        (0, 0.5, 0.5), (1, 0.5, 0.5), n=11)
    np.testing.assert_allclose(s, np.linspace(0, 1, 11))
    np.testing.assert_allclose(values["x"], np.linspace(0, 1, 11), atol=1e-8)
    assert values["v"].shape == (11, 3)


def test_sample_plane_returns_a_prescribed_linear_field_exactly(unit_cube_tet):
    """On the plane X2 = 0.5 of the unit cube, f = 1 + 2 X1 - 3 X3 sampled on a 7 x 5 grid
    (boundary points included) is f at the grid points; a vector field keeps its components;
    points off the mesh are NaN."""
    u, v = np.linspace(0, 1, 7), np.linspace(0, 1, 5)
    f = 1 + 2 * ngs.x - 3 * ngs.z
    got = postprocess.sample_plane(unit_cube_tet, {"f": f, "w": ngs.CF((ngs.x, ngs.y, ngs.z))},
                                   (0, 0.5, 0), (1, 0, 0), (0, 0, 1), u, v)
    X1, X3 = np.meshgrid(u, v)
    assert got["f"].shape == (5, 7) and got["w"].shape == (5, 7, 3)
    np.testing.assert_allclose(got["f"], 1 + 2 * X1 - 3 * X3, atol=1e-12)
    np.testing.assert_allclose(got["w"][..., 1], 0.5, atol=1e-12)
    outside = postprocess.sample_plane(unit_cube_tet, {"f": f}, (0, 0.5, 0), (1, 0, 0),
                                       (0, 0, 1), [0.5, 1.5], [0.5])["f"]
    assert np.isfinite(outside[0, 0]) and np.isnan(outside[0, 1])
