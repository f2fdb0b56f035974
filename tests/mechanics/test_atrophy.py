"""ngincompat.mechanics.atrophy: the atrophy law against the closed-form solution of its ODE."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from ngincompat.errors import ParameterError
from ngincompat.fem.transport import logistic, logistic_integral
from ngincompat.mechanics.atrophy import AtrophyLaw, exposure_increment


def closed_form(t, G, theta_min=0.7, c0=0.1, alpha=0.6):
    """theta(t) for a uniform logistic c: theta_min + (1 - theta_min) exp(-G I(t) / span)."""
    span = 1 - theta_min
    return theta_min + span * np.exp(-G * logistic_integral(t, c0, alpha) / span)


def test_closed_form_numbers():
    # brain-scenes.md O-A3
    assert closed_form(np.array([10, 20, 40]), 0.03) == pytest.approx(
        [0.86140, 0.75959, 0.70807], abs=1e-5)
    assert closed_form(40, 0.001) == pytest.approx(0.96593, abs=1e-5)


def test_exact_exposure_gives_the_closed_form_to_round_off():
    law = AtrophyLaw(0.03, 0.7)
    t = np.linspace(0, 40, 9)
    assert law.theta(logistic_integral(t, 0.1, 0.6)) == pytest.approx(closed_form(t, 0.03),
                                                                      rel=1e-14)


def test_stepwise_update_matches_the_ODE_first_order_and_never_passes_theta_min():
    law = AtrophyLaw(0.03, 0.7)
    errors = []
    for dt in (0.4, 0.2, 0.1):
        E = 0.0
        for k in range(1, int(round(40 / dt)) + 1):
            E += exposure_increment(logistic(k * dt, 0.1, 0.6), dt)   # c frozen at c^{n+1}
        errors.append(law.theta(E) - closed_form(40, 0.03))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(rates - 1) < 0.1), (errors, rates)
    # any exposure, however large, stays above theta_min; c outside [0, 1] is clamped
    big = AtrophyLaw(1.0, 0.7)
    assert np.all(big.theta(np.array([0.0, 1.0, 10.0, 1e3])) >= 0.7)
    assert exposure_increment(np.array([-0.1, 0.5, 1.2]), 2.0) == pytest.approx([0, 1, 2])


def test_bad_input_names_the_parameter():
    with pytest.raises(ParameterError, match="rate_gray.*>= 0"):
        AtrophyLaw(-1.0, 0.7, "rate_gray")
    with pytest.raises(ParameterError, match="theta_min.*in \\(0, 1\\)"):
        AtrophyLaw(0.1, 1.0)
    with pytest.raises(ParameterError, match="rate_white.*pass theta_min"):
        AtrophyLaw(4.0, 0.7, "rate_white").check_step(0.1)
    AtrophyLaw(2.9, 0.7).check_step(0.1)


def test_steps_at_frozen_c_compose_into_the_exposure():
    """theta^{n+1} = theta_min + (theta^n - theta_min) exp(-G dt c^{n+1} / (1 - theta_min)),
    step after step from theta = 1, is theta of the summed exposure, whatever the steps."""
    law = AtrophyLaw(0.05, 0.6)
    rng = np.random.default_rng(3)
    dts, cs = rng.uniform(0.1, 3.0, 20), rng.uniform(-0.2, 1.3, 20)
    theta, exposure = 1.0, 0.0
    for dt, c in zip(dts, cs, strict=True):
        theta = 0.6 + (theta - 0.6) * np.exp(-0.05 * dt * np.clip(c, 0, 1) / 0.4)
        exposure += exposure_increment(c, dt)
    assert law.theta(exposure) == pytest.approx(theta, rel=1e-14)
    assert law.theta(0.0) == 1.0


def test_theta_of_a_field_is_the_same_law(unit_cube_hex):
    """With ``exp=ngsolve.exp`` the exposure may be a CoefficientFunction: the values are the
    numpy law's."""
    law = AtrophyLaw(0.03, 0.7)
    exposure = 10 * ngs.x + 5 * ngs.y * ngs.z
    points = random_points(6)
    got = values_at(law.theta(exposure, exp=ngs.exp), unit_cube_hex, points)[:, 0]
    expected = law.theta(10 * points[:, 0] + 5 * points[:, 1] * points[:, 2])
    np.testing.assert_allclose(got, expected, rtol=1e-14)
