"""Figures a reader can read: no magnified round-off, distinguishable curves, units."""

import numpy as np

from ngincompat import plots
from ngincompat.scenes import CylinderScene, DiscScene, HemisphereScene


def _axes(fig):
    fig.canvas.draw()
    return fig.axes


def test_round_off_around_a_constant_is_drawn_flat():
    """Curl Fg : Curl Fg of the cylinder is 1/16 up to 1e-11: no offset, no magnification."""
    x = np.linspace(0, 1, 101)
    noisy = 0.0625 + 1e-11 * np.sin(40 * x)
    fig = plots.profile_figure(x, {"curl": noisy}, "X2 [mm]", "Curl [1/mm^2]")
    (ax,) = _axes(fig)
    lo, hi = ax.get_ylim()
    assert hi - lo >= plots.RELATIVE_FLOOR * 0.0625
    assert ax.yaxis.get_major_formatter().get_offset() == ""


def test_a_stress_floor_keeps_a_stress_free_body_flat():
    x = np.linspace(0, 1, 101)
    fig = plots.profile_figure(x, {"S11": 1e-9 * np.cos(9 * x)}, "X2 [mm]", "stress [MPa]",
                               floor=5.5e-4)
    (ax,) = _axes(fig)
    lo, hi = ax.get_ylim()
    assert hi - lo >= 5.5e-4


def test_coinciding_curves_differ_in_style():
    x = np.linspace(0, 1, 11)
    fig = plots.profile_figure(x, {"S22": x, "S33": x}, "X1 [mm]", "stress [MPa]")
    a, b = fig.axes[0].get_lines()
    assert (a.get_linestyle(), a.get_marker()) != (b.get_linestyle(), b.get_marker())


def test_titles_name_the_variant_and_labels_carry_units():
    assert "fibers=circumferential" in DiscScene(fibers="circumferential").title()
    assert "profile=concave" in HemisphereScene(profile="concave").title()
    results = CylinderScene(order=1, maxh=0.5).run()
    for spec in results.figures:
        assert "[" in spec.xlabel and "[" in spec.ylabel, spec
        fig = plots.figure(results, spec)
        assert fig.axes[0].get_title() == spec.title
