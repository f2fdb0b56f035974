"""Colour maps on the deformed boundary: the triangulation covers the boundary, the fields are
evaluated where the triangles are, the body is drawn moved by its displacement, and a signed
field gets a scale centred at zero."""

import matplotlib
import ngsolve as ngs
import numpy as np
import pytest
from netgen.occ import Box, OCCGeometry, Pnt

from ngincompat.workflow import surface


@pytest.fixture(scope="module")
def mesh():
    return ngs.Mesh(OCCGeometry(Box(Pnt(0, 0, 0), Pnt(1, 2, 1))).GenerateMesh(maxh=0.6))


def _areas(tri):
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)


@pytest.mark.parametrize("k", [1, 3])
def test_the_triangles_cover_the_boundary(mesh, k):
    """Their areas add up to the box's surface, 2 (1 + 2 + 2) = 10, at every subdivision."""
    tri = surface.boundary_triangles(mesh, k)
    nface = sum(1 for _ in mesh.Elements(ngs.BND))
    assert len(tri) == nface * k * k
    assert _areas(tri).sum() == pytest.approx(10.0, rel=1e-12)


def test_fields_are_evaluated_at_the_corners(mesh):
    tri = surface.boundary_triangles(mesh, 2)
    points = tri.reshape(-1, 3)
    (values,) = surface.evaluate(mesh, [ngs.x + 10 * ngs.z], points)
    # the points are found 1e-7 of the size inside: the field is off by its gradient times that
    np.testing.assert_allclose(values, points[:, 0] + 10 * points[:, 2], atol=1e-5)


def test_the_body_is_drawn_moved_by_its_displacement(mesh):
    """u = (0.5 X1, 0, 0) stretches the box to X1 in [0, 1.5]."""
    u = ngs.CF((0.5 * ngs.x, 0, 0))
    panels = [surface.Panel("f", ngs.x - 0.25, signed=True), surface.Panel("g", ngs.y + 1)]
    fig = surface.surface_figure(mesh, u, panels, "t", "mm", subdivision=1)
    axes = [ax for ax in fig.axes if hasattr(ax, "get_zlim")]
    assert axes[0].get_xlim() == pytest.approx((0.0, 1.5), abs=1e-6)


def test_a_triangulated_surface_is_drawn_moved_with_values_at_its_points():
    """The unit corner tetrahedron's four faces, f = X1 - X2 at its points, drawn on the
    reference and on the surface moved by u = (X1, 0, 0) (X1 in [0, 2]); each triangle takes
    the mean of its corners; f takes both signs, so the automatic scale is diverging."""
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    triangles = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    f = points[:, 0] - points[:, 1]
    u = np.column_stack([points[:, 0], np.zeros(4), np.zeros(4)])
    panels = [surface.Panel("f", f, signed=None), surface.Panel("f moved", f, u=u)]
    fig = surface.triangulated_figure(points, triangles, panels, "t", "cm")
    axes = [ax for ax in fig.axes if hasattr(ax, "get_zlim")]
    assert axes[0].get_xlim() == pytest.approx((0.0, 2.0))        # both panels' extent
    assert axes[0].get_xlabel() == "X1 [cm]"
    reference, moved = (ax.collections[0] for ax in axes)
    means = f[triangles].mean(axis=1)

    def same(drawn, expected):      # the triangles as a set (matplotlib sorts them by depth)
        np.testing.assert_allclose(sorted(map(tuple, drawn)), sorted(map(tuple, expected)))

    same(reference.get_facecolor(),
         matplotlib.colormaps["RdBu_r"](means / abs(means).max() / 2 + 0.5))
    low, high = means.min(), means.max()                             # signed=False: viridis
    same(moved.get_facecolor(), matplotlib.colormaps["viridis"]((means - low) / (high - low)))


def test_arrows_show_the_vector_field_on_the_side_facing_the_camera(mesh):
    """b = (0, 0, X1) on the box, seen from above (elevation 90): the arrows stand on the
    top face only (X3 = 1, its outward normal toward the camera), each the vector at its
    point, all scaled by one factor with the longest ARROW_LENGTH of the box's size (2)."""
    b = ngs.CF((0, 0, ngs.x))
    panel = surface.Panel("|b|", ngs.Norm(b), arrows=b)
    fig = surface.surface_figure(mesh, None, [panel], "t", "mm", view=(90, 0), subdivision=2)
    (ax,) = [ax for ax in fig.axes if hasattr(ax, "get_zlim")]
    (quiver,) = [c for c in ax.collections if type(c).__name__ == "Line3DCollection"]
    # matplotlib's shafts come first, each from the tip to the tail
    shafts = [np.asarray(seg) for seg in quiver._segments3d[:len(quiver._segments3d) // 3]]
    starts = np.array([s[1] for s in shafts])
    lengths = np.array([s[0, 2] - s[1, 2] for s in shafts])
    assert 10 <= len(shafts) <= surface.ARROWS
    np.testing.assert_allclose(starts[:, 2], 1.0, atol=1e-9)        # on the top face
    scale = surface.ARROW_LENGTH * 2.0 / starts[:, 0].max()
    # the field is evaluated 1e-7 of the size inside the face (surface.evaluate)
    np.testing.assert_allclose(lengths, scale * starts[:, 0], rtol=1e-5)
    # the same panel seen from below: the bottom face (X3 = 0) carries them
    fig = surface.surface_figure(mesh, None, [panel], "t", "mm", view=(-90, 0), subdivision=2)
    (ax,) = [ax for ax in fig.axes if hasattr(ax, "get_zlim")]
    (quiver,) = [c for c in ax.collections if type(c).__name__ == "Line3DCollection"]
    shafts = quiver._segments3d[:len(quiver._segments3d) // 3]
    assert np.allclose([np.asarray(s)[1, 2] for s in shafts], 0.0, atol=1e-9)
