"""ngincompat.sampling: element points and boxes, and a field's largest value over the points."""

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat import sampling

XYZ = ngs.CF((ngs.x, ngs.y, ngs.z))


def test_maximum_skips_undefined_points_only(unit_cube_hex):
    """A NaN at the vertex X = 0 (a cone point of 1 / R) is left out; NaN everywhere stays
    NaN."""
    R = ngs.sqrt(ngs.x * ngs.x + ngs.y * ngs.y + ngs.z * ngs.z)
    assert sampling.maximum(ngs.x / R, unit_cube_hex) == pytest.approx(1.0)
    assert np.isnan(sampling.maximum(ngs.sqrt(-1 - ngs.x), unit_cube_hex))


def test_maximum_over_element_points(unit_cube_hex):
    assert sampling.maximum(ngs.x * ngs.y, unit_cube_hex) == pytest.approx(1.0)


def test_argmax_finds_the_value_and_the_point(unit_cube_hex):
    value, where = sampling.argmax(ngs.x * ngs.y - ngs.z, unit_cube_hex)
    assert value == pytest.approx(1.0)
    np.testing.assert_allclose(where, (1, 1, 0), atol=1e-12)


def test_element_points_are_a_rule_and_the_vertices_of_every_element(unit_cube_hex):
    """27 hexahedra: each gives the points of the rule of order 4 and its 8 vertices; on the
    boundary, 54 quadrilaterals give their rule's points and 4 vertices each. All points lie
    in the cube, every corner of it among them."""
    for vb, et, elements, vertices in ((ngs.VOL, ngs.ET.HEX, 27, 8),
                                       (ngs.BND, ngs.ET.QUAD, 54, 4)):
        points = np.asarray(XYZ(sampling.element_points(unit_cube_hex, 4, vb))).reshape(-1, 3)
        rule = len(ngs.IntegrationRule(et, 4).points)
        assert len(points) == elements * (rule + vertices)
        assert points.min() >= -1e-14 and points.max() <= 1 + 1e-14
        corners = {(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)}
        assert corners <= {tuple(p) for p in np.round(points, 12)}
        if vb == ngs.BND:       # every point on a face of the cube
            assert np.abs(np.minimum(points, 1 - points).min(axis=1)).max() < 1e-14


def test_the_element_boxes_of_a_structured_mesh_are_its_cells(unit_cube_hex):
    """The straight hexahedra of the 3 x 3 x 3 cube: each box is a cell [i, i + 1] / 3 in every
    direction, and the 27 boxes are the 27 cells."""
    lo, hi = sampling.element_boxes(unit_cube_hex)
    assert lo.shape == hi.shape == (27, 3)
    np.testing.assert_allclose(hi - lo, 1 / 3, rtol=1e-12)
    cells = {tuple(c) for c in np.round(3 * lo).astype(int)}
    assert cells == {(i, j, k) for i in range(3) for j in range(3) for k in range(3)}
    np.testing.assert_allclose(3 * lo, np.round(3 * lo), atol=1e-12)


def test_the_element_boxes_of_tetrahedra_hold_their_vertices(unit_cube_tet):
    lo, hi = sampling.element_boxes(unit_cube_tet)
    points = np.array([v.point for v in unit_cube_tet.vertices])
    for k, el in enumerate(unit_cube_tet.Elements(ngs.VOL)):
        corners = points[[v.nr for v in el.vertices]]
        np.testing.assert_allclose(lo[k], corners.min(axis=0), atol=1e-14)
        np.testing.assert_allclose(hi[k], corners.max(axis=0), atol=1e-14)


def test_the_maximum_of_a_field_whose_peak_is_inside_an_element(unit_cube_hex):
    """1 - |X - c|^2 peaks at c = (0.5, 0.5, 0.5), the centre of the middle element, an
    integration point of the (3-point Gauss) rule of order 4 on the 3 x 3 x 3 mesh: the
    maximum is 1 there; the negated field's largest value is at the corners."""
    centre = ngs.CF((0.5, 0.5, 0.5))
    bump = 1 - ngs.InnerProduct(XYZ - centre, XYZ - centre)
    value, where = sampling.argmax(bump, unit_cube_hex)
    assert value == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(where, (0.5, 0.5, 0.5), atol=1e-12)
    assert sampling.maximum(-bump, unit_cube_hex) == pytest.approx(-1 + 0.75, abs=1e-12)
