"""The shape of a sampled plane curve: its curvature, from the circle fitted to it, and its
sulci.

The circle A (x^2 + z^2) + D x + E z + F = 0 is fitted algebraically with Pratt's
normalisation D^2 + E^2 - 4 A F = 1 (V. Pratt, Computer Graphics 21 (1987) 145): the
coefficients a = (A, D, E, F) minimise |Z a|^2, Z the rows (x^2 + z^2, x, z, 1) of the
samples, subject to a^T B a = 1, the smallest non-negative eigenvalue of Z^T Z a = eta B a.
The normalisation makes |grad| = |(2 A x + D, 2 A z + E)| = 1 on the circle, so 1 / R =
2 |A|, and a straight line (A = 0) is fitted as well as a circle: the curvature passes
through zero continuously. The fit is invariant under rigid motions, and exact for points on
a circle.

The sulci of a line z(x) between two symmetry planes (roller ends: the line goes on as its
mirror image beyond each end, a period of twice its length) are its troughs, counted with a
hysteresis of a ``fraction`` of its peak-to-peak height: walking the period from its highest
point, a trough is where the line, having fallen by at least that much from its last crest,
rises by at least that much again (so that ripples and a crease's twin tips make no sulci of
their own). A period holds every sulcus twice, one on an end plane (half of it in the image)
once, so the count is half the troughs of the period. The depth of a sulcus is that below the
lower of its two crests.
"""

from collections.abc import Sequence

import numpy as np
from scipy.linalg import eig

from ngincompat.errors import require

#: The Pratt constraint a^T B a = D^2 + E^2 - 4 A F for a = (A, D, E, F).
_PRATT = np.array([[0.0, 0.0, 0.0, -2.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0],
                   [-2.0, 0.0, 0.0, 0.0]])


def circle_curvature(x: Sequence[float] | np.ndarray, z: Sequence[float] | np.ndarray) -> float:
    """The signed curvature 1 / R of the circle fitted to the points (x, z) (at least 3):
    positive where the curve bulges toward +z (the centre below it), zero for a line.

    The sign: the unit normal (2 A x + D, 2 A z + E) is oriented to point toward +z on
    average over the points; it points away from the centre where A > 0, so the curvature is
    2 A."""
    x, z = np.asarray(x, float), np.asarray(z, float)
    require(x.shape == z.shape and x.ndim == 1 and len(x) >= 3, "points", x.shape,
            "two equal 1-d arrays of at least 3 coordinates")
    scale = max(np.ptp(x), np.ptp(z))
    require(scale > 0, "points", scale, "not all at one place")
    xs, zs = (x - x.mean()) / scale, (z - z.mean()) / scale
    Z = np.column_stack([xs * xs + zs * zs, xs, zs, np.ones_like(xs)])
    values, vectors = eig(Z.T @ Z, _PRATT)
    values = values.real
    admissible = np.flatnonzero(np.isfinite(values) & (values > -1e-12 * np.abs(values).max()))
    a = vectors[:, admissible[np.argmin(values[admissible])]].real
    a /= np.sqrt(a @ _PRATT @ a)
    if np.mean(2 * a[0] * zs + a[2]) < 0:
        a = -a
    return float(2 * a[0] / scale)


def sulci(z: Sequence[float] | np.ndarray, fraction: float = 0.1) -> tuple[float, float]:
    """The number of sulci of the line sampled at the heights ``z`` between two symmetry
    planes (one on an end counts one half) and the depth of the deepest (see the module's
    notes); (0, 0) for a line whose height does not vary."""
    z = np.asarray(z, float)
    require(z.ndim == 1 and len(z) >= 3 and np.isfinite(z).all(), "heights", z.shape,
            "a 1-d array of at least 3 finite values")
    threshold = fraction * np.ptp(z)
    if threshold == 0:
        return 0.0, 0.0
    period = np.concatenate([z, z[-2:0:-1]])
    walk = np.roll(period, -int(np.argmax(period)))
    crests, troughs, falling, extreme = [walk[0]], [], True, walk[0]
    for value in np.append(walk[1:], walk[0]):
        if falling and value - extreme >= threshold:
            troughs.append(extreme)
            falling, extreme = False, value
        elif not falling and extreme - value >= threshold:
            crests.append(extreme)
            falling, extreme = True, value
        else:
            extreme = min(extreme, value) if falling else max(extreme, value)
    crests.append(extreme)
    depths = [min(left, right) - trough
              for left, right, trough in zip(crests[:-1], crests[1:], troughs, strict=True)]
    return len(troughs) / 2, float(max(depths))
