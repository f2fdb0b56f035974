"""Growth tensors (eq. 13, 18, 23) and the positivity check of theta."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from ngincompat import fields
from ngincompat.errors import ParameterError
from ngincompat.growth import (
    AreaGrowth,
    FiberGrowth,
    IsotropicGrowth,
    TensorGrowth,
    check_positive,
    make_growth,
)

THETA = 1 + 0.5 * ngs.x + 0.2 * ngs.y


@pytest.mark.parametrize("growth", [
    IsotropicGrowth(THETA),
    AreaGrowth(THETA, fields.constant((1.0, 1.0, 0.0))),
    FiberGrowth(THETA, fields.constant((0.0, 2.0, 1.0))),
])
def test_volume_change_is_theta(growth, unit_cube_hex):
    """det Fg = theta for each of the three kinds (section 2.3)."""
    pts = random_points(10)
    np.testing.assert_allclose(values_at(ngs.Det(growth.Fg), unit_cube_hex, pts),
                               values_at(growth.theta, unit_cube_hex, pts), rtol=1e-13)


def test_growth_tensor_forms(unit_cube_hex):
    """Fg maps N0 to N0 for area growth (thickness unchanged), stretches f0 by theta for fiber
    growth and every direction by theta^(1/3) for isotropic growth."""
    pts = random_points(5)
    theta = values_at(THETA, unit_cube_hex, pts)[:, 0]
    n = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    area = AreaGrowth(THETA, fields.constant(n)).Fg
    np.testing.assert_allclose(values_at(area * ngs.CF(tuple(n)), unit_cube_hex, pts),
                               np.tile(n, (5, 1)), atol=1e-14)
    s = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    np.testing.assert_allclose(values_at(area * ngs.CF(tuple(s)), unit_cube_hex, pts),
                               np.sqrt(theta)[:, None] * s, rtol=1e-13)
    f = np.array([0.0, 2.0, 1.0]) / np.sqrt(5)
    fiber = FiberGrowth(THETA, fields.constant(f)).Fg
    np.testing.assert_allclose(values_at(fiber * ngs.CF(tuple(f)), unit_cube_hex, pts),
                               theta[:, None] * f, rtol=1e-13)
    iso = IsotropicGrowth(THETA).Fg
    np.testing.assert_allclose(values_at(iso, unit_cube_hex, pts),
                               np.cbrt(theta)[:, None] * np.eye(3).ravel(), rtol=1e-13)


def test_tensor_growth_takes_theta_from_the_determinant(unit_cube_hex):
    Fg = ngs.CF((1 + ngs.x, 0, 0, 0, 2, 0, 0, 0, 1), dims=(3, 3))
    growth = TensorGrowth(Fg)
    pts = random_points(5)
    np.testing.assert_allclose(values_at(growth.theta, unit_cube_hex, pts)[:, 0],
                               2 * (1 + pts[:, 0]), rtol=1e-14)
    with pytest.raises(ParameterError, match="3x3"):
        TensorGrowth(ngs.CF((1, 2, 3)))


def test_make_growth_by_name():
    assert make_growth("isotropic", THETA).kind == "isotropic"
    assert make_growth("area", THETA, fields.constant("e3")).kind == "area"
    with pytest.raises(ParameterError, match="growth = 'volume' is unknown"):
        make_growth("volume", THETA)
    with pytest.raises(ParameterError, match="needs a direction"):
        make_growth("fiber", THETA)


def test_non_positive_theta_is_an_error_that_names_where(unit_cube_hex):
    time = ngs.Parameter(0.0)
    check_positive(1 + ngs.x * time, unit_cube_hex, time)
    with pytest.raises(ParameterError, match=r"theta = 0 at X = \(1, [0-9.]+, [0-9.]+\), t = 0.5:"):
        check_positive(1 - 2 * ngs.x * time, unit_cube_hex, time)
    assert time.Get() == 0.0  # the caller's time is restored
    with pytest.raises(ParameterError, match="positive"):
        check_positive(ngs.log(ngs.x), unit_cube_hex)


def test_bilayer_axon_orientations(unit_cube_hex):
    """Straight axons are normal to the interface; curved ones fan out from the focus below
    the middle; concentric ones are orthogonal to the curved ones and to e2 (in-plane)."""
    pts = random_points(12)
    straight = values_at(fields.axons("straight").cf, unit_cube_hex, pts)
    np.testing.assert_allclose(straight, np.tile([0, 0, 1.0], (12, 1)))
    curved = values_at(fields.axons("curved", interface=0.95, length=1.0).cf, unit_cube_hex, pts)
    concentric = values_at(fields.axons("concentric", interface=0.95, length=1.0).cf,
                           unit_cube_hex, pts)
    np.testing.assert_allclose(np.linalg.norm(curved, axis=1), 1, rtol=1e-12)
    np.testing.assert_allclose(np.sum(curved * concentric, axis=1), 0, atol=1e-12)
    np.testing.assert_allclose(concentric[:, 1], 0, atol=1e-12)
    focus = np.array([0.5, 0.0, 0.95 - 3.0])
    d = pts - focus
    d[:, 1] = 0
    np.testing.assert_allclose(curved, d / np.linalg.norm(d, axis=1)[:, None], rtol=1e-12)
    with pytest.raises(ParameterError, match="axons = 'wavy'"):
        fields.axons("wavy")
