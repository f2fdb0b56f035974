"""A tissue expander as a rigid dome the skin rests on, in frictionless contact (section 3.6).

The expander over a footprint (:data:`ngincompat.names.FOOTPRINTS`, sized as in
:func:`geometries.skin_patch`) is the surface x3 = H phi(x1, x2) of height H, with phi a dome
that is 1 at its top and vanishes on the footprint's edge:

* circle of radius R: phi = 1 - r^2 / R^2, the inflated shape of a membrane under pressure
  (the solution of -Lap w = 1 on the disc, w = 0 on its edge, scaled);
* rectangle and square of half sides A, B: phi = (1 - x^2/A^2)(1 - y^2/B^2), a product of the
  membrane's one-dimensional profiles (the Poisson solution's series is not used);
* crescent, the disc |X| < R minus the disc |X - (R, 0)| < R: phi proportional to
  (1 - r1^2/R^2)(r2^2/R^2 - 1), zero on both arcs.

phi is 0 outside the footprint (the base the expander lies on). The gap of a point x of the
skin's lower surface is its distance above the dome to first order,

    g(x) = (x3 - H phi(x1, x2)) / sqrt(1 + H^2 |grad phi|^2),

negative where the skin penetrates the expander. The contact is enforced by a smoothed penalty:
the contact pressure per unit reference area is p = kappa r(-g), with r the ramp max(s, 0)
rounded over a width ``width`` eps (a quadratic blend, so that dp/dg is continuous):

    r(s) = 0                   s <= 0,
         = s^2 / (2 eps)       0 < s < eps,
         = s - eps / 2         s >= eps,

and the energy (kappa) int R(-g) dA over the skin's lower surface in the reference
configuration, R(s) = int_0^s r = s^3 / (6 eps) on (0, eps), s^2 / 2 - eps s / 2 + eps^2 / 6
beyond. Its force -kappa r(-g) dg/dx is normal to the dome (frictionless: the skin slides
freely). R is twice continuously differentiable, so Newton's tangent does not jump where a
point of the surface crosses g = 0 (the plain penalty (kappa / 2) min(g, 0)^2, eps = 0, has a
tangent that switches between 0 and kappa there: on a skin laid onto the dome, g = 0 up to
round-off, its Newton iterations did not converge). p is zero wherever the gap is open
(g >= 0), and the penetration of a point that carries the pressure p is p / kappa + eps / 2
(p >= kappa eps / 2), so it vanishes like 1 / kappa + eps / 2.

The gap's derivative jumps on the footprint's edge (grad phi does), but the edge lies on the
base (x3 = 0 there, g = 0 on both sides) and R vanishes with its first two derivatives at
g = 0, so the energy is twice differentiable across it too.

All functions accept NGSolve CoefficientFunctions (so Newton gets the exact tangent by
symbolic differentiation) or numpy arrays. :class:`ExpanderContact` is the contact as a term
of a :class:`~ngincompat.fem.coupled.CoupledProblem`.
"""

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar, TypeAlias

import ngsolve as ngs
import numpy as np

from ngincompat import names
from ngincompat.errors import require
from ngincompat.fem.terms import Unknown, VolumeHolder

# what the functions here take and give: CoefficientFunctions, or numpy arrays
_Values: TypeAlias = ngs.CoefficientFunction | np.ndarray


def _ifpos(c: _Values, a: Any, b: Any) -> _Values:
    """a where c > 0, else b, for CoefficientFunctions or arrays."""
    if isinstance(c, ngs.CoefficientFunction):
        return ngs.IfPos(c, a, b)
    return np.where(c > 0, a, b)


def ramp(s: _Values, eps: float) -> tuple[_Values, _Values]:
    """The ramp max(s, 0) rounded over the width ``eps`` (see the module's notes), r(s) = 0,
    s^2 / (2 eps), s - eps / 2, and its integral R(s) = 0, s^3 / (6 eps), s^2 / 2 - eps s / 2
    + eps^2 / 6 (s <= 0, 0 < s < eps, s >= eps); eps = 0: max(s, 0) and max(s, 0)^2 / 2."""
    if eps == 0:
        return _ifpos(s, s, 0 * s), _ifpos(s, s * s / 2, 0 * s)
    inner = _ifpos(s - eps, s - eps / 2, s * s / (2 * eps))
    integral = _ifpos(s - eps, s * s / 2 - eps * s / 2 + eps * eps / 6, s * s * s / (6 * eps))
    return _ifpos(s, inner, 0 * s), _ifpos(s, integral, 0 * s)


@dataclass(frozen=True)
class Expander:
    """A rigid dome over a footprint; ``penalty`` kappa (MPa/cm) enforces the contact, its
    ramp rounded over the penetration ``width`` eps (cm)."""

    #: The domes this module can shape, one per footprint of the skin patch.
    FOOTPRINTS: ClassVar[tuple[str, ...]] = names.FOOTPRINTS

    footprint: str
    size: float
    penalty: float
    width: float = 0.0

    def __post_init__(self) -> None:
        require(self.footprint in self.FOOTPRINTS, "footprint", self.footprint,
                ", ".join(self.FOOTPRINTS))
        require(self.size > 0, "footprint_size", self.size, "> 0")
        require(math.isfinite(self.penalty) and self.penalty > 0, "penalty", self.penalty,
                "> 0 (finite)")
        require(math.isfinite(self.width) and self.width >= 0, "contact_width", self.width,
                ">= 0 (finite)")

    def factors(self) -> tuple[tuple[float, ...], ...]:
        """The dome as a product of quadratics: (sign, x0, y0, cx, cy) stands for
        sign (1 - cx (x - x0)^2 - cy (y - y0)^2); inside the footprint all are positive."""
        r = self.size / 2
        if self.footprint == "circle":
            return ((1, 0, 0, 1 / r**2, 1 / r**2),)
        if self.footprint == "crescent":
            return ((1, 0, 0, 1 / r**2, 1 / r**2), (-1, r, 0, 1 / r**2, 1 / r**2))
        a, b = r, (r / 2 if self.footprint == "rectangle" else r)
        return ((1, 0, 0, 1 / a**2, 0), (1, 0, 0, 0, 1 / b**2))

    def _raw(self, x: _Values, y: _Values) -> tuple[_Values, _Values, _Values]:
        """phi before scaling to 1 at its top, and its gradient (zero outside)."""
        values, grads = [], []
        for sign, x0, y0, cx, cy in self.factors():
            values.append(sign * (1 - cx * (x - x0) ** 2 - cy * (y - y0) ** 2))
            grads.append((-2 * sign * cx * (x - x0), -2 * sign * cy * (y - y0)))
        phi, dx, dy = values[0], grads[0][0], grads[0][1]
        for f, (fx, fy) in zip(values[1:], grads[1:], strict=True):
            phi, dx, dy = phi * f, dx * f + phi * fx, dy * f + phi * fy
        for f in values:             # zero wherever a factor is not positive
            phi, dx, dy = (_ifpos(f, phi, 0 * f), _ifpos(f, dx, 0 * f),
                           _ifpos(f, dy, 0 * f))
        return phi, dx, dy

    @cached_property
    def peak(self) -> float:
        """The largest value of the unscaled dome (1 but for the crescent, found on a grid of
        the footprint's bounding box with 1001 x 1001 points)."""
        s = np.linspace(-self.size / 2, self.size / 2, 1001)
        x, y = np.meshgrid(s, s)
        return float(np.max(self._raw(x, y)[0]))

    def shape(self, x: _Values, y: _Values) -> tuple[_Values, ...]:
        """phi(x, y) and its gradient, scaled so that the top of the dome is at 1."""
        peak = self.peak
        return tuple(c / peak for c in self._raw(x, y))

    def gap(self, x: ngs.CoefficientFunction | Sequence[np.ndarray],
            height: ngs.CoefficientFunction | float) -> _Values:
        """The gap g of the point x (a 3-vector CF, or a tuple of arrays) above the dome of
        ``height``: negative where the skin penetrates the expander."""
        phi, dx, dy = self.shape(x[0], x[1])
        slope = (1 + height * height * (dx * dx + dy * dy)) ** 0.5
        return (x[2] - height * phi) / slope

    def ramp(self, s: _Values) -> tuple[_Values, _Values]:
        """The rounded ramp r(s) and its integral R(s) over the width (:func:`ramp`)."""
        return ramp(s, self.width)

    def energy(self, x: ngs.CoefficientFunction | Sequence[np.ndarray],
               height: ngs.CoefficientFunction | float) -> _Values:
        """The penalty energy per reference area, kappa R(-g)."""
        return self.penalty * self.ramp(-self.gap(x, height))[1]

    def pressure(self, x: ngs.CoefficientFunction | Sequence[np.ndarray],
                 height: ngs.CoefficientFunction | float) -> _Values:
        """The contact pressure kappa r(-g) per reference area (zero where open)."""
        return self.penalty * self.ramp(-self.gap(x, height))[0]

    def points(self, spacing: float) -> np.ndarray:
        """Points of the footprint (X3 = 0) on a square grid of ``spacing``, for sampling."""
        require(spacing > 0, "spacing", spacing, "> 0")
        n = int(math.ceil(self.size / spacing)) + 1
        s = np.linspace(-self.size / 2, self.size / 2, n)
        x, y = (c.ravel() for c in np.meshgrid(s, s))
        inside = self._raw(x, y)[0] > 0
        return np.column_stack([x[inside], y[inside], np.zeros(np.count_nonzero(inside))])


def sample(mesh: ngs.Mesh, expander: Expander, cfs: Mapping[str, ngs.CoefficientFunction],
           spacing: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Values of the CFs ``cfs`` (name -> CF) on the skin's lower surface at the footprint's
    points of a grid of ``spacing`` (:meth:`Expander.points`); returns (points, values)."""
    pts = expander.points(spacing)
    where = mesh(pts[:, 0], pts[:, 1], np.full(len(pts), 1e-9))
    return pts, {k: np.asarray(cf(where)).ravel() for k, cf in cfs.items()}


def measure(mesh: ngs.Mesh, boundary: str, expander: Expander, height: float,
            gap: ngs.CoefficientFunction, pressure: ngs.CoefficientFunction) -> dict[str, float]:
    """The expander and its contact with the skin's lower surface ``boundary``: height,
    contact area (where g < 0, reference area), the contact force (the integral of the
    pressure over the reference surface), largest penetration (on a grid of spacing
    size / 50), largest contact pressure with its distance from the centre, and the mean
    pressure over the contact area (the contact force per contact area)."""
    region = mesh.Boundaries(boundary)

    def integral(cf: ngs.CoefficientFunction) -> float:
        return ngs.Integrate(cf, mesh, ngs.BND, definedon=region, order=8)

    area, force = integral(ngs.IfPos(-gap, 1.0, 0.0)), integral(pressure)
    pts, values = sample(mesh, expander, {"gap": gap, "pressure": pressure},
                         expander.size / 50)
    top = int(np.argmax(values["pressure"]))
    return {"expander_height": height,
            "contact_area": area,
            "contact_force": force,
            "penetration_max": max(0.0, -float(np.min(values["gap"]))),
            "contact_pressure_max": float(values["pressure"][top]),
            "contact_pressure_max_radius": float(np.hypot(*pts[top, :2])),
            "contact_pressure_mean": force / area if area > 0 else 0.0}


class ExpanderContact(VolumeHolder):
    """The expander under the ``boundary`` (initially in the plane X3 = 0), in penalty
    contact with it: the energy int kappa R(-g) dA over the boundary (see the module's
    notes), with the dome's height H set by its own volume H int phi dA, the Parameter
    ``target``. There is no extra unknown; the volume under the boundary is measured
    (:meth:`volume`: it exceeds the expander's where the skin leaves it and falls short by
    the penetration). The penalty's kink needs more integration points than the
    displacement's order gives: the residual is integrated with two more.

    Parameters
    ----------
    expander : Expander
    boundary : str
        The boundary that rests on the expander.
    """

    def __init__(self, expander: Expander, boundary: str) -> None:
        super().__init__(boundary)
        self.expander = expander

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals:
        self.mesh, self.u = problem.mesh, problem.u
        region = self.mesh.Boundaries(self.boundary)
        self.base_integral = ngs.Integrate(self.expander.shape(ngs.x, ngs.y)[0], self.mesh,
                                           ngs.BND, definedon=region, order=8)
        u, v = problem.displacement.trial, problem.displacement.test
        contact = self.expander.energy(  # type: ignore[union-attr]  # of a CF, a CF
            _position(u), self.height()).Diff(u, v)
        return contact.Compile() * self._measure()

    def _measure(self) -> ngs.comp.DifferentialSymbol:
        """The boundary's integral, with the two more degrees the penalty's kink needs."""
        return ngs.ds(self.boundary, bonus_intorder=2)

    def held_energy(self, u: ngs.CoefficientFunction) -> ngs.comp.SumOfIntegrals:
        return self.expander.energy(  # type: ignore[union-attr]  # of a CF, a CF
            _position(u), self.height()).Compile() * self._measure()

    def height(self) -> ngs.CoefficientFunction:
        """The expander's height H (a CF) whose volume H int phi dA is the target."""
        return self.target / self.base_integral

    def expander_height(self) -> float:
        """The expander's height H at the current target (:meth:`height`'s value)."""
        return self.target.Get() / self.base_integral

    def set_target(self, volume: float, lift: bool = False) -> None:
        """Set the expander's volume; with ``lift``, the state moves with the expander's
        top (u += dH phi(x1, x2) e3, dH its change of height, x = X + u the point's current
        place): a predictor that keeps every point's height above the expander, for Newton
        to start close to contact. (Lifted by phi at the reference X instead, the skin,
        drawn in over the dome, sank into it, and each inflation step began with Newton
        steps shortened 128-fold: the default circle's inflation took 152 iterations against
        79.)"""
        change = volume - self.target.Get()
        self.target.Set(volume)
        if lift and change != 0:
            phi = self.expander.shape(ngs.x + self.u[0], ngs.y + self.u[1])[0]
            step = ngs.GridFunction(self.u.space)
            step.Set(ngs.CoefficientFunction((0, 0, change / self.base_integral * phi)))
            self.u.vec.data += step.vec

    def gap(self) -> ngs.CoefficientFunction:
        """The contact gap g of the current state (a CF; negative: penetration)."""
        return self.expander.gap(_position(self.u), self.height())

    def contact_pressure(self) -> ngs.CoefficientFunction:
        """The contact pressure of the current state (a CF, per unit reference area)."""
        return self.expander.pressure(_position(self.u), self.height())

    def energy(self, order: int = 8) -> float:
        """The penalty energy of the current state, integrated by NGSolve's rule of
        ``order`` (the default as :func:`measure`'s)."""
        density = self.expander.energy(_position(self.u), self.height())
        return ngs.Integrate(density, self.mesh, ngs.BND,
                             definedon=self.mesh.Boundaries(self.boundary), order=order)

    def measures(self) -> dict[str, float]:
        """The expander and the contact (:func:`measure`)."""
        return measure(self.mesh, self.boundary, self.expander, self.expander_height(),
                       self.gap(), self.contact_pressure())


def _position(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """The current position x = X + u."""
    return ngs.CoefficientFunction((ngs.x, ngs.y, ngs.z)) + u
