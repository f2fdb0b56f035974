"""Fixtures shared by the geometry tests."""

import ngsolve as ngs
import pytest


def _builds_at_two_sizes(build, kwargs, volume, boundaries, materials, maxh):
    """``build(maxh=h, **kwargs)`` at h = ``maxh`` and ``maxh`` / 1.5: the volume (to 2e-3),
    the names of the boundaries and materials, and more elements on the finer mesh."""
    elements = []
    for h in (maxh, maxh / 1.5):
        mesh = build(maxh=h, **kwargs)
        assert ngs.Integrate(1, mesh) == pytest.approx(volume, rel=2e-3)
        assert set(mesh.GetBoundaries()) == boundaries
        assert set(mesh.GetMaterials()) == materials
        elements.append(mesh.ne)
    assert elements[1] > elements[0]


@pytest.fixture
def builds_at_two_sizes():
    """The check of :func:`_builds_at_two_sizes`, for a builder and its expected body."""
    return _builds_at_two_sizes

