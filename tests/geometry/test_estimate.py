"""geometries.estimate: element counts before meshing, in closed form, exact for the hex cube."""

import math

import pytest

from geometries import BUILDERS, cube
from geometries import estimate as est


@pytest.mark.parametrize("side, maxh, quarter", [(1.0, 0.25, False), (1.0, 0.3, False),
                                                 (2.0, 0.5, True), (1.0, 0.2, True),
                                                 (3.0, 1.0, False)])
def test_the_hexahedral_cube_is_counted_exactly(side, maxh, quarter):
    """The structured cube has ceil(side / maxh)^3 hexahedra, its quarter n ceil(n / 2)^2:
    the estimate is the mesh's count."""
    mesh = cube(side=side, maxh=maxh, quarter=quarter)
    assert est.cube_elements(side=side, maxh=maxh, quarter=quarter) == mesh.ne


def test_every_builder_has_an_estimate_that_takes_its_keywords():
    """One estimate per builder, by name; keywords that do not change the count (the curve
    order, the material, the footprint) are accepted and ignored."""
    assert set(est.ESTIMATES) == set(BUILDERS)
    for name, guess in est.ESTIMATES.items():
        plain = guess()
        assert plain >= 1, name
        assert guess(curve_order=2, material="x", footprint="circle") == plain, name


def test_tetrahedra_are_cells_of_h_cubed_and_a_thin_extent_counts_one_cell():
    """TETS_PER_CELL per cell of h^3 in the box, times the body's share of it; an extent
    below h counts as one cell (the skin patch is one element thick)."""
    assert est.tets((2.0, 3.0, 4.0), 0.5) == pytest.approx(5.0 * 4 * 6 * 8)
    assert est.tets((2.0, 3.0, 4.0), 0.5, fill=0.5) == pytest.approx(5.0 * 4 * 6 * 8 / 2)
    assert est.tets((2.0, 3.0, 0.1), 0.5) == pytest.approx(5.0 * 4 * 6)
    assert est.triangles((3.0, 1.0), 0.25) == pytest.approx(2.0 * 12 * 4)
    # halving h multiplies a solid's count by 8 and a section's by 4
    assert est.tets((1.0, 1.0, 1.0), 0.05) / est.tets((1.0, 1.0, 1.0), 0.1) == pytest.approx(8)
    assert est.triangles((1.0, 1.0), 0.05) / est.triangles((1.0, 1.0), 0.1) == pytest.approx(4)
    assert est.skin_patch_elements(maxh=1.0) == pytest.approx(5.0 * 10 * 10)


def test_the_grading_around_a_point_is_the_integral_of_the_cell_density():
    """TETS_PER_CELL Omega / g^3 ln(h / h0): nothing when h0 >= h, and additive over an
    intermediate size (the integral over two shells is the integral over their union)."""
    assert est.graded_point(0.5, 0.5) == 0.0 and est.graded_point(0.5, 1.0) == 0.0
    assert est.graded_point(1.0, 0.01, 2 * math.pi) == pytest.approx(
        5.0 * 2 * math.pi / 0.3 ** 3 * math.log(100))
    assert est.graded_point(1.0, 0.01) == pytest.approx(
        est.graded_point(1.0, 0.1) + est.graded_point(0.1, 0.01))


def test_a_curved_surface_caps_the_size_at_half_its_radius():
    assert est.curved(0.25, 1.0) == 0.25
    assert est.curved(0.25, 0.1) == pytest.approx(0.05)
    thin = est.cylinder_elements(area=1e-3, maxh=0.25)
    radius = math.sqrt(1e-3 / math.pi)
    assert thin == pytest.approx(est.tets((2 * radius, 2 * radius, 1.0), 0.5 * radius,
                                          fill=math.pi / 4))


def test_the_hemisphere_quarter_and_centre():
    """The quarter is a quarter of the half ball; a finer centre adds the graded half space
    around it, from the centre's size to the body's."""
    full = est.hemisphere_elements(maxh=0.3)
    assert est.hemisphere_elements(maxh=0.3, quarter=True) == pytest.approx(full / 4)
    graded = est.hemisphere_elements(maxh=0.3, centre_maxh=0.01)
    assert graded - full == pytest.approx(est.graded_point(0.3, 0.01, 2 * math.pi))
    assert full == pytest.approx(est.tets((2.0, 2.0, 1.0), 0.3, fill=math.pi / 6))


def test_the_bilayer_adds_its_fine_cortex_and_the_grading_below_it():
    """Meshed at maxh throughout: the two layers' triangles; a fine cortex meshes the cortex
    at cortex_maxh and adds the strip graded from it, 2 (length / h0) / g triangles."""
    plain = est.bilayer_elements(maxh=0.05)
    assert plain == pytest.approx(est.triangles((3.0, 0.05), 0.05)
                                  + est.triangles((3.0, 0.95), 0.05))
    fine = est.bilayer_elements(maxh=0.1, cortex_maxh=0.01)
    assert fine == pytest.approx(est.triangles((3.0, 0.05), 0.01)
                                 + est.triangles((3.0, 0.95), 0.1) + 2.0 * 300 / 0.3)
    refined = est.bilayer_elements(maxh=0.1, cortex_maxh=0.01, top_maxh=0.005)
    assert refined > fine


@pytest.mark.parametrize("name", sorted(est.ESTIMATES))
def test_an_absurd_size_gives_an_infinite_estimate_never_nan(name):
    huge = {"cube": dict(side=1e308, maxh=1e-308, elements="tet"),
            "hemisphere": dict(R0=1e308, maxh=1e-308),
            "disc": dict(R0=1e308, height=1e308, maxh=1e-308),
            "cylinder": dict(area=1e308, length=1e308, maxh=1e-308),
            "skin_patch": dict(side=1e308, thickness=1e308, maxh=1e-308),
            "bilayer": dict(length=1e308, height=1e308, cortex=1e300, maxh=1e-308),
            "brain": dict(semi_axes=(1e308, 1e308, 1e308), maxh=1e-308)}[name]
    assert math.isinf(est.ESTIMATES[name](**huge))
