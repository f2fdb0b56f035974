"""What every figure of the package shares: tick labels without an offset or multiplier over
the axis, titles wrapped to the figure's width, and the colour scale of a field map
(diverging and centred at zero for a signed field, sequential otherwise, never magnifying
round-off around a constant).
"""

import textwrap

import numpy as np
from matplotlib import colors
from matplotlib.ticker import FormatStrFormatter

#: Smallest range of an axis or a colour scale relative to its largest absolute value:
#: round-off around a constant is drawn flat, not magnified into a pattern.
RELATIVE_FLOOR = 1e-4


def tick_format(lo: float, hi: float) -> FormatStrFormatter:
    """Tick labels for the range [lo, hi]: enough significant digits to tell ticks a tenth
    of the range apart (three at least), no offset or multiplier printed over the axis."""
    big = max(abs(lo), abs(hi))
    digits = 3
    if hi > lo and big > 0:
        digits = int(np.clip(np.ceil(np.log10(big / (hi - lo))) + 2, 3, 12))
    return FormatStrFormatter(f"%.{digits}g")


def wrapped(title: str, width_inches: float, fontsize: float = 10) -> str:
    """``title`` broken into lines that fit ``width_inches`` at ``fontsize`` points, never
    inside a formula $...$ (an average character is taken as 0.62 of the font size, a
    margin for wide ones)."""
    if not title:
        return title
    chars = max(int(width_inches * 72 / (0.62 * fontsize)), 20)
    # never break inside $...$ (mathtext is parsed line by line)
    kept = "$".join(p.replace(" ", "\0") if i % 2 else p
                    for i, p in enumerate(title.split("$")))
    return "\n".join(textwrap.wrap(kept, chars)).replace("\0", " ")


#: Per cent of the values beyond each end of the colour scale of a map drawn from sampled
#: values (sections, a gathered surface, a 3-D view), where they are peaks (:data:`PEAK`): a
#: few peaks at mesh singularities do not wash out the rest.
MAP_CLIP = 0.5

#: How far beyond its clipped range (in widths of that range) the values at an end of a
#: colour scale must reach for :func:`colour_scale` to clip there.
PEAK = 0.25


def drawn(values: np.ndarray) -> np.ndarray:
    """The values a map draws, flat: those neither masked nor NaN or infinite (a masked
    entry keeps its mask, whatever value lies under it)."""
    return np.ma.compressed(np.ma.masked_invalid(np.ma.asarray(values, dtype=float)))


def colour_scale(values: np.ndarray, signed: bool | None = None, floor: float = 0.0,
                 clip: float = 0.0) -> tuple[colors.Normalize, str]:
    """(norm, colour map name) of a field map.

    Parameters
    ----------
    values : array
        The values drawn (NaN and masked entries are left out).
    signed : bool or None
        A signed quantity (a stress component) gets the diverging map "RdBu_r" from -m to m,
        whatever its values; an unsigned one "viridis". None: signed if the values take both
        signs.
    floor : float
        Smallest range of the scale, besides :data:`RELATIVE_FLOOR` of the largest absolute
        value.
    clip : float
        Per cent of the values left beyond each end of the scale (the colour bar's ends then
        mean "or beyond"), so that a few peaks at mesh singularities do not wash out the
        rest; at an end only where they are peaks there (beyond the clipped range by more
        than :data:`PEAK` times its width); 0: the scale spans all values.
    """
    data = drawn(values)
    if data.size == 0:
        return colors.Normalize(0, 1), "viridis"
    lo, hi = float(data.min()), float(data.max())
    if clip:
        low, high = (float(v) for v in np.percentile(data, [clip, 100 - clip]))
        beyond = PEAK * (high - low)
        lo, hi = (low if low - lo > beyond else lo), (high if hi - high > beyond else hi)
    if signed is None:
        signed = data.min() < 0 < data.max()
    least = max(floor, RELATIVE_FLOOR * max(abs(lo), abs(hi)), 1e-300)
    if signed:
        m = max(-lo, hi, least / 2)
        return colors.Normalize(-m, m), "RdBu_r"
    if hi - lo < least:
        lo, hi = (lo + hi - least) / 2, (lo + hi + least) / 2
    return colors.Normalize(lo, hi), "viridis"


def extend(values: np.ndarray, norm: colors.Norm) -> str:
    """The ``extend`` of the colour bar of ``values`` drawn with ``norm``: an arrow at each
    end beyond which values lie (a scale of :func:`colour_scale` that clipped them)."""
    data = drawn(values)
    below = bool(data.size and data.min() < norm.vmin)
    above = bool(data.size and data.max() > norm.vmax)
    return {(False, False): "neither", (True, False): "min", (False, True): "max",
            (True, True): "both"}[below, above]

