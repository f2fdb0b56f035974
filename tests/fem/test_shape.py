"""ngincompat.fem.shape: the signed curvature of a fitted circle and the sulci of a line."""

import numpy as np
import pytest

from ngincompat.errors import ParameterError
from ngincompat.fem.shape import circle_curvature, sulci


def _arc(radius, centre, start, stop, n=15):
    angle = np.linspace(start, stop, n)
    return centre[0] + radius * np.cos(angle), centre[1] + radius * np.sin(angle)


def test_the_sign_says_on_which_side_the_centre_lies():
    """An arc bulging toward +z (its centre below it) has curvature +1/R, the same arc
    mirrored (centre above) -1/R."""
    x, z = _arc(2.0, (0.0, 0.0), np.pi / 3, 2 * np.pi / 3)
    assert circle_curvature(x, z) == pytest.approx(0.5, rel=1e-9)
    assert circle_curvature(x, -z) == pytest.approx(-0.5, rel=1e-9)


def test_the_fit_is_invariant_under_rigid_motions_and_scales_as_one_over_length():
    """Points far from the origin and turned by a small angle give the same curvature as the
    arc at the origin; the arc scaled by 1000 has a thousandth of it."""
    x, z = _arc(0.7, (0.0, 0.0), 1.2, 1.9)
    kappa = circle_curvature(x, z)
    assert kappa == pytest.approx(1 / 0.7, rel=1e-9)
    c, s = np.cos(0.2), np.sin(0.2)
    moved = circle_curvature(1e3 + c * x - s * z, -5e2 + s * x + c * z)
    assert moved == pytest.approx(kappa, rel=1e-8)
    assert circle_curvature(1000 * x, 1000 * z) == pytest.approx(kappa / 1000, rel=1e-9)


def test_a_shallow_parabola_has_its_osculating_curvature():
    """z = a x^2 sampled on |x| <= 0.01: the fitted circle is the osculating one at the apex,
    of radius 1 / (2 |a|), its centre above the apex for a > 0 (a valley: curvature -2 a)."""
    x = np.linspace(-0.01, 0.01, 21)
    for a in (0.5, -3.0):
        assert circle_curvature(x, a * x * x) == pytest.approx(-2 * a, rel=1e-3)


def test_a_straight_line_and_a_flat_line_have_no_curvature():
    s = np.linspace(-1.0, 2.0, 9)
    assert circle_curvature(s, 0.3 * s + 1) == pytest.approx(0.0, abs=1e-12)
    assert circle_curvature(s, np.zeros_like(s)) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("x, z", [([0.0, 1.0], [0.0, 1.0]), ([0.0, 1.0, 2.0], [0.0, 1.0]),
                                  ([[0.0, 1.0, 2.0]], [[0.0, 1.0, 2.0]]),
                                  ([1.0, 1.0, 1.0], [2.0, 2.0, 2.0])])
def test_too_few_or_ill_shaped_or_coincident_points_are_refused(x, z):
    with pytest.raises(ParameterError, match="^points = "):
        circle_curvature(x, z)


def test_one_trough_in_the_middle_is_one_sulcus():
    """cos(2 pi x) on [0, 1]: crests on the end planes, a trough of depth 2 at x = 1/2."""
    x = np.linspace(0.0, 1.0, 201)
    count, depth = sulci(np.cos(2 * np.pi * x))
    assert count == 1.0 and depth == pytest.approx(2.0, rel=1e-12)


def test_a_trough_on_an_end_plane_is_half_a_sulcus():
    """cos(pi x) on [0, 1]: its trough lies on the plane x = 1, half of it in the mirror
    image."""
    x = np.linspace(0.0, 1.0, 101)
    assert sulci(np.cos(np.pi * x)) == (0.5, pytest.approx(2.0, rel=1e-12))
    assert sulci(-np.cos(np.pi * x)) == (0.5, pytest.approx(2.0, rel=1e-12))


def test_the_depth_is_below_the_lower_crest():
    """Heights 1, 0, 0.5: a trough between a crest of 1 and one of 0.5 (on the end plane):
    one sulcus, 0.5 deep."""
    assert sulci([1.0, 0.0, 0.5]) == (1.0, 0.5)


def test_ripples_below_the_hysteresis_make_no_sulci():
    """Two troughs of depth 1 with ripples of 0.04 on them: the ripples count at a fraction
    of 1 % of the height, not at the default 10 %."""
    x = np.linspace(0.0, 1.0, 401)
    z = 0.5 * np.cos(4 * np.pi * x) + 0.02 * np.cos(60 * np.pi * x)
    count, depth = sulci(z)
    assert count == 2.0 and depth == pytest.approx(1.0, abs=0.05)
    assert sulci(z, fraction=0.01)[0] > count


def test_a_flat_line_has_no_sulci_and_bad_heights_are_refused():
    assert sulci(np.full(7, 0.3)) == (0.0, 0.0)
    for heights in ([0.0, 1.0], [0.0, np.nan, 1.0], [[0.0, 1.0, 2.0]]):
        with pytest.raises(ParameterError, match="^heights = "):
            sulci(heights)
