"""ngincompat.workflow.style: tick labels, wrapped titles and the colour scale of a map."""

import numpy as np
import pytest
from matplotlib import colors

from ngincompat.workflow import style


def test_a_signed_field_is_centred_at_zero_and_round_off_is_drawn_flat():
    """A field of both signs gets the diverging map from -max|f| to max|f|, one of one sign a
    sequential one."""
    norm, cmap = style.colour_scale(np.array([-0.25, 1.0]), signed=True)
    assert (norm.vmin, norm.vmax, cmap) == (-1.0, 1.0, "RdBu_r")
    norm, cmap = style.colour_scale(np.array([1.0, 3.0]))
    assert (norm.vmin, norm.vmax, cmap) == (1.0, 3.0, "viridis")
    # round-off around a constant is drawn flat: the scale is widened, not magnified
    norm, _ = style.colour_scale(0.0625 + 1e-12 * np.arange(3))
    assert norm.vmax - norm.vmin >= style.RELATIVE_FLOOR * 0.0625


def test_a_clipped_scale_leaves_a_peak_beyond_its_end():
    values = np.concatenate([np.linspace(0, 1, 999), [100.0]])
    norm, cmap = style.colour_scale(values, clip=0.5)
    assert cmap == "viridis" and norm.vmax < 1.01
    norm, cmap = style.colour_scale(np.array([-1.0, 2.0]))          # both signs: diverging
    assert (norm.vmin, norm.vmax, cmap) == (-2.0, 2.0, "RdBu_r")


def test_long_titles_wrap_to_the_figure_and_keep_their_formulas():
    title = r"(a) area growth $\vartheta^g$ of the skin, deflated, $\bar n_\phi$ plane [-]"
    lines = style.wrapped(title, 2.0).split("\n")
    assert len(lines) > 1 and " ".join(lines) == title
    assert all(line.count("$") % 2 == 0 for line in lines)        # no formula cut in two
    assert all(len(line) <= 24 for line in lines if "$" not in line)


def test_a_clip_keeps_an_end_whose_values_are_no_peak():
    """Evenly spread values have nothing beyond their percentiles by more than PEAK times
    the range: the scale spans them all."""
    norm, _ = style.colour_scale(np.linspace(0.0, 1.0, 1000), clip=0.5)
    assert (norm.vmin, norm.vmax) == (0.0, 1.0)
    # a peak at the low end only: clipped there, the high end kept
    values = np.concatenate([[-100.0], np.linspace(0.0, 1.0, 999)])
    norm, _ = style.colour_scale(values, signed=False, clip=0.5)
    assert -0.01 < norm.vmin < 0.01 and norm.vmax == 1.0


def test_the_scale_leaves_out_values_that_are_not_finite():
    norm, cmap = style.colour_scale([1.0, np.nan, 2.0, np.inf, -np.inf])
    assert (norm.vmin, norm.vmax, cmap) == (1.0, 2.0, "viridis")
    norm, cmap = style.colour_scale([np.nan, np.nan])           # nothing to draw
    assert (norm.vmin, norm.vmax, cmap) == (0.0, 1.0, "viridis")


def test_a_floor_widens_a_narrow_scale_about_its_middle():
    norm, _ = style.colour_scale([1.0, 1.1], floor=0.5)
    assert (norm.vmin, norm.vmax) == pytest.approx((0.8, 1.3))
    norm, cmap = style.colour_scale([0.0, 1e-3], signed=True, floor=1.0)
    assert (norm.vmin, norm.vmax, cmap) == (-0.5, 0.5, "RdBu_r")
    # negative values of one sign: sequential, not forced to include zero
    norm, cmap = style.colour_scale([-3.0, -1.0])
    assert (norm.vmin, norm.vmax, cmap) == (-3.0, -1.0, "viridis")


@pytest.mark.parametrize("values, expected", [
    ([0.0, 1.0, 2.0], "both"), ([0.5, 1.0, 2.0], "max"), ([0.0, 1.0, 1.5], "min"),
    ([0.5, 1.5], "neither"), ([np.nan, 1.0], "neither"), ([], "neither")])
def test_the_colour_bar_extends_at_each_end_beyond_which_values_lie(values, expected):
    assert style.extend(values, colors.Normalize(0.5, 1.5)) == expected


@pytest.mark.parametrize("lo, hi, fmt", [
    (0.0, 1.0, "%.3g"),                 # a range as wide as its values: three digits
    (1000.0, 1000.01, "%.8g"),          # 1e5 times narrower than the values: 5 more
    (1.0, 1.0, "%.3g"),                 # no range
    (0.0, 0.0, "%.3g"),
    (1.0, 1.0 + 1e-15, "%.12g"),        # at most twelve
])
def test_ticks_carry_the_digits_that_tell_a_tenth_of_the_range_apart(lo, hi, fmt):
    formatter = style.tick_format(lo, hi)
    assert formatter.fmt == fmt
    assert formatter(1000.005 if lo == 1000.0 else 0.5) != ""


def test_ticks_of_a_narrow_range_read_apart():
    """Ticks a tenth of the range apart print differently, without an offset."""
    lo, hi = 273.15, 273.16
    formatter = style.tick_format(lo, hi)
    ticks = [formatter(v) for v in np.linspace(lo, hi, 11)]
    assert len(set(ticks)) == 11


def test_an_empty_title_is_left_as_it_is_and_a_short_one_on_one_line():
    assert style.wrapped("", 2.0) == "" and style.wrapped(None, 2.0) is None
    assert style.wrapped("a short title", 6.0) == "a short title"
    # a narrow figure still takes 20 characters a line
    assert all(len(line) <= 20 for line in style.wrapped("word " * 20, 0.1).split("\n"))


def test_a_masked_entry_does_not_set_the_scale_whatever_lies_under_it():
    """A masked 100 among 1 and 2 is not drawn: the scale and its arrows are those of 1-2."""
    from ngincompat.workflow.style import colour_scale, drawn, extend
    values = np.ma.array([1.0, 2.0, 100.0, np.nan], mask=[False, False, True, False])
    assert list(drawn(values)) == [1.0, 2.0]
    norm, _ = colour_scale(values, signed=False)
    assert norm.vmax < 100 and norm.vmax >= 2.0
    assert extend(values, norm) == "neither"
