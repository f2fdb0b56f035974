"""geometries.cube: the cube and its quarter, hexahedral or tetrahedral, named faces, checks."""

import ngsolve as ngs
import pytest

from geometries import cube
from geometries.cube import FACES
from ngincompat.errors import ParameterError


def _face_centre_and_area(mesh, name):
    region = mesh.Boundaries(name)
    area = ngs.Integrate(1, mesh, ngs.BND, definedon=region)
    centre = [ngs.Integrate(c, mesh, ngs.BND, definedon=region) / area
              for c in (ngs.x, ngs.y, ngs.z)]
    return centre, area


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


@pytest.mark.parametrize("side, maxh, cells", [(1.0, 0.3, 4), (2.0, 0.5, 4), (3.0, 1.0, 3),
                                               (1.0, 1.0, 1)])
def test_hexahedra_per_edge_are_ceil_side_over_maxh(side, maxh, cells):
    """ceil(side / maxh) cells per edge, each side / cells long: a maxh that divides the side
    exactly (1 / 1, 3 / 1) gives no extra cell for round-off."""
    mesh = cube(side=side, maxh=maxh)
    assert mesh.ne == cells ** 3
    assert ngs.Integrate(1, mesh) == pytest.approx(side ** 3, rel=1e-12)


@pytest.mark.parametrize("elements", ["hex", "tet"])
def test_the_quarter_is_cut_by_the_mid_planes_named_back_and_top(elements):
    """The quarter [0, 2] x [0, 1]^2 of the cube of side 2: a quarter of the volume, its
    ``back`` and ``top`` faces on the mid-planes X2 = 1 and X3 = 1, the other faces where the
    cube's are; the hexahedra keep ceil(n / 2) cells across the halved edges."""
    mesh = cube(side=2.0, maxh=0.5, elements=elements, quarter=True)
    assert ngs.Integrate(1, mesh) == pytest.approx(2.0, rel=1e-10)
    assert set(mesh.GetBoundaries()) == set(FACES)
    expected = {"left": ((0, 0.5, 0.5), 1.0), "right": ((2, 0.5, 0.5), 1.0),
                "front": ((1, 0, 0.5), 2.0), "back": ((1, 1, 0.5), 2.0),
                "bottom": ((1, 0.5, 0), 2.0), "top": ((1, 0.5, 1), 2.0)}
    for name, (centre, area) in expected.items():
        got_centre, got_area = _face_centre_and_area(mesh, name)
        assert got_area == pytest.approx(area, rel=1e-10), name
        assert got_centre == pytest.approx(centre, abs=1e-10), name
    if elements == "hex":
        assert mesh.ne == 4 * 2 * 2


@pytest.mark.parametrize("elements", ["hex", "tet"])
def test_the_material_is_named_as_asked(elements):
    mesh = cube(maxh=0.5, elements=elements, material="gel")
    assert mesh.GetMaterials() == ("gel",)


def test_a_curved_tetrahedral_cube_keeps_its_volume():
    """curve_order > 1 curves the tetrahedral mesh (a cube's faces are flat: nothing moves)."""
    mesh = cube(maxh=0.5, elements="tet", curve_order=3)
    assert ngs.Integrate(1, mesh) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("kwargs, name", [
    (dict(side=-1.0), "side"), (dict(maxh=0.0), "maxh"),
    (dict(maxh=2.0), "maxh"), (dict(elements="prism"), "elements"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        cube(**kwargs)


@pytest.mark.parametrize("curve_order", [0, 1.5])
def test_the_curve_order_must_be_an_integer_of_at_least_one(curve_order):
    with pytest.raises(ParameterError, match="^curve_order = .*an integer >= 1"):
        cube(curve_order=curve_order)
