"""geometries.cylinder: the cylinder along e1 on the planes X2 = 0, X3 = 0, named faces, checks."""

import math

import ngsolve as ngs
import numpy as np
import pytest

from geometries import cylinder
from ngincompat.errors import ParameterError


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(cylinder, {}, math.pi / 4, {"left", "right", "mantle"}, {"tissue"}, 0.3)


def test_the_cylinder_rests_on_the_coordinate_planes_with_its_axis_along_e1():
    """Cross-section 2 mm^2 (radius sqrt(2 / pi)), length 3: the volume is area x length,
    the end faces have the cross-section's area at X1 = 0 and X1 = length, centred on the
    axis X2 = X3 = radius; the body touches X2 = 0 and X3 = 0 and lies above them."""
    area, length = 2.0, 3.0
    radius = math.sqrt(area / math.pi)
    mesh = cylinder(area=area, length=length, maxh=0.4)
    assert ngs.Integrate(1, mesh) == pytest.approx(area * length, rel=2e-3)
    for name, level in (("left", 0.0), ("right", length)):
        region = mesh.Boundaries(name)
        got = ngs.Integrate(1, mesh, ngs.BND, definedon=region)
        assert got == pytest.approx(area, rel=2e-3), name
        centre = [ngs.Integrate(c, mesh, ngs.BND, definedon=region) / got
                  for c in (ngs.x, ngs.y, ngs.z)]
        assert centre == pytest.approx((level, radius, radius), abs=1e-6), name
    mantle = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("mantle"))
    assert mantle == pytest.approx(2 * math.pi * radius * length, rel=2e-3)
    points = np.array([v.point for v in mesh.vertices])
    # the vertices lie on the circle: inside the square [0, 2 radius]^2, near its sides
    assert np.all(points[:, 1:] >= -1e-12) and np.all(points[:, 1:] <= 2 * radius + 1e-12)
    assert np.all(points[:, 1:].min(axis=0) < 1e-2 * radius)
    assert np.all(points[:, 1:].max(axis=0) > (2 - 1e-2) * radius)


def test_the_material_is_named_as_asked():
    assert cylinder(maxh=0.5, material="gel").GetMaterials() == ("gel",)


def test_invalid_dimensions_are_clear_errors():
    with pytest.raises(ParameterError, match="^area = "):
        cylinder(area=0)


def test_a_non_positive_length_is_a_clear_error():
    with pytest.raises(ParameterError, match="^length = -1 .*> 0"):
        cylinder(length=-1)
