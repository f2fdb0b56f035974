"""ngincompat.fem.resolution: elements across a layer, exact on structured meshes, NaN off it."""

import numpy as np
import pytest
from ngsolve.meshes import MakeStructured3DMesh

from geometries import cube
from ngincompat.fem.resolution import elements_across

E3 = np.array([0.0, 0.0, 1.0])


def _columns(points, normal=E3, length=1.0):
    """Segments from ``points`` along ``normal`` of the given length."""
    inner = np.asarray(points, float)
    return inner, inner + length * np.asarray(normal), np.tile(normal, (len(inner), 1))


@pytest.mark.parametrize("maxh, cells", [(0.5, 2), (0.25, 4), (1 / 3, 3)])
def test_the_hexahedral_cube_has_its_cells_across(maxh, cells):
    """Segments through the unit cube along e3: each meets cells 1 / n high, so a thickness
    of 1 is n elements across, a thickness of 1/2 half as many."""
    mesh = cube(maxh=maxh)
    inner, outer, normal = _columns([[0.3, 0.6, 0.0], [0.1, 0.9, 0.0], [0.5, 0.5, 0.0]])
    across = elements_across(mesh, inner, outer, normal, np.ones(3), material="tissue")
    np.testing.assert_allclose(across, cells, rtol=1e-12)
    half = elements_across(mesh, inner, outer, normal, np.full(3, 0.5), material="tissue")
    np.testing.assert_allclose(half, cells / 2, rtol=1e-12)


def test_tetrahedra_cut_from_the_cells_count_as_the_cells():
    """Each cube of a 3 x 3 x 3 grid cut into tetrahedra: every tetrahedron spans its cube's
    height along e3, so the layer is 3 elements across, as for the hexahedra."""
    mesh = MakeStructured3DMesh(hexes=False, nx=3, ny=3, nz=3)
    assert mesh.ne > 27
    inner, outer, normal = _columns([[0.3, 0.6, 0.0], [0.8, 0.2, 0.0]])
    across = elements_across(mesh, inner, outer, normal, np.ones(2),
                             material=mesh.GetMaterials()[0])
    np.testing.assert_allclose(across, 3.0, rtol=1e-12)


def test_an_oblique_direction_measures_the_extent_along_it():
    """Along N = (e1 + e3) / sqrt(2) a cell of edge h extends 2 h / sqrt(2) = sqrt(2) h: a
    thickness of sqrt(2) h is one element across."""
    mesh = cube(maxh=0.25)
    normal = np.array([1.0, 0.0, 1.0]) / np.sqrt(2)
    inner, outer, normals = _columns([[0.1, 0.4, 0.1]], normal=normal, length=0.4 * np.sqrt(2))
    across = elements_across(mesh, inner, outer, normals, np.array([np.sqrt(2) * 0.25]),
                             material="tissue")
    np.testing.assert_allclose(across, 1.0, rtol=1e-12)


def test_segments_outside_the_layer_or_the_mesh_are_nan():
    """A segment through the other material or outside the mesh counts nothing (NaN); one
    half in the layer counts its samples in it."""
    mesh = cube(maxh=0.5)
    inner, outer, normal = _columns([[0.3, 0.3, 0.0], [3.0, 3.0, 0.0]])
    other = elements_across(mesh, inner, outer, normal, np.ones(2), material="gray")
    assert np.all(np.isnan(other))
    counted = elements_across(mesh, inner, outer, normal, np.ones(2), material="tissue")
    assert counted[0] == pytest.approx(2.0) and np.isnan(counted[1])
    partly = elements_across(mesh, np.array([[0.3, 0.3, 0.5]]), np.array([[0.3, 0.3, 1.5]]),
                             E3[None], np.ones(1), material="tissue", samples=8)
    assert partly[0] == pytest.approx(2.0)

