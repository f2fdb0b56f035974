"""ngincompat.references.radial: the growing ball's 1-D solution against closed forms, scaling."""

import numpy as np
import pytest
from scipy.integrate import quad

from ngincompat.references.radial import solve_radial

#: Lame parameters (nu = 1/3: E / (1 - nu) = 2.2).
MU, LAM = 0.55, 1.1


@pytest.fixture(scope="module")
def linear_growth():
    """theta = 1 + R / 4 in the unit ball: the hemisphere's profile."""
    return solve_radial(lambda R: 1 + R / 4, MU, LAM)


def test_uniform_growth_is_stress_free_and_a_dilation():
    """theta constant: r = theta^(1/3) R and no stress."""
    ref = solve_radial(lambda R: 1.5 + 0 * R, MU, LAM)
    R = np.linspace(0.01, 1.0, 9)
    np.testing.assert_allclose(ref.radius(R), 1.5 ** (1 / 3) * R, rtol=1e-10)
    for sigma in ref.cauchy(R):
        assert np.abs(sigma).max() < 1e-9


def test_small_growth_is_the_linear_thermoelastic_sphere():
    """theta = 1 + eps R is the free strain eps R / 3 of a sphere heated to T ~ R; the linear
    solution (Timoshenko and Goodier, Theory of elasticity, section 151), with
    k = E / (1 - nu): sigma_rr = 2 k eps / 12 (1 - R), sigma_tt = k eps / 3 (1/2 - 3 R / 4),
    to O(eps) relative."""
    eps = 1e-4
    ref = solve_radial(lambda R: 1 + eps * R, MU, LAM)
    E = MU * (3 * LAM + 2 * MU) / (LAM + MU)
    nu = LAM / (2 * (LAM + MU))
    k = E / (1 - nu)
    R = np.linspace(0.05, 1.0, 12)
    sigma_rr, sigma_tt = ref.cauchy(R)
    np.testing.assert_allclose(sigma_rr / eps, 2 * k / 12 * (1 - R), atol=1e-3 * k)
    np.testing.assert_allclose(sigma_tt / eps, k / 3 * (0.5 - 0.75 * R), atol=1e-3 * k)


def test_the_surface_is_free_and_the_centre_isotropic(linear_growth):
    """sigma_rr(R0) = 0; at the centre sigma_rr = sigma_tt (no direction is special), in
    tension: the outer layers, grown more, pull it outward."""
    sigma_rr, sigma_tt = linear_growth.cauchy(np.array([1e-4, 1.0]))
    assert abs(sigma_rr[1]) < 1e-9 * abs(sigma_rr[0])
    assert sigma_rr[0] == pytest.approx(sigma_tt[0], rel=1e-3)
    assert sigma_rr[0] > 0 and sigma_tt[1] < 0


def test_a_free_body_has_zero_mean_stress(linear_growth):
    """Without body force or traction the integral of sigma over the deformed body vanishes
    (div(sigma x x) = sigma): int (sigma_rr + 2 sigma_tt) r^2 dr = 0, here as an integral
    over R with dr = lambda_r dR, lambda_r from the radius' derivative."""
    def trace_density(R, h=1e-6):
        r = linear_growth.radius(R)
        dr = (linear_growth.radius(R + h) - linear_growth.radius(R - h)) / (2 * h)
        sigma_rr, sigma_tt = linear_growth.cauchy(R)
        return (sigma_rr + 2 * sigma_tt) * r * r * dr

    total, _ = quad(trace_density, 1e-5, 1.0, epsabs=1e-14, limit=400)
    size, _ = quad(lambda R: abs(trace_density(R)), 1e-5, 1.0, limit=400)
    assert size > 1e-3
    assert abs(total) < 1e-8 * size


def test_lengths_scale_and_stresses_stay(linear_growth):
    """A ball of radius 2 grown as theta(R / 2): its deformed radii are twice the unit ball's
    at the corresponding points, its stresses the same."""
    big = solve_radial(lambda R: 1 + R / 8, MU, LAM, R0=2.0)
    R = np.linspace(0.05, 1.0, 7)
    np.testing.assert_allclose(big.radius(2 * R), 2 * linear_growth.radius(R), rtol=1e-8)
    for got, expected in zip(big.cauchy(2 * R), linear_growth.cauchy(R), strict=True):
        np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9)


def test_stresses_scale_with_the_moduli_and_the_shape_does_not(linear_growth):
    stiff = solve_radial(lambda R: 1 + R / 4, 10 * MU, 10 * LAM)
    R = np.linspace(0.05, 1.0, 7)
    np.testing.assert_allclose(stiff.radius(R), linear_growth.radius(R), rtol=1e-9)
    for got, expected in zip(stiff.cauchy(R), linear_growth.cauchy(R), strict=True):
        np.testing.assert_allclose(got, 10 * expected, rtol=1e-6, atol=1e-8)
