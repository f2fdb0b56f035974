"""Growth tensors Fg (eq. 13, 18, 23) driven by a growth indicator theta(X, t).

Each growth kind is a frozen dataclass holding theta (a scalar CoefficientFunction, usually a
function of the reference coordinates and a time :class:`ngsolve.Parameter`) and, where the
kind needs one, a :class:`~ngincompat.fields.DirectionField`. ``Fg`` is the growth tensor and
``Jg = det Fg`` its volume change; for the three kinds of section 2.3, Jg = theta.
"""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from .errors import ParameterError
from .fields import DirectionField
from .sampling import element_points


@dataclass(frozen=True, eq=False)
class IsotropicGrowth:
    """Isotropic volume growth, eq. (13): Fg = theta^(1/3) I."""

    theta: ngs.CoefficientFunction
    kind = "isotropic"

    @property
    def Fg(self):
        return self.theta ** (1.0 / 3.0) * ngs.Id(3)

    @property
    def Jg(self):
        return self.theta


@dataclass(frozen=True, eq=False)
class AreaGrowth:
    """Transversely isotropic area growth about N0, eq. (18).

    Fg = sqrt(theta) I + (1 - sqrt(theta)) N0 (x) N0.
    """

    theta: ngs.CoefficientFunction
    normal: DirectionField
    kind = "area"

    @property
    def Fg(self):
        s = ngs.sqrt(self.theta)
        n = self.normal.cf
        return s * ngs.Id(3) + (1 - s) * ngs.OuterProduct(n, n)

    @property
    def Jg(self):
        return self.theta


@dataclass(frozen=True, eq=False)
class FiberGrowth:
    """Uniaxial fiber growth along f0, eq. (23): Fg = I + (theta - 1) f0 (x) f0."""

    theta: ngs.CoefficientFunction
    fiber: DirectionField
    kind = "fiber"

    @property
    def Fg(self):
        f = self.fiber.cf
        return ngs.Id(3) + (self.theta - 1) * ngs.OuterProduct(f, f)

    @property
    def Jg(self):
        return self.theta


@dataclass(frozen=True, eq=False)
class TensorGrowth:
    """A growth tensor given directly by the user, a 3x3 CoefficientFunction of (X, t).

    Its growth indicator is the volume change, theta = det Fg.
    """

    tensor: ngs.CoefficientFunction
    kind = "tensor"

    def __post_init__(self):
        if tuple(self.tensor.dims) != (3, 3):
            raise ParameterError(f"growth tensor must be 3x3, got dims {tuple(self.tensor.dims)}")

    @property
    def Fg(self):
        return self.tensor

    @property
    def Jg(self):
        return ngs.Det(self.tensor)

    @property
    def theta(self):
        return self.Jg


KINDS = ("isotropic", "area", "fiber")


def make_growth(kind, theta, direction=None):
    """Build a growth model by name.

    Parameters
    ----------
    kind : {"isotropic", "area", "fiber"}
    theta : ngsolve.CoefficientFunction
        The growth indicator theta(X, t).
    direction : DirectionField, optional
        N0 for area growth, f0 for fiber growth; ignored for isotropic growth.
    """
    if kind == "isotropic":
        return IsotropicGrowth(theta)
    if kind not in KINDS:
        raise ParameterError(f"growth = {kind!r} is unknown: allowed {', '.join(KINDS)}")
    if direction is None:
        raise ParameterError(f"{kind} growth needs a direction (N0 or f0)")
    return AreaGrowth(theta, direction) if kind == "area" else FiberGrowth(theta, direction)


def check_positive(theta, mesh, time=None, times=(0.0, 0.25, 0.5, 0.75, 1.0), order=4):
    """Raise :class:`ParameterError` unless 0 < theta < inf everywhere in the body.

    theta is evaluated at the vertices and at the points of an integration rule of the given
    order in every element, at each of ``times`` (when a time Parameter is given). The message
    names the worst point and time: a non-finite value (NaN or +-inf) if there is one, else the
    smallest value.

    Parameters
    ----------
    theta : ngsolve.CoefficientFunction
        The growth indicator theta(X, t).
    mesh : ngsolve.Mesh
        The body.
    time : ngsolve.Parameter, optional
        What t stands for in theta; it is restored after the check.
    times : sequence of float
        The times checked when ``time`` is given.
    order : int
        Order of the integration rule whose points are checked.

    Raises
    ------
    ParameterError
        If theta is not finite, or not positive, somewhere.
    """
    points = element_points(mesh, order)
    coords = np.column_stack([np.asarray(c(points)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    saved = time.Get() if time is not None else None
    try:
        for t in times if time is not None else (None,):
            if time is not None:
                time.Set(t)
            values = np.asarray(theta(points)).ravel()
            finite = np.isfinite(values)
            bad = ~finite | (values <= 0)
            if bad.any():
                i = int(np.argmin(np.where(finite, values, -np.inf)))
                where = "({:.4g}, {:.4g}, {:.4g})".format(*coords[i])
                when = "" if t is None else f", t = {t:g}"
                what = (f"theta = {values[i]:.4g}" if finite[i]
                        else f"theta is not finite (theta = {values[i]})")
                raise ParameterError(
                    f"{what} at X = {where}{when}: the growth indicator must be finite and "
                    "positive (0 < theta < inf) everywhere in the body")
    finally:
        if time is not None:
            time.Set(saved)
