"""ngincompat.scenes.atrophy.tissues: the brain's tissues, the planes of its Burgers vectors
and the extent of a mesh."""

import numpy as np
import pytest

from geometries import brain, cube
from ngincompat.scenes.atrophy.tissues import PLANES, TISSUES, bounding_box


def test_the_planes_are_the_coordinate_planes_by_their_unit_normals():
    normals = np.array(list(PLANES.values()), dtype=float)
    np.testing.assert_array_equal(normals, np.eye(3))
    assert list(PLANES) == ["e1", "e2", "e3"]


def test_the_tissues_are_the_materials_of_the_brain_mesh():
    mesh = brain(semi_axes=(3.0, 2.5, 2.0), gray=0.5, maxh=1.5, curve_order=1)
    assert set(TISSUES) == set(mesh.GetMaterials())


@pytest.mark.parametrize("side", [1.0, 2.5])
def test_the_bounding_box_of_a_cube_is_its_corners(side):
    low, high = bounding_box(cube(side=side, maxh=side / 2))
    np.testing.assert_allclose(low, [0.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(high, [side] * 3, atol=1e-12)


def test_the_bounding_box_of_the_ellipsoid_is_its_semi_axes():
    """The vertices of the ellipsoid lie in it, on its surface: the box is within +-(a, b, c)
    and reaches it to a fraction of the mesh size (the vertex nearest a pole)."""
    axes = np.array([3.0, 2.5, 2.0])
    low, high = bounding_box(brain(semi_axes=tuple(axes), gray=0.5, maxh=1.0, curve_order=1))
    for corner in (high, -low):
        assert np.all(corner <= axes + 1e-9) and np.all(corner >= axes - 0.05)
