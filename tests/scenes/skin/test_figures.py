"""ngincompat.scenes.skin.figures: the maps at mid-thickness and the figures of section 3.6."""

import ngsolve as ngs
import numpy as np
import pytest

from geometries import skin_patch
from geometries.skin_patch import SIDE, THICKNESS
from ngincompat.scenes.skin.figures import MAPS, figures, mid_plane
from ngincompat.scenes.skin.scene import SkinExpansionScene
from ngincompat.workflow.results import MapsFigure, ProfileFigure


@pytest.fixture(scope="module")
def grid():
    mesh = skin_patch(footprint="circle", footprint_size=5.0, maxh=2.0, curve_order=1)
    fields = {"theta": 1 + ngs.x * ngs.x, "|b|": ngs.y + ngs.z}
    return mid_plane(mesh, fields, n=11)


def test_the_maps_sample_the_fields_on_the_mid_thickness_plane(grid):
    u = np.linspace(-SIDE / 2, SIDE / 2, 11)
    assert np.array_equal(grid["mid_u"], u) and np.array_equal(grid["mid_v"], u)
    theta, b = np.asarray(grid["mid_theta"]), np.asarray(grid["mid_|b|"])
    assert theta.size == b.size == 121
    # theta = 1 + X1^2 and |b| = X2 + X3 at X3 = thickness / 2, whatever the grid's order
    assert np.sort(theta.ravel()) == pytest.approx(np.sort(np.add.outer(1 + u * u, 0 * u)
                                                           .ravel()), abs=1e-9)
    assert np.sort(b.ravel()) == pytest.approx(np.sort(np.add.outer(0 * u, u + THICKNESS / 2)
                                                       .ravel()), abs=1e-9)
    assert "mid_sigma_max_released" not in grid          # only the fields given


def test_the_figures_map_what_the_grid_holds_in_the_scenes_units(grid):
    made = figures(SkinExpansionScene(footprint="circle"), grid)
    maps, profile, stress = made
    assert isinstance(maps, MapsFigure)
    assert isinstance(profile, ProfileFigure) and isinstance(stress, ProfileFigure)
    assert set(maps.curves.values()) == {"mid_theta", "mid_|b|"}
    assert "|b| on e3 [1/cm]" in maps.curves
    assert "[MPa]" in stress.ylabel and "circle" in maps.title
    assert len(MAPS) == 4
