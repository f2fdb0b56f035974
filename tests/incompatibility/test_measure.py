"""The one incompatibility measurement of every scene (ngincompat.incompatibility.measure)."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import l2_norm, values_at

from ngincompat import sampling
from ngincompat.incompatibility import operators as inc
from ngincompat.incompatibility.measure import Incompatibility
from ngincompat.mechanics.growth import IsotropicGrowth

#: theta = 1 + 0.3 X1 + 0.2 X2^2 + 0.4 X3^2: Burgers vectors on all three coordinate
#: planes, the largest on a different plane in different places.
THETA = 1 + 0.3 * ngs.x + 0.2 * ngs.y ** 2 + 0.4 * ngs.z ** 2
PLANES = {"e1": (1, 0, 0), "e2": (0, 1, 0), "e3": (0, 0, 1)}


def _grad():
    return ngs.CF((0.3, 0.4 * ngs.y, 0.8 * ngs.z))


def test_the_exact_path_gives_eq16_and_the_paper_planes_burgers_vectors(unit_cube_hex):
    measured = Incompatibility.exact(IsotropicGrowth(THETA).Fg, PLANES)
    closed = inc.G_isotropic_closed_form(THETA, _grad())
    assert l2_norm(measured.G - closed, unit_cube_hex) < 1e-12 * l2_norm(closed, unit_cube_hex)
    fields = measured.fields()
    for label, n in PLANES.items():
        expected = closed.trans * ngs.CF(n)           # eq. (11), from eq. (16)
        assert l2_norm(fields[f"b_{label}"] - expected, unit_cube_hex) < 1e-12
    assert measured.Fg_h is None


def test_the_projected_path_converges_to_the_exact_one(unit_cube_hex):
    exact = Incompatibility.exact(IsotropicGrowth(THETA).Fg, PLANES).G
    errors = [l2_norm(Incompatibility.projected(IsotropicGrowth(THETA).Fg, unit_cube_hex,
                                                order, PLANES).G - exact, unit_cube_hex)
              for order in (2, 4)]
    assert errors[1] < 0.1 * errors[0]


def test_the_field_names_are_one_set_and_the_largest_burgers_vector_is_pointwise(
        unit_cube_hex):
    fields = Incompatibility.exact(IsotropicGrowth(THETA).Fg, PLANES).fields()
    assert set(fields) == {"G", "curlFg_sq", "|b|",
                           *(f"b_{p}" for p in PLANES), *(f"|b_{p}|" for p in PLANES)}
    points = [(0.5, 0.5, 0.05), (0.1, 0.1, 0.9), (0.5, 0.9, 0.9)]
    largest = values_at(fields["|b|"], unit_cube_hex, points)
    each = np.array([values_at(fields[f"|b_{p}|"], unit_cube_hex, points) for p in PLANES])
    assert np.allclose(largest, each.max(axis=0), rtol=0, atol=1e-15)
    # the planes take turns: a plane that is largest everywhere would not test the max
    assert sorted(np.argmax(each[:, :, 0], axis=0)) == [0, 1, 2]


def test_burgers_max_is_the_largest_of_the_planes_maxima(unit_cube_hex):
    measured = Incompatibility.exact(IsotropicGrowth(THETA).Fg, PLANES)
    fields = measured.fields()
    assert measured.burgers_max(unit_cube_hex) == pytest.approx(
        sampling.maximum(fields["|b|"], unit_cube_hex), rel=1e-14)
    assert measured.burgers_max(unit_cube_hex) > 0
    assert Incompatibility.exact(IsotropicGrowth(THETA).Fg, {}).burgers_max(unit_cube_hex) == 0


def test_norm_L2_of_G_against_the_closed_form(unit_cube_hex):
    measured = Incompatibility.exact(IsotropicGrowth(THETA).Fg, PLANES)
    closed = inc.G_isotropic_closed_form(THETA, _grad())
    expected = ngs.Integrate(ngs.InnerProduct(closed, closed), unit_cube_hex, order=10) ** 0.5
    assert measured.norm_L2(unit_cube_hex, 10) == pytest.approx(expected, rel=1e-12)
    assert measured.norm_L2(unit_cube_hex, 10, scale=4) == pytest.approx(2 * expected,
                                                                          rel=1e-12)


def test_uniform_growth_has_no_incompatibility(unit_cube_hex):
    measured = Incompatibility.projected(IsotropicGrowth(ngs.CF(1.3)).Fg, unit_cube_hex, 2,
                                         PLANES)
    assert measured.burgers_max(unit_cube_hex) < 1e-10      # round-off of the interpolation
    assert measured.Fg_h is not None
