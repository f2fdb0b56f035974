"""The linear bifurcation analysis of a growing layer on a substrate, against closed forms:
the homogeneous state, isotropic elasticity, Biot's surface instability and the thin-film
limit."""

import numpy as np
import pytest

from ngincompat.errors import ParameterError
from ngincompat.references import bifurcation
from ngincompat.references.bifurcation import (
    Bilayer,
    critical_growth,
    determinant,
    moduli,
    onset,
    prebuckled_cortex,
    stroh_matrix,
    thin_film,
)


@pytest.mark.parametrize("ratio, lambda3, s11, s22", [
    (10, 1.15940, -0.67251, -0.35626), (100, 1.19488, -0.73643, -0.42957),
    (1000, 1.19947, -0.74462, -0.43893)])
def test_homogeneous_cortex_at_theta_1_2(ratio, lambda3, s11, s22):
    """sigma33 = 0 solved for lambda3 with eq. (36), lam / mu = ratio (values derived
    separately, to 5 digits)."""
    state = prebuckled_cortex(1.2, 1.0, ratio)
    assert state.lambda3 == pytest.approx(lambda3, abs=1e-5)
    assert state.sigma11 == pytest.approx(s11, abs=1e-5)
    assert state.sigma22 == pytest.approx(s22, abs=1e-5)


def test_incompressible_limit_of_the_homogeneous_cortex():
    """lambda3 -> theta, sigma11 -> mu (theta^-2 - theta^2), sigma22 -> mu (1 - theta^2)."""
    theta, mu = 1.3, 2.0
    state = prebuckled_cortex(theta, mu, 1e7 * mu)
    assert state.lambda3 == pytest.approx(theta, rel=1e-6)
    assert state.sigma11 == pytest.approx(mu * (theta ** -2 - theta ** 2), rel=1e-5)
    assert state.sigma22 == pytest.approx(mu * (1 - theta ** 2), rel=1e-5)


def test_moduli_of_the_reference_state_are_linear_elasticity():
    mu, lam = 1.5, 4.0
    A = moduli(np.eye(3), np.eye(3), mu, lam)
    d = np.eye(3)
    expected = (lam * np.einsum("ij,kl->ijkl", d, d) + mu * (np.einsum("ik,jl->ijkl", d, d)
                + np.einsum("il,jk->ijkl", d, d)))
    np.testing.assert_allclose(A, expected, atol=1e-12)


def test_isotropic_substrate_has_double_exponents_plus_minus_k():
    """Plane-strain isotropic elasticity: the solutions of a sin/cos mode grow and decay like
    exp(+-k X3) and X3 exp(+-k X3)."""
    k = 7.0
    K = stroh_matrix(moduli(np.eye(3), np.eye(3), 1.0, 3.0), k)
    exponents = np.sort(np.linalg.eigvals(K).real)
    np.testing.assert_allclose(exponents, [-k, -k, k, k], rtol=1e-6)


def test_a_deep_grown_half_space_buckles_at_biots_stretch():
    """The whole body grows: its elastic stretch 1/theta reaches Biot's 0.543689 (incompressible
    neo-Hookean, plane strain) for every wavelength short against the depth."""
    body = Bilayer(height=0.2, cortex=0.2, mu_cortex=1.0, lam_cortex=1e4, mu_sub=1.0,
                   lam_sub=1e4)
    assert critical_growth(body, 50.0, resolution=0.01) == pytest.approx(1 / 0.543689,
                                                                         rel=1e-4)


def test_stiff_thin_film_meets_the_thin_film_formula():
    """mu_f / mu_s = 1000 on a deep substrate: critical strain (1/4)(3 mu_s/mu_f)^(2/3) and
    wavelength 2 pi t (mu_f / 3 mu_s)^(1/3), both nearly incompressible."""
    film = Bilayer(height=40.0, cortex=0.05, mu_cortex=1000.0, lam_cortex=1e6, mu_sub=1.0,
                   lam_sub=1e3)
    first = onset(film, k_range=(0.5, 20.0), theta_max=1.1, resolution=0.0005)
    growth, wavelength = thin_film(1000.0, 1.0, 0.05)
    assert first.growth - 1 == pytest.approx(growth - 1, rel=0.01)
    assert first.wavelength == pytest.approx(wavelength, rel=0.01)


def test_a_deep_layer_is_carried_only_as_deep_as_its_growing_solutions_need(monkeypatch):
    """A short wavelength in a deep substrate (k h = 3,000): carried :data:`SATURATION` / 2k
    deep, the basis spans the same growing solutions as carried through all of it, the
    determinant keeps its sign and its root, in a few dozen sub-steps, not thousands."""
    k = 300.0
    deep = Bilayer(height=10.05, cortex=0.05, mu_cortex=3.0, lam_cortex=300.0, mu_sub=1.0,
                   lam_sub=100.0)
    qr, calls = np.linalg.qr, []
    monkeypatch.setattr(np.linalg, "qr", lambda *a: calls.append(1) or qr(*a))
    Z, sign = deep.substrate_basis(k)
    assert len(calls) <= bifurcation.SATURATION
    values = [determinant(deep, k, theta) for theta in (1.2, 2.0)]
    root = critical_growth(deep, k, resolution=0.05)
    deep.substrate_basis.cache_clear()
    deep.cortex_moduli.cache_clear()
    monkeypatch.setattr(bifurcation, "SATURATION", np.inf)
    Z_full, sign_full = deep.substrate_basis(k)
    assert len(calls) > 1000
    np.testing.assert_allclose(Z @ Z.T, Z_full @ Z_full.T, atol=1e-12)
    full = [determinant(deep, k, theta) for theta in (1.2, 2.0)]
    assert np.sign(values) @ np.sign(full) == 2
    assert np.isfinite(root)
    assert critical_growth(deep, k, resolution=0.05) == pytest.approx(root, abs=1e-10)


def test_bad_bilayers_name_the_parameter():
    with pytest.raises(ParameterError, match="cortex = 2"):
        Bilayer(height=1.0, cortex=2.0, mu_cortex=3.0, lam_cortex=300.0, mu_sub=1.0,
                lam_sub=100.0)
    with pytest.raises(ParameterError, match="mu_sub"):
        Bilayer(height=1.0, cortex=0.05, mu_cortex=3.0, lam_cortex=300.0, mu_sub=0.0,
                lam_sub=100.0)
