"""geometries.brain: a gray shell around a white ellipsoid, semi-axes along e1-e3, checks."""

import math

import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import OCCGeometry

from geometries import brain, brain_geometry
from ngincompat.errors import ParameterError


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(brain, {}, 4 / 3 * math.pi * 8.5 * 7 * 6, {"surface", "interface"},
                        {"gray", "white"}, 2.5)


def test_brain_gray_shell_volume():
    mesh = brain(maxh=2.5)
    white = ngs.Integrate(1, mesh, definedon=mesh.Materials("white"))
    assert white == pytest.approx(4 / 3 * math.pi * 8.2 * 6.7 * 5.7, rel=5e-3)


def test_a_round_brain_has_the_spheres_areas_and_volumes():
    """Semi-axes 2, 2, 2 and a shell of 0.5: the surface and the interface are spheres of
    radius 2 and 1.5, the gray matter the shell between them."""
    mesh = brain(semi_axes=(2, 2, 2), gray=0.5, maxh=0.5)
    for name, radius in (("surface", 2.0), ("interface", 1.5)):
        area = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries(name))
        assert area == pytest.approx(4 * math.pi * radius ** 2, rel=2e-3), name
    gray = ngs.Integrate(1, mesh, definedon=mesh.Materials("gray"))
    assert gray == pytest.approx(4 / 3 * math.pi * (2 ** 3 - 1.5 ** 3), rel=5e-3)


def test_the_semi_axes_lie_along_e1_e2_e3():
    """Semi-axes 3, 2, 1.5 (front-back, left-right, up-down): the vertices' extents along
    X1, X2, X3 are the semi-axes, centred at the origin."""
    mesh = brain(semi_axes=(3.0, 2.0, 1.5), gray=0.5, maxh=1.0, curve_order=1)
    points = np.array([v.point for v in mesh.vertices])
    np.testing.assert_allclose(points.max(axis=0), (3.0, 2.0, 1.5), rtol=2e-2)
    np.testing.assert_allclose(points.min(axis=0), (-3.0, -2.0, -1.5), rtol=2e-2)
    assert np.all(np.sum((points / (3.0, 2.0, 1.5)) ** 2, axis=1) <= 1 + 1e-9)


def test_the_geometry_alone_is_an_unmeshed_occ_geometry_of_the_same_body():
    """:func:`brain_geometry` (for a mesh made on one rank) holds the same two solids: its
    mesh has the builder's materials and boundaries."""
    geometry = brain_geometry(semi_axes=(2.0, 1.5, 1.0), gray=0.4)
    assert isinstance(geometry, OCCGeometry)
    mesh = ngs.Mesh(geometry.GenerateMesh(maxh=1.0))
    assert set(mesh.GetMaterials()) == {"gray", "white"}
    assert set(mesh.GetBoundaries()) == {"surface", "interface"}


@pytest.mark.parametrize("kwargs, name", [
    (dict(gray=4.0), "gray"), (dict(semi_axes=(1, 2)), "semi_axes"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        brain(**kwargs)


@pytest.mark.parametrize("kwargs, name", [
    (dict(semi_axes=(8.5, 0.0, 6.0)), "semi_axes"), (dict(gray=0.0), "gray"),
    (dict(semi_axes=(2.0, 2.0, 2.0), gray=1.0), "gray"),
])
def test_the_geometry_refuses_what_the_builder_refuses(kwargs, name):
    """A semi-axis > 0; the shell thinner than half the smallest semi-axis."""
    with pytest.raises(ParameterError, match=f"^{name} = "):
        brain_geometry(**kwargs)
