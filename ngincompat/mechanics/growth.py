"""Growth tensors Fg (eq. 13, 18, 23) driven by a growth indicator theta(X, t).

A growth model is anything with the shape of :class:`GrowthModel`: the indicator ``theta``
(a scalar CoefficientFunction, usually a function of the reference coordinates and a time
:class:`ngsolve.Parameter`), the growth tensor ``Fg``, its volume change ``Jg = det Fg``, the
closed-form incompatibility tensor G where one is known, and the total stretch measure that
drives growth laws (section 2.6). For the three kinds of section 2.3, Jg = theta.

A growth *kind* that is built from theta (and, where it needs one, a
:class:`~ngincompat.mechanics.fields.DirectionField`) subclasses :class:`GrowthKind` and names
itself in
the class attribute ``kind``; defining the class registers it, so :func:`make_growth`, the
``custom`` scene and :class:`~ngincompat.fem.terms.GrowthEnergy` find it by that name. A new
kind is one class::

    @dataclass(frozen=True, eq=False)
    class AxialGrowth(GrowthKind):
        theta: ngs.CoefficientFunction
        kind = "axial"

        @property
        def Fg(self):
            return ngs.CF((self.theta, 0, 0, 0, 1, 0, 0, 0, 1), dims=(3, 3))

        def stretch(self, F):
            return ngs.Norm(F * ngs.CF((1, 0, 0)))
"""

from collections.abc import KeysView, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, Self, TypeAlias, runtime_checkable

import ngsolve as ngs
import numpy as np

from ngincompat.errors import ParameterError
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics import bounds
from ngincompat.mechanics.fields import DirectionField
from ngincompat.sampling import element_boxes, element_points

CF: TypeAlias = ngs.CoefficientFunction


@runtime_checkable
class GrowthModel(Protocol):
    """What the mechanics, the incompatibility analysis and the growth laws use of a growth
    model."""

    @property
    def theta(self) -> CF:
        """The growth indicator theta(X, t), > 0."""

    @property
    def Fg(self) -> CF:
        """The growth tensor, 3x3."""

    @property
    def Jg(self) -> CF:
        """Its volume change det Fg."""

    def closed_form_G(self) -> CF | None:
        """G = (1/Jg) Fg Curl Fg written out in closed form (section 2.3), or None."""

    def stretch(self, F: CF) -> CF:
        """The total stretch measure theta_total of the deformation gradient F whose ratio
        theta_e = theta_total / theta drives growth laws (section 2.6)."""


#: The registered growth kinds, name -> class, in the order of their definition.
_KINDS: dict[str, type["GrowthKind"]] = {}

#: The names of the registered growth kinds: a live view, so kinds defined later appear too.
KINDS: KeysView[str] = _KINDS.keys()


class GrowthKind:
    """Base of the growth kinds built from a growth indicator theta, registered by name.

    A subclass that sets the class attribute ``kind`` is registered under that name when it
    is defined; it must provide ``Fg`` and ``stretch(F)`` (see :class:`GrowthModel`) and be
    constructible as ``cls(theta)``, or ``cls(theta, direction)`` when ``direction_role``
    names the direction it needs. ``Jg = theta`` and ``closed_form_G() = None`` are the
    defaults.

    Attributes
    ----------
    kind : str
        The registry name (class attribute).
    direction_role : str or None
        What the direction is, e.g. "N0" (class attribute); None for a kind without one.
    """

    kind: ClassVar[str]
    direction_role: ClassVar[str | None] = None
    theta: CF

    if TYPE_CHECKING:   # the constructor a registered kind has (a dataclass's)
        def __init__(self, theta: CF, direction: DirectionField | None = None) -> None: ...

        # and what it must provide (:meth:`__init_subclass__` checks that it does)
        @property
        def Fg(self) -> CF: ...

        def stretch(self, F: CF) -> CF: ...

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("kind")
        if name is None:
            return
        missing = [m for m in ("Fg", "stretch") if not hasattr(cls, m)]
        if missing:
            raise TypeError(f"growth kind {name!r} ({cls.__qualname__}) lacks "
                            f"{', '.join(missing)}")
        if name in _KINDS:
            raise TypeError(f"growth kind {name!r} is already registered by "
                            f"{_KINDS[name].__qualname__}")
        _KINDS[name] = cls

    @classmethod
    def from_theta(cls, theta: CF, direction: DirectionField | None = None) -> Self:
        """The growth of this kind for the indicator theta.

        Parameters
        ----------
        theta : ngsolve.CoefficientFunction
            The growth indicator theta(X, t).
        direction : DirectionField, optional
            The direction of a kind that needs one (N0, f0); ignored by one that does not.

        Raises
        ------
        ParameterError
            If the kind needs a direction and none is given.
        """
        if cls.direction_role is None:
            return cls(theta)
        if direction is None:
            raise ParameterError(f"{cls.kind} growth needs a direction ({cls.direction_role})")
        return cls(theta, direction)

    @property
    def Jg(self) -> CF:
        """det Fg, which is theta for the kinds of section 2.3."""
        return self.theta

    def closed_form_G(self) -> CF | None:
        """No closed form unless the kind writes one out."""
        return None


def growth_kind(name: str) -> type[GrowthKind]:
    """The registered growth kind called ``name``.

    Raises
    ------
    ParameterError
        If no kind of that name is registered; the message lists those that are.
    """
    try:
        return _KINDS[name]
    except KeyError:
        raise ParameterError(
            f"growth = {name!r} is unknown: allowed {', '.join(_KINDS)}") from None


def make_growth(kind: str, theta: CF, direction: DirectionField | None = None) -> GrowthKind:
    """Build a growth model by the name of its kind.

    Parameters
    ----------
    kind : str
        A registered kind (:data:`KINDS`): "isotropic", "area", "fiber" or one defined
        elsewhere.
    theta : ngsolve.CoefficientFunction
        The growth indicator theta(X, t).
    direction : DirectionField, optional
        N0 for area growth, f0 for fiber growth; ignored by kinds without a direction.
    """
    return growth_kind(kind).from_theta(theta, direction)


@dataclass(frozen=True, eq=False)
class IsotropicGrowth(GrowthKind):
    """Isotropic volume growth, eq. (13): Fg = theta^(1/3) I."""

    theta: CF
    kind = "isotropic"

    @property
    def Fg(self) -> CF:
        return self.theta ** (1.0 / 3.0) * ngs.Id(3)

    def stretch(self, F: CF) -> CF:
        """The volume stretch J = det F (section 2.6)."""
        return ngs.Det(F)

    def closed_form_G(self) -> CF:
        """G of eq. (16), with the gradient of theta taken symbolically."""
        return inc.G_isotropic_closed_form(self.theta, inc.grad_scalar(self.theta))


@dataclass(frozen=True, eq=False)
class AreaGrowth(GrowthKind):
    """Transversely isotropic area growth about N0, eq. (18).

    Fg = sqrt(theta) I + (1 - sqrt(theta)) N0 (x) N0.
    """

    theta: CF
    normal: DirectionField
    kind = "area"
    direction_role = "N0"

    @property
    def Fg(self) -> CF:
        s = ngs.sqrt(self.theta)
        n = self.normal.cf
        return s * ngs.Id(3) + (1 - s) * ngs.OuterProduct(n, n)

    def stretch(self, F: CF) -> CF:
        """The area stretch J |F^-T N0| of the plane normal to N0 (Nanson, section 2.6)."""
        return ngs.Det(F) * ngs.Norm(ngs.Inv(F).trans * self.normal.cf)

    def closed_form_G(self) -> CF | None:
        """G of eq. (20) for a constant N0; None for a varying one."""
        if not self.normal.is_constant:
            return None
        return inc.G_area_closed_form(self.theta, inc.grad_scalar(self.theta), self.normal.cf)


@dataclass(frozen=True, eq=False)
class FiberGrowth(GrowthKind):
    """Uniaxial fiber growth along f0, eq. (23): Fg = I + (theta - 1) f0 (x) f0."""

    theta: CF
    fiber: DirectionField
    kind = "fiber"
    direction_role = "f0"

    @property
    def Fg(self) -> CF:
        f = self.fiber.cf
        return ngs.Id(3) + (self.theta - 1) * ngs.OuterProduct(f, f)

    def stretch(self, F: CF) -> CF:
        """The fiber stretch |F f0| (section 2.6)."""
        return ngs.Norm(F * self.fiber.cf)

    def closed_form_G(self) -> CF | None:
        """G of eq. (25) for a constant f0; None for a varying one."""
        if not self.fiber.is_constant:
            return None
        return inc.G_fiber_closed_form(self.theta, inc.grad_scalar(self.theta), self.fiber.cf)


@dataclass(frozen=True, eq=False)
class TensorGrowth:
    """A growth tensor given directly by the user, a 3x3 CoefficientFunction of (X, t).

    Its growth indicator is the volume change, theta = det Fg. Not a registered kind: it is
    built from a tensor, not from theta.
    """

    tensor: CF
    kind = "tensor"

    def __post_init__(self) -> None:
        if tuple(self.tensor.dims) != (3, 3):
            raise ParameterError(f"growth tensor must be 3x3, got dims {tuple(self.tensor.dims)}")

    @property
    def Fg(self) -> CF:
        return self.tensor

    @property
    def Jg(self) -> CF:
        return ngs.Det(self.tensor)

    @property
    def theta(self) -> CF:
        return self.Jg

    def stretch(self, F: CF) -> CF:
        """The volume stretch J = det F, the measure conjugate to theta = det Fg."""
        return ngs.Det(F)

    def closed_form_G(self) -> None:
        """None: no closed form for a general tensor."""
        return None


#: The times at which :func:`check_positive` checks a time-dependent theta: 1/128 apart, so a
#: growth that dips below zero for a sixty-fourth of the time is found (five times were
#: checked before, and theta = 1 + 2 sin(8 pi t), -1 at t = 3/16, passed).
CHECK_TIMES = tuple(k / 128 for k in range(129))


#: The largest theta whose cube, Jg of isotropic growth, is a finite float (5.6e102).
THETA_MAX = float(np.cbrt(np.finfo(float).max))
#: The smallest growth indicator taken (see :func:`check_positive`).
THETA_FLOOR = 1e-3


def check_positive(theta: CF, mesh: ngs.Mesh, time: ngs.Parameter | None = None,
                   times: Sequence[float] = CHECK_TIMES, order: int = 4,
                   expression: str | None = None) -> None:
    """Raise :class:`ParameterError` unless 0 < theta < inf everywhere in the body, and its
    cube, Jg of isotropic growth (eq. 13), is finite too.

    theta is evaluated at the vertices and at the points of an integration rule of the given
    order in every element, at each of ``times`` (when a time Parameter is given). The message
    names the worst point and time: a non-finite value (NaN or +-inf) if there is one, else the
    smallest value. Given the ``expression`` theta was parsed from, theta > 0 is then proven
    between those points too, on a box around every element over the whole growth time
    (:func:`ngincompat.mechanics.bounds.positive_on`: interval arithmetic), or a point where it
    fails is named.

    Parameters
    ----------
    theta : ngsolve.CoefficientFunction
        The growth indicator theta(X, t).
    mesh : ngsolve.Mesh
        The body.
    time : ngsolve.Parameter, optional
        What t stands for in theta; it is restored after the check.
    times : sequence of float
        The times checked when ``time`` is given (:data:`CHECK_TIMES`: 129 in [0, 1]).
    order : int
        Order of the integration rule whose points are checked.
    expression : str, optional
        The expression theta is (:mod:`ngincompat.mechanics.expressions`), in X1, X2, X3 and t.

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
            finite = np.isfinite(values) & (np.abs(values) < THETA_MAX)
            bad = ~finite | (values <= 0)
            low = finite & (values < THETA_FLOOR)
            if not (bad.any() or low.any()):
                continue
            i = int(np.argmin(np.where(finite, values, -np.inf)))
            at = "X = ({:.4g}, {:.4g}, {:.4g})".format(*coords[i]) + (
                "" if t is None else f", t = {t:g}")
            if not bad.any():
                raise ParameterError(
                    f"theta = {values[i]:.4g} at {at} is below {THETA_FLOOR:g}: the growth "
                    "indicator must be at least that everywhere in the body (a thousandfold "
                    "shrinking leaves no tissue, and the growth tensor becomes singular in "
                    "double precision)")
            what = (f"theta = {values[i]:.4g}" if finite[i] else
                    f"theta is not finite (theta = {values[i]})"
                    if not np.isfinite(values[i]) else
                    f"theta = {values[i]:.4g} overflows its cube, the volume growth Jg")
            raise ParameterError(
                f"{what} at {at}: the growth indicator must be finite and "
                "positive (0 < theta < inf) everywhere in the body")
    finally:
        if time is not None:
            time.Set(saved)
    if expression is not None:
        lo, hi = element_boxes(mesh, order)
        span = (min(times), max(times)) if time is not None else (1.0, 1.0)
        found = bounds.positive_on(expression, np.column_stack([lo, np.full(len(lo), span[0])]),
                                   np.column_stack([hi, np.full(len(hi), span[1])]))
        if found is not None:
            (x, y, z, t), value, sampled = found
            where = f"X = ({x:.4g}, {y:.4g}, {z:.4g})" + (f", t = {t:.4g}" if time is not None
                                                           else "")
            what = (f"theta = {value:.4g} at {where}, between the points where it was sampled"
                    if sampled else f"theta could not be shown positive near {where}: its "
                    f"bounds there reach {value:.4g}")
            raise ParameterError(
                f"{what}: the growth indicator must be finite and positive "
                "(0 < theta < inf) everywhere in the body")
