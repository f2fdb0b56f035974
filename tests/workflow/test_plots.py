"""Figures a reader can read: no magnified round-off, distinguishable curves, units."""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg

from ngincompat.scenes import CylinderScene, DiscScene, HemisphereScene
from ngincompat.workflow import plots


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
        assert fig.axes[0].get_title().replace("\n", " ") == spec.title


def _grid_profile(scale):
    """A 3 x 2 grid: a linear field f = scale (X1 - X3) on it, moved by u = (0.1 X1, 0.2 X3)."""
    x1, x3 = np.linspace(0, 2, 5), np.linspace(0, 1, 3)
    X1, X3 = np.meshgrid(x1, x3)
    return {"X1": x1, "X3": x3, "f": scale * (X1 - X3), "g": X1 + 1,
            "u": np.stack([0.1 * X1, 0.2 * X3], axis=-1)}


def test_deformed_figure_draws_each_field_on_the_moved_grid():
    """The panels' points are X + u, the colours the field's values; one colour scale per
    column (the rows compare), centred on zero for a field of both signs; a column that a
    row lacks is left out."""
    rows = {"one": _grid_profile(1.0), "two": _grid_profile(3.0)}
    rows["two"].pop("g")
    panels = {"f [kPa]": ("f", "u"), "g [-]": ("g", "u"), "h [-]": ("h", "u_released")}
    fig = plots.deformed_figure(rows, panels, ("X1", "X3"), "X1 [cm]", "X3 [cm]", "t")
    maps = [ax for ax in fig.axes if ax.collections and ax.get_title()]
    assert [ax.get_title() for ax in maps] == ["one: f [kPa]", "two: f [kPa]"]
    X1, X3 = np.meshgrid(rows["one"]["X1"], rows["one"]["X3"])
    mesh = maps[0].collections[0]
    np.testing.assert_allclose(mesh.get_coordinates(),
                               np.stack([1.1 * X1, 1.2 * X3], axis=-1))
    np.testing.assert_allclose(mesh.get_array().reshape(X1.shape), X1 - X3)
    for ax in maps:
        assert ax.collections[0].get_clim() == (-6.0, 6.0)   # both rows, symmetric
        assert ax.collections[0].colorbar.extend == "neither"  # no peak: nothing clipped
        assert ax.get_xlabel() == "X1 [cm]"


def test_a_long_panel_title_is_broken_to_the_width_of_its_panel():
    """Fig. 7's "after release" titles ran under the colour bar's arrow: a title is broken
    into lines no wider than its panel with the colour bar beside it."""
    label = "concentric: after release: max principal Cauchy stress [kPa]"
    fig = plots.deformed_figure({"": _grid_profile(1.0)}, {label: ("f", "u")}, ("X1", "X3"),
                                "X1 [cm]", "X3 [cm]")
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw(renderer)
    ax = next(ax for ax in fig.axes if ax.collections)
    bar = ax.collections[0].colorbar.ax
    title = ax.title.get_window_extent(renderer)
    assert "\n" in ax.get_title() and ax.get_title().replace("\n", " ") == label
    assert title.x1 <= bar.get_window_extent(renderer).x0


def test_a_peak_of_the_deformed_figure_is_beyond_its_colour_bar_which_says_so():
    """One point of 1000 times the rest of a stress (a crease tip's) does not set the scale;
    the colour bar gets an arrow at its top. A field of one sign keeps its whole range."""
    X1, X3 = np.meshgrid(np.linspace(0, 2, 41), np.linspace(0, 1, 21))
    f = X1 - X3                 # a stress: both signs
    f[10, 20] = 1000.0
    profile = {"X1": X1[0], "X3": X3[:, 0], "f": f, "u": np.zeros(X1.shape + (2,))}
    fig = plots.deformed_figure({"two": profile}, {"f [kPa]": ("f", "u")},
                                ("X1", "X3"), "X1 [cm]", "X3 [cm]")
    image = [ax for ax in fig.axes if ax.collections and ax.get_title()][0].collections[0]
    assert image.get_clim()[1] < 3.0
    assert image.colorbar.extend == "max"
    profile["f"] = np.abs(f)    # one sign (a growth): its whole range, no arrow
    fig = plots.deformed_figure({"two": profile}, {"f [-]": ("f", "u")},
                                ("X1", "X3"), "X1 [cm]", "X3 [cm]")
    image = [ax for ax in fig.axes if ax.collections and ax.get_title()][0].collections[0]
    assert image.get_clim()[1] == 1000.0 and image.colorbar.extend == "neither"


def test_the_deformed_figure_keeps_every_label_inside_when_the_body_grows_taller():
    """A fold lifts the top above the reference grid (the preview bilayer: 0.6 cm tall, 0.8
    folded): the figure's height follows the deformed body, so no axis label is cut off at
    its edge (the folding figure's X1 labels once were)."""
    X1, X3 = np.meshgrid(np.linspace(0, 1, 41), np.linspace(0, 0.6, 25))
    u = np.stack([np.zeros_like(X1), 0.35 * X3 * np.cos(2 * np.pi * X1) ** 2], axis=-1)
    profile = {"X1": X1[0], "X3": X3[:, 0], "f": X1 - X3, "g": X1 + 1.0, "u": u}
    panels = {"f [kPa]": ("f", "u"), "g [-]": ("g", "u"), "f again [kPa]": ("f", "u"),
              "g again [-]": ("g", "u")}
    fig = plots.deformed_figure({"": profile}, panels, ("X1", "X3"), "X1 [cm]", "X3 [cm]",
                                "a long title over four panels")
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    page = fig.bbox
    for ax in fig.axes:
        box = ax.get_tightbbox(renderer)
        assert box.y0 >= page.y0 - 1 and box.y1 <= page.y1 + 1, (ax.get_title(), box, page)


def test_a_marked_metric_is_a_dashed_line_in_the_legend_and_a_missing_one_is_left_out():
    """The folding eigenvalue's curve marks the onset, theta_c where it crosses zero."""
    from types import SimpleNamespace

    from ngincompat.scenes.folding import FoldingScene
    from ngincompat.scenes.folding.figures import figures
    spec = next(f for f in figures(FoldingScene(), {"depth": {}, "section": {}})
                if f.file == "eigenvalue.png")
    assert list(spec.marks.values()) == ["onset_growth"]
    theta = np.array([1.08, 1.16, 1.24, 1.28, 1.32])
    results = SimpleNamespace(profiles={"perfect": {"theta_c": theta,
                                                    "eigenvalue": 15 - 80 * (theta - 1.08)}},
                              metrics={"onset_growth": 1.2706})
    ax = plots.figure(results, spec).axes[0]
    (line,) = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
    assert line.get_xdata()[0] == 1.2706
    assert line.get_label().endswith("theta_c = 1.271")
    assert line.get_label() in [t.get_text() for t in ax.get_legend().get_texts()]
    results.metrics["onset_growth"] = float("nan")          # no onset: no line
    assert not [line for line in plots.figure(results, spec).axes[0].get_lines()
                if line.get_linestyle() == "--"]


def test_a_maps_panel_draws_its_in_plane_vectors_as_arrows_where_they_are_not_small():
    """A vortex u = (-y, x) r on a disc: arrows on the panel that asks for them, none on the
    other, none outside the body (NaN) and none below the floor near the centre; each arrow
    is the field's direction, all scaled alike."""
    from matplotlib.quiver import Quiver

    from ngincompat.workflow.plots import QUIVER, QUIVER_FLOOR, maps_figure

    u = v = np.linspace(-1.0, 1.0, 41)
    U, V = np.meshgrid(u, v)
    inside = U ** 2 + V ** 2 <= 1.0
    field = np.where(inside, np.hypot(U, V), np.nan)
    vectors = np.where(inside[..., None], np.stack([-V, U], axis=-1), np.nan)
    profile = {"e3_u": u, "e3_v": v, "e3_r": field, "e3_s": field}
    fig = maps_figure(profile, {"r": "e3_r", "s": "e3_s"}, "cm", arrows={"r": vectors})
    quivers = [[c for c in ax.collections if isinstance(c, Quiver)] for ax in fig.axes[::2]]
    assert [len(q) for q in quivers] == [1, 0]
    arrows = quivers[0][0]
    at, uv = arrows.get_offsets(), np.column_stack([arrows.U, arrows.V])
    r = np.hypot(at[:, 0], at[:, 1])
    assert 0 < len(at) < QUIVER ** 2
    assert np.all(r <= 1.0 + 1e-12) and np.all(r >= QUIVER_FLOOR - 1e-12)
    expected = np.column_stack([-at[:, 1], at[:, 0]])
    assert np.allclose(uv, expected * (np.linalg.norm(uv) / np.linalg.norm(expected)))
