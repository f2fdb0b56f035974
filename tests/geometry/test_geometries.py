"""Geometry builders: volumes, names, validation."""

import math

import ngsolve as ngs
import pytest

from geometries import (
    FOOTPRINTS,
    bilayer,
    brain,
    cube,
    cylinder,
    disc,
    footprint_area,
    footprint_size,
    hemisphere,
    skin_patch,
)
from geometries.cube import FACES
from ngincompat.errors import ParameterError


@pytest.mark.parametrize("elements", ["hex", "tet"])
@pytest.mark.parametrize("maxh", [0.5, 0.25])
def test_cube_volume_and_names(elements, maxh):
    mesh = cube(side=2.0, maxh=maxh * 2, elements=elements)
    assert ngs.Integrate(1, mesh) == pytest.approx(8.0, rel=1e-10)
    assert set(mesh.GetBoundaries()) == set(FACES)
    assert mesh.GetMaterials() == ("tissue",)
    centre = {"left": (0, 1, 1), "right": (2, 1, 1), "front": (1, 0, 1), "back": (1, 2, 1),
              "bottom": (1, 1, 0), "top": (1, 1, 2)}
    for name, expected in centre.items():
        region = mesh.Boundaries(name)
        area = ngs.Integrate(1, mesh, ngs.BND, definedon=region)
        assert area == pytest.approx(4.0, rel=1e-10)
        got = [ngs.Integrate(c, mesh, ngs.BND, definedon=region) / area
               for c in (ngs.x, ngs.y, ngs.z)]
        assert got == pytest.approx(expected, abs=1e-10)


def test_cube_mesh_size_controls_element_count():
    assert cube(maxh=0.5).ne == 8
    assert cube(maxh=0.25).ne == 64
    assert cube(maxh=0.25, elements="tet").ne > cube(maxh=0.5, elements="tet").ne


BUILDS = {
    "hemisphere": (hemisphere, {}, 2 / 3 * math.pi, {"flat", "surface"}, {"tissue"}, 0.3),
    "disc": (disc, {}, 0.5 * math.pi, {"bottom", "top", "rim"}, {"tissue"}, 0.3),
    "cylinder": (cylinder, {}, math.pi / 4, {"left", "right", "mantle"}, {"tissue"}, 0.3),
    "skin_patch": (skin_patch, {"footprint": "circle"}, 30.0,
                   {"footprint", "bottom", "top", "periphery", "footprint_wall"}, {"skin"}, 2.0),
    "bilayer": (bilayer, {}, 3.0, {"left", "right", "top", "bottom", "interface"},
                {"cortex", "subcortex"}, 0.1),
    "brain": (brain, {}, 4 / 3 * math.pi * 8.5 * 7 * 6, {"surface", "interface"},
              {"gray", "white"}, 2.5),
}


@pytest.mark.parametrize("name", sorted(BUILDS))
def test_every_geometry_builds_at_two_sizes_with_volume_and_names(name):
    build, kwargs, volume, boundaries, materials, maxh = BUILDS[name]
    elements = []
    for h in (maxh, maxh / 1.5):
        mesh = build(maxh=h, **kwargs)
        assert ngs.Integrate(1, mesh) == pytest.approx(volume, rel=2e-3)
        assert set(mesh.GetBoundaries()) == boundaries
        assert set(mesh.GetMaterials()) == materials
        elements.append(mesh.ne)
    assert elements[1] > elements[0]


def test_bilayer_cortex_is_the_top_layer_of_the_section():
    mesh = bilayer(maxh=0.1)
    assert mesh.dim == 2
    cortex = ngs.Integrate(1, mesh, definedon=mesh.Materials("cortex"))
    assert cortex == pytest.approx(3.0 * 0.05, rel=1e-8)
    assert ngs.Integrate(ngs.y, mesh, definedon=mesh.Materials("cortex")) / cortex == \
        pytest.approx(0.975, rel=1e-8)


def test_brain_gray_shell_volume():
    mesh = brain(maxh=2.5)
    white = ngs.Integrate(1, mesh, definedon=mesh.Materials("white"))
    assert white == pytest.approx(4 / 3 * math.pi * 8.2 * 6.7 * 5.7, rel=5e-3)


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


def test_hemisphere_centre_refinement_adds_elements():
    assert hemisphere(maxh=0.3, centre_maxh=0.05).ne > hemisphere(maxh=0.3).ne


@pytest.mark.parametrize("build, kwargs, name", [
    (cube, dict(side=-1.0), "side"), (cube, dict(maxh=0.0), "maxh"),
    (cube, dict(maxh=2.0), "maxh"), (cube, dict(elements="prism"), "elements"),
    (hemisphere, dict(R0=0), "R0"), (hemisphere, dict(centre_maxh=1.0), "centre_maxh"),
    (disc, dict(height=-0.1), "height"), (cylinder, dict(area=0), "area"),
    (skin_patch, dict(footprint_size=12.0), "footprint_size"),
    (skin_patch, dict(footprint="star"), "footprint"),
    (lambda **kw: footprint_size("circle", **kw), dict(area=-1.0), "footprint_area"),
    (skin_patch, dict(thickness=20.0), "thickness"),
    (bilayer, dict(cortex=1.5), "cortex"), (brain, dict(gray=4.0), "gray"),
    (brain, dict(semi_axes=(1, 2)), "semi_axes"), (disc, dict(curve_order=0), "curve_order"),
])
def test_invalid_dimensions_are_clear_errors(build, kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        build(**kwargs)
