"""geometries.bilayer: the section's named edges and layers, its graded cortex and top, checks."""

import ngsolve as ngs
import pytest

from geometries import bilayer
from ngincompat.errors import ParameterError


def _length(mesh, name):
    return ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries(name))


def _edges(mesh, name):
    return sum(1 for el in mesh.Elements(ngs.BND) if el.mat == name)


def test_builds_at_two_sizes_with_volume_and_names(builds_at_two_sizes):
    builds_at_two_sizes(bilayer, {}, 3.0, {"left", "right", "top", "bottom", "interface"},
                        {"cortex", "subcortex"}, 0.1)


def test_bilayer_cortex_is_the_top_layer_of_the_section():
    mesh = bilayer(maxh=0.1)
    assert mesh.dim == 2
    cortex = ngs.Integrate(1, mesh, definedon=mesh.Materials("cortex"))
    assert cortex == pytest.approx(3.0 * 0.05, rel=1e-8)
    assert ngs.Integrate(ngs.y, mesh, definedon=mesh.Materials("cortex")) / cortex == \
        pytest.approx(0.975, rel=1e-8)


def test_the_edges_are_where_their_names_say():
    """A 2 x 1 section with a cortex of 0.2: left and right have the height's length at
    X1 = 0 and X1 = length, bottom, interface and top the length's at X2 = 0, 0.8, 1."""
    mesh = bilayer(length=2.0, height=1.0, cortex=0.2, maxh=0.25)
    for name, length, coordinate, level in (
            ("left", 1.0, ngs.x, 0.0), ("right", 1.0, ngs.x, 2.0),
            ("bottom", 2.0, ngs.y, 0.0), ("interface", 2.0, ngs.y, 0.8),
            ("top", 2.0, ngs.y, 1.0)):
        assert _length(mesh, name) == pytest.approx(length, rel=1e-12), name
        assert ngs.Integrate((coordinate - level) ** 2, mesh, ngs.BND,
                             definedon=mesh.Boundaries(name)) == pytest.approx(
            0.0, abs=1e-24), name
    assert all(el.type == ngs.ET.TRIG for el in mesh.Elements(ngs.VOL))


def test_a_fine_cortex_and_top_refine_them_and_leave_the_bottom_coarse():
    """cortex_maxh refines the cortex and the interface, top_maxh the top edge further; the
    bottom edge keeps about length / maxh segments (Netgen's segments are up to 1.2 x the
    size asked for)."""
    plain = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    fine = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25, cortex_maxh=0.05)
    top = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25, cortex_maxh=0.05,
                  top_maxh=0.0125)
    assert _edges(fine, "interface") >= 0.8 / 0.05 > _edges(plain, "interface")
    assert _edges(fine, "top") >= 0.8 / 0.05
    assert _edges(top, "top") >= 0.8 / 0.0125 > _edges(fine, "top")
    assert _edges(top, "interface") < 0.8 / 0.0125
    for mesh in (plain, fine, top):
        assert _edges(mesh, "bottom") <= 2 * 1.0 / 0.25
    assert fine.ne > plain.ne and top.ne > fine.ne


@pytest.mark.parametrize("kwargs, name", [
    (dict(cortex=1.5), "cortex"), (dict(length=0.0), "length"), (dict(height=-1.0), "height"),
    (dict(cortex_maxh=0.1), "cortex_maxh"), (dict(cortex_maxh=0.0), "cortex_maxh"),
    (dict(cortex_maxh=0.02, top_maxh=0.03), "top_maxh"),
])
def test_invalid_dimensions_are_clear_errors(kwargs, name):
    """The cortex thinner than the section; the cortex's size in (0, maxh], the top's in
    (0, cortex_maxh]."""
    with pytest.raises(ParameterError, match=f"^{name} = "):
        bilayer(**kwargs)
