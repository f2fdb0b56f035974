"""Depth below the surface (Fig. 5e's abscissa) against the closed forms of a spherical
shell: distances R - r and |r - (R - g)|, band volumes 4 pi / 3 (r_1^3 - r_2^3)."""

import ngsolve as ngs
import numpy as np
import pytest

from geometries import brain
from ngincompat.fem import depth

R, G = 1.2, 0.4          # outer radius and gray thickness [cm]


@pytest.fixture(scope="module")
def shell():
    return brain(semi_axes=(R, R, R), gray=G, maxh=0.12, curve_order=2)


def test_distances_from_the_surface_and_the_interface(shell):
    """At the vertices (on or between the spheres), within the facets' sagitta and the
    sampling's spacing (h^2 / 8R + h / 16 < 0.03 cm)."""
    r = np.linalg.norm([v.point for v in shell.vertices], axis=1)
    to_surface = depth.distance(shell, "surface").vec.FV().NumPy()
    to_interface = depth.distance(shell, "interface").vec.FV().NumPy()
    assert np.max(np.abs(to_surface - (R - r))) < 0.03
    assert np.max(np.abs(to_interface - np.abs(r - (R - G)))) < 0.03


def test_mean_thickness_and_band_volumes(shell):
    """T = gray volume / mean area = (R^3 - r^3) / (3/2 (R^2 + r^2)), r = R - g; the band
    0 <= xi < 1/2 is the outer half of the shell, 1 <= xi < 2 the white ball's outer shell of
    thickness T."""
    xi, _, thickness = depth.depth_coordinate(shell)
    r = R - G
    assert thickness == pytest.approx((R ** 3 - r ** 3) / (1.5 * (R ** 2 + r ** 2)), rel=5e-3)
    _, volumes = depth.band_means({}, xi, np.array([0.0, 0.5, 1.0, 2.0]), shell)
    ball = 4 * np.pi / 3
    expected = [ball * (R ** 3 - (R - G / 2) ** 3), ball * ((R - G / 2) ** 3 - (R - G) ** 3),
                ball * ((R - G) ** 3 - (R - G - thickness) ** 3)]
    assert volumes == pytest.approx(expected, rel=0.05)
    means, _ = depth.band_means({"one": ngs.CF(1.0)}, xi, np.array([0.0, 1.0]), shell)
    assert means["one"][0] == pytest.approx(1.0, rel=1e-12)
