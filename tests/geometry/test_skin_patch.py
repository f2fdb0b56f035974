"""geometries.skin_patch: the patch, its marked footprint, footprint areas and sizes, checks."""

import math

import ngsolve as ngs
import pytest

from geometries import FOOTPRINTS, footprint_area, footprint_size, skin_patch
from geometries.skin_patch import SIDE, THICKNESS
from ngincompat.errors import ParameterError


def _area(mesh, name):
    return ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries(name))


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(skin_patch, {"footprint": "circle"}, 30.0,
                        {"footprint", "bottom", "top", "periphery", "footprint_wall"},
                        {"skin"}, 2.0)


@pytest.mark.parametrize("footprint", FOOTPRINTS)
def test_skin_patch_footprints(footprint):
    mesh = skin_patch(footprint=footprint, maxh=2.0)
    area = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("footprint"))
    assert area == pytest.approx(footprint_area(footprint, 5.0), rel=2e-3)
    rest = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("bottom"))
    assert area + rest == pytest.approx(100.0, rel=1e-8)


def test_footprints_of_equal_area():
    sizes = {f: footprint_size(f, 24.5) for f in FOOTPRINTS}
    assert sizes["rectangle"] == pytest.approx(7.0, rel=1e-12)
    assert sizes["square"] == pytest.approx(24.5 ** 0.5, rel=1e-12)
    assert sizes["circle"] == pytest.approx(2 * (24.5 / math.pi) ** 0.5, rel=1e-12)
    for footprint, size in sizes.items():
        mesh = skin_patch(footprint=footprint, footprint_size=size, maxh=2.0)
        area = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("footprint"))
        assert area == pytest.approx(24.5, rel=2e-3), footprint


def test_footprint_areas_in_closed_form():
    """Size 4: the rectangle 4 x 2, the square 4 x 4, the circle of diameter 4, and the
    crescent, a disc of radius r = 2 less its lens with the disc shifted by r:
    pi r^2 - (2 pi / 3 - sqrt(3) / 2) r^2 = (pi / 3 + sqrt(3) / 2) r^2."""
    assert footprint_area("rectangle", 4.0) == pytest.approx(8.0, rel=1e-15)
    assert footprint_area("square", 4.0) == pytest.approx(16.0, rel=1e-15)
    assert footprint_area("circle", 4.0) == pytest.approx(4 * math.pi, rel=1e-15)
    assert footprint_area("crescent", 4.0) == pytest.approx(
        (math.pi / 3 + math.sqrt(3) / 2) * 4, rel=1e-14)


@pytest.mark.parametrize("footprint", FOOTPRINTS)
def test_footprint_size_inverts_the_area(footprint):
    """The area is quadratic in the size: size(area(s)) = s, and four times the area is twice
    the size."""
    for size in (0.5, 3.0, 7.25):
        assert footprint_size(footprint, footprint_area(footprint, size)) == pytest.approx(
            size, rel=1e-14)
    assert footprint_size(footprint, 40.0) == pytest.approx(2 * footprint_size(footprint, 10.0),
                                                            rel=1e-14)


def test_the_patch_faces_at_the_paper_dimensions():
    """The paper's 10 x 10 x 0.3 cm patch: top of area side^2, the four sides of area
    4 side thickness, the bottom and the footprint together side^2; the default footprint is
    the rectangle of size side / 2."""
    mesh = skin_patch(maxh=2.0)
    assert set(mesh.GetMaterials()) == {"skin"}
    assert ngs.Integrate(1, mesh) == pytest.approx(SIDE ** 2 * THICKNESS, rel=1e-8)
    assert _area(mesh, "top") == pytest.approx(SIDE ** 2, rel=1e-8)
    assert _area(mesh, "periphery") == pytest.approx(4 * SIDE * THICKNESS, rel=1e-8)
    assert _area(mesh, "footprint") == pytest.approx(footprint_area("rectangle", SIDE / 2),
                                                     rel=1e-8)
    # the wall stands on the footprint's edge, through the whole thickness
    assert _area(mesh, "footprint_wall") == pytest.approx(3 * SIDE / 2 * THICKNESS, rel=1e-8)


@pytest.mark.parametrize("kwargs, name", [
    (dict(footprint_size=12.0), "footprint_size"),
    (dict(footprint="star"), "footprint"),
    (dict(thickness=20.0), "thickness"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        skin_patch(**kwargs)


def test_an_invalid_footprint_area_is_a_clear_error():
    with pytest.raises(ParameterError, match="^footprint_area = "):
        footprint_size("circle", area=-1.0)


def test_the_footprint_keeps_a_margin_of_one_thickness():
    """The largest footprint is side - 2 thickness: 9.4 cm on the paper's patch."""
    with pytest.raises(ParameterError, match=r"^footprint_size = 9.5 .*in \(0, 9.4\]"):
        skin_patch(footprint_size=9.5)
    with pytest.raises(ParameterError, match="^footprint = 'star' .*rectangle, circle"):
        footprint_size("star", 1.0)
