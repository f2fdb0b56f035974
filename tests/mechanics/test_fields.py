"""ngincompat.mechanics.fields: unit directions: constant, radial, axons, by region, by name."""

import numpy as np
import pytest
from conftest import random_points, values_at

from geometries import bilayer
from ngincompat.errors import ParameterError
from ngincompat.mechanics import fields


def test_bilayer_axon_orientations(unit_cube_hex):
    """Straight axons are normal to the interface; curved ones fan out from the focus below
    the middle; concentric ones are orthogonal to the curved ones and to e2 (in-plane)."""
    pts = random_points(12)
    straight = values_at(fields.axons("straight").cf, unit_cube_hex, pts)
    np.testing.assert_allclose(straight, np.tile([0, 0, 1.0], (12, 1)))
    curved = values_at(fields.axons("curved", interface=0.95, length=1.0).cf, unit_cube_hex, pts)
    concentric = values_at(fields.axons("concentric", interface=0.95, length=1.0).cf,
                           unit_cube_hex, pts)
    np.testing.assert_allclose(np.linalg.norm(curved, axis=1), 1, rtol=1e-12)
    np.testing.assert_allclose(np.sum(curved * concentric, axis=1), 0, atol=1e-12)
    np.testing.assert_allclose(concentric[:, 1], 0, atol=1e-12)
    focus = np.array([0.5, 0.0, 0.95 - 3.0])
    d = pts - focus
    d[:, 1] = 0
    np.testing.assert_allclose(curved, d / np.linalg.norm(d, axis=1)[:, None], rtol=1e-12)
    with pytest.raises(ParameterError, match="axons = 'wavy'"):
        fields.axons("wavy")


def test_bilayer_axon_orientations_on_the_section():
    """On the section of a body in plane strain (X2 vertical, X3 out of plane): straight
    axons are e2, curved ones fan out in the plane from the focus below the middle,
    concentric ones are orthogonal to them and in the plane; another vertical is refused."""
    mesh = bilayer(length=1.0, height=1.0, cortex=0.05, maxh=0.2)
    pts = random_points(12)[:, :2] * 0.9 + 0.05
    points = mesh(pts[:, 0], pts[:, 1])
    kw = dict(interface=0.95, length=1.0, vertical="e2")
    straight, curved, concentric = (
        np.asarray(fields.axons(kind, **kw).cf(points))
        for kind in ("straight", "curved", "concentric"))
    np.testing.assert_allclose(straight, np.tile([0, 1.0, 0], (12, 1)))
    d = np.column_stack([pts - [0.5, 0.95 - 3.0], np.zeros(12)])
    np.testing.assert_allclose(curved, d / np.linalg.norm(d, axis=1)[:, None], rtol=1e-12)
    np.testing.assert_allclose(np.sum(curved * concentric, axis=1), 0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(concentric, axis=1), 1, rtol=1e-12)
    np.testing.assert_allclose(concentric[:, 2], 0, atol=1e-12)
    with pytest.raises(ParameterError, match="vertical = 'e1'"):
        fields.axons("curved", vertical="e1")


def test_a_constant_direction_is_normalised_and_named():
    d = fields.constant((3.0, 0.0, 4.0))
    assert d.is_constant and d.vector == pytest.approx((0.6, 0.0, 0.8), rel=1e-15)
    assert d.name == "(0.6, 0, 0.8)"
    assert fields.constant((3.0, 0.0, 4.0), name="N0").name == "N0"
    e2 = fields.constant("e2")
    assert e2.vector == (0.0, 1.0, 0.0) and e2.name == "e2"


@pytest.mark.parametrize("vector, message", [
    ("e4", "direction 'e4' is unknown"), ((0, 0, 0), "not all zero"),
    ((1, 2), "three finite numbers"), ((1, np.nan, 0), "three finite numbers"),
    ((1, np.inf, 0), "three finite numbers"),
])
def test_a_bad_constant_direction_is_refused(vector, message):
    with pytest.raises(ParameterError, match=message):
        fields.constant(vector)


def test_radial_directions_about_a_point_and_about_an_axis(unit_cube_hex):
    """About the point c: (X - c) / |X - c|. About the line c + s a: the part of X - c normal
    to a, normalised. Unit vectors, not constant."""
    pts = random_points(10, seed=5)
    centre = np.array([0.2, -0.3, 0.5])
    about_point = fields.radial(tuple(centre))
    assert not about_point.is_constant and about_point.name == "radial"
    d = pts - centre
    np.testing.assert_allclose(values_at(about_point.cf, unit_cube_hex, pts),
                               d / np.linalg.norm(d, axis=1)[:, None], rtol=1e-12)
    about_axis = values_at(fields.radial(tuple(centre), axis=(0, 0, 2)).cf, unit_cube_hex, pts)
    d[:, 2] = 0
    np.testing.assert_allclose(about_axis, d / np.linalg.norm(d, axis=1)[:, None], rtol=1e-12)


def test_circumferential_is_the_axis_cross_the_radial(unit_cube_hex):
    """About e3 through the origin: (-X2, X1, 0) / sqrt(X1^2 + X2^2), normal to the radial
    direction and to the axis."""
    pts = random_points(10, seed=6)
    got = values_at(fields.circumferential().cf, unit_cube_hex, pts)
    r = np.hypot(pts[:, 0], pts[:, 1])
    expected = np.column_stack([-pts[:, 1] / r, pts[:, 0] / r, np.zeros(len(pts))])
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15)
    about_e1 = values_at(fields.circumferential("e1").cf, unit_cube_hex, pts)
    np.testing.assert_allclose(about_e1[:, 0], 0, atol=1e-15)
    np.testing.assert_allclose(np.sum(about_e1 * pts, axis=1), 0, atol=1e-14)


@pytest.mark.parametrize("name, vector", [("e1", (1, 0, 0)), ("e3", (0, 0, 1))])
def test_the_axes_by_name_are_constant(name, vector):
    got = fields.from_name(name)
    assert got.is_constant and got.vector == vector


def test_the_named_radial_and_axon_fields_are_those_of_their_functions(unit_cube_hex):
    pts = random_points(5, seed=7)
    for name, field in (("radial", fields.radial()),
                        ("radial_xy", fields.radial(axis="e3")),
                        ("circumferential", fields.circumferential()),
                        ("axons_curved", fields.axons("curved")),
                        ("axons_straight", fields.axons("straight"))):
        np.testing.assert_allclose(values_at(fields.from_name(name).cf, unit_cube_hex, pts),
                                   values_at(field.cf, unit_cube_hex, pts), rtol=1e-15)


def test_an_unknown_name_is_refused_under_the_parameters_name():
    with pytest.raises(ParameterError, match=r"^f0 = 'spiral' is unknown: allowed e1, e2, e3, "
                                             r"radial, .*axons_curved"):
        fields.from_name("spiral", parameter="f0")


def test_a_field_by_region_takes_each_regions_direction():
    """The cortex's e1 above the subcortex's e2 on the section: each region its own vector;
    constant only when every region has the same constant; one field for each region."""
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    f0 = fields.by_region(mesh, {"cortex": fields.constant("e1"),
                                 "subcortex": fields.constant("e2")}, "f0")
    assert f0.name == "f0" and not f0.is_constant
    np.testing.assert_allclose(f0.cf(mesh(0.5, 0.45)), (1, 0, 0))
    np.testing.assert_allclose(f0.cf(mesh(0.5, 0.1)), (0, 1, 0))
    same = fields.by_region(mesh, {"cortex": fields.constant("e3"),
                                   "subcortex": fields.constant((0, 0, 2))}, "N0")
    assert same.is_constant and same.vector == (0.0, 0.0, 1.0)
    with pytest.raises(ParameterError, match=r"one for each region: cortex, subcortex"):
        fields.by_region(mesh, {"cortex": fields.constant("e1")}, "f0")


def test_the_axons_focus_depth_must_be_positive():
    with pytest.raises(ParameterError, match="^focus_depth = 0 "):
        fields.axons("curved", focus_depth=0)
    assert fields.axons("straight", focus_depth=0).vector == (0.0, 0.0, 1.0)
