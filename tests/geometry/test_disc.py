"""geometries.disc: the flat disc's volume, named faces and checked dimensions."""

import math

import ngsolve as ngs
import pytest

from geometries import disc
from ngincompat.errors import ParameterError


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(disc, {}, 0.5 * math.pi, {"bottom", "top", "rim"}, {"tissue"}, 0.3)


def test_faces_lie_where_the_docstring_puts_them():
    """R0 = 2, height 0.4: bottom and top are discs of area pi R0^2 at X3 = 0 and X3 =
    height, the rim a mantle of area 2 pi R0 height centred on the axis at mid-height."""
    R0, height = 2.0, 0.4
    mesh = disc(R0=R0, height=height, maxh=0.5)
    assert ngs.Integrate(1, mesh) == pytest.approx(math.pi * R0 ** 2 * height, rel=2e-3)
    for name, level in (("bottom", 0.0), ("top", height)):
        region = mesh.Boundaries(name)
        area = ngs.Integrate(1, mesh, ngs.BND, definedon=region)
        assert area == pytest.approx(math.pi * R0 ** 2, rel=2e-3), name
        assert ngs.Integrate((ngs.z - level) ** 2, mesh, ngs.BND,
                             definedon=region) == pytest.approx(0.0, abs=1e-20), name
    rim = mesh.Boundaries("rim")
    area = ngs.Integrate(1, mesh, ngs.BND, definedon=rim)
    assert area == pytest.approx(2 * math.pi * R0 * height, rel=2e-3)
    centre = [ngs.Integrate(c, mesh, ngs.BND, definedon=rim) / area
              for c in (ngs.x, ngs.y, ngs.z)]
    assert centre == pytest.approx((0.0, 0.0, height / 2), abs=1e-6)
    radius = ngs.sqrt(ngs.x * ngs.x + ngs.y * ngs.y)
    assert ngs.Integrate(radius, mesh, ngs.BND, definedon=rim) / area == pytest.approx(
        R0, rel=1e-3)


def test_the_material_is_named_as_asked():
    assert disc(maxh=0.5, material="gel").GetMaterials() == ("gel",)


@pytest.mark.parametrize("kwargs, name", [
    (dict(height=-0.1), "height"), (dict(curve_order=0), "curve_order"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        disc(**kwargs)


def test_a_non_positive_radius_is_a_clear_error():
    with pytest.raises(ParameterError, match="^R0 = 0 .*> 0"):
        disc(R0=0)
