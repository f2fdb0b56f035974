"""Geometry builders: volumes, names, validation."""

import ngsolve as ngs
import pytest

from geometries import cube
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


@pytest.mark.parametrize("kwargs, name", [
    (dict(side=-1.0), "side"), (dict(maxh=0.0), "maxh"), (dict(maxh=2.0), "maxh"),
    (dict(elements="prism"), "elements"),
])
def test_cube_rejects_bad_dimensions(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        cube(**kwargs)
