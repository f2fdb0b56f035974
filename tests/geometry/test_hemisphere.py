"""geometries.hemisphere: the half ball and its quarter, graded centre, named faces, checks."""

import math

import ngsolve as ngs
import pytest

from geometries import hemisphere
from ngincompat.errors import ParameterError


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(hemisphere, {}, 2 / 3 * math.pi, {"flat", "surface"}, {"tissue"}, 0.3)


def test_hemisphere_centre_refinement_adds_elements():
    assert hemisphere(maxh=0.3, centre_maxh=0.05).ne > hemisphere(maxh=0.3).ne


def test_the_flat_face_is_the_disc_at_x3_0_and_the_cap_the_half_sphere():
    """Radius 2: the flat face has area pi R0^2 at X3 = 0, the cap 2 pi R0^2 with its
    centroid at X3 = R0 / 2 (Archimedes: a zone's area is proportional to its height)."""
    R0 = 2.0
    mesh = hemisphere(R0=R0, maxh=0.6)
    flat = mesh.Boundaries("flat")
    cap = mesh.Boundaries("surface")
    area_flat = ngs.Integrate(1, mesh, ngs.BND, definedon=flat)
    area_cap = ngs.Integrate(1, mesh, ngs.BND, definedon=cap)
    assert area_flat == pytest.approx(math.pi * R0 ** 2, rel=2e-3)
    assert area_cap == pytest.approx(2 * math.pi * R0 ** 2, rel=2e-3)
    assert ngs.Integrate(ngs.z * ngs.z, mesh, ngs.BND, definedon=flat) == pytest.approx(
        0.0, abs=1e-20)
    assert ngs.Integrate(ngs.z, mesh, ngs.BND, definedon=cap) / area_cap == pytest.approx(
        R0 / 2, rel=2e-3)
    assert ngs.Integrate(1, mesh) == pytest.approx(2 / 3 * math.pi * R0 ** 3, rel=2e-3)


def test_the_quarter_has_a_quarter_of_the_volume_and_its_mirror_planes():
    """X1, X2 >= 0: volume pi R0^3 / 6, the faces ``xmirror`` on X1 = 0 and ``ymirror`` on
    X2 = 0, each a quarter disc of area pi R0^2 / 4."""
    mesh = hemisphere(maxh=0.3, quarter=True)
    assert ngs.Integrate(1, mesh) == pytest.approx(math.pi / 6, rel=2e-3)
    assert set(mesh.GetBoundaries()) == {"flat", "surface", "xmirror", "ymirror"}
    for name, coordinate in (("xmirror", ngs.x), ("ymirror", ngs.y)):
        region = mesh.Boundaries(name)
        assert ngs.Integrate(1, mesh, ngs.BND, definedon=region) == pytest.approx(
            math.pi / 4, rel=2e-3)
        assert ngs.Integrate(coordinate * coordinate, mesh, ngs.BND,
                             definedon=region) == pytest.approx(0.0, abs=1e-20)
    assert ngs.Integrate(ngs.IfPos(-ngs.x - 1e-9, 1, 0), mesh) == 0.0


def test_the_material_is_named_as_asked():
    assert hemisphere(maxh=0.5, material="gel").GetMaterials() == ("gel",)


@pytest.mark.parametrize("kwargs, name", [
    (dict(R0=0), "R0"), (dict(centre_maxh=1.0), "centre_maxh"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        hemisphere(**kwargs)


@pytest.mark.parametrize("kwargs, name", [
    (dict(maxh=-0.1), "maxh"), (dict(maxh=11.0), "maxh"), (dict(curve_order=9), "curve_order"),
    (dict(centre_maxh=0.0), "centre_maxh"),
])
def test_mesh_arguments_out_of_range_are_clear_errors(kwargs, name):
    """maxh in (0, 10 R0], curve_order in [1, 8], centre_maxh in (0, maxh]."""
    with pytest.raises(ParameterError, match=f"^{name} = "):
        hemisphere(**kwargs)
