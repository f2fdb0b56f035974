"""Growth laws for mechanically coupled growth (section 2.6, eq. 44-48).

A law (:class:`GrowthLaw`) gives the growth rate d theta / dt from the current growth theta and
the elastic stretch measure theta_e = theta_total / theta, where theta_total is the total
stretch that matches the growth kind (``stretch(F)`` of a
:class:`~ngincompat.mechanics.growth.GrowthModel`). The update is implicit Euler (eq. 48),

    R^g = theta_{n+1} - theta_n - dt * rate(theta_{n+1}, theta_e(F, theta_{n+1})) = 0,

solved together with equilibrium in the global Newton iteration, so the tangent contains the
growth part c^g of eq. (49) exactly (it is the symbolic derivative of the same residual).
"""

from dataclasses import dataclass
from typing import Protocol, TypeAlias

import ngsolve as ngs

from ngincompat.errors import require

CF: TypeAlias = ngs.CoefficientFunction


class GrowthLaw(Protocol):
    """What the coupled problem uses of a growth law."""

    def rate(self, theta: CF, theta_e: CF) -> CF:
        """d theta / dt at growth theta and elastic stretch theta_e (section 2.6)."""


def _macaulay(a: CF) -> CF:
    return ngs.IfPos(a, a, 0.0)


def _positive_power(a: CF, n: float) -> CF:
    """<a>^n, with a derivative that is finite everywhere (a ** n alone has a NaN derivative
    at a = 0 for non-integer arithmetic; the branch not taken is never used)."""
    if n == 0:
        return ngs.IfPos(a, 1.0, 0.0)
    return ngs.IfPos(a, a ** n, 0.0)


@dataclass(frozen=True)
class StrainDrivenLaw:
    """Strain-driven growth, eq. (45):

    rate = (1/tau) ((theta_max - theta) / (theta_max - 1))^gamma <theta_e - theta_crit>.

    Parameters
    ----------
    tau : float
        Time constant, > 0 (its unit is the time unit of the scene).
    theta_max : float
        Upper limit of growth, > 1: the rate vanishes there (saturation).
    gamma : float
        Shape exponent, >= 0.
    theta_crit : float
        Elastic stretch below which nothing grows (homeostasis), > 0.
    """

    tau: float
    theta_max: float
    gamma: float = 2.0
    theta_crit: float = 1.0

    def __post_init__(self) -> None:
        require(self.tau > 0, "tau", self.tau, "> 0")
        require(self.theta_max > 1, "theta_max", self.theta_max, "> 1")
        require(self.gamma >= 0, "gamma", self.gamma, ">= 0")
        require(self.theta_crit > 0, "theta_crit", self.theta_crit, "> 0")

    def rate(self, theta: CF, theta_e: CF) -> CF:
        room = _positive_power((self.theta_max - theta) / (self.theta_max - 1), self.gamma)
        return (1.0 / self.tau) * room * _macaulay(theta_e - self.theta_crit)


@dataclass(frozen=True)
class HillLaw:
    """Hill-type growth with saturation in the stimulus, eq. (46):

    rate = k s^n / (K^n + s^n) <(theta_max - theta) / (theta_max - 1)>,
    s = <theta_e - theta_crit>;

    the last factor (ours; eq. 46 has none) lets growth saturate continuously at
    ``theta_max``, so that Newton's method sees a continuous rate.

    Parameters
    ----------
    k : float
        Largest growth rate, > 0 (1 / time unit of the scene).
    K : float
        Stimulus of half the largest rate, > 0.
    n : float
        Hill exponent, >= 1.
    theta_crit : float
        Elastic stretch below which nothing grows, > 0.
    theta_max : float
        Saturation of growth, > 1.
    """

    k: float
    K: float
    n: float = 2.0
    theta_crit: float = 1.0
    theta_max: float = 3.0

    def __post_init__(self) -> None:
        require(self.k > 0, "k", self.k, "> 0")
        require(self.K > 0, "K", self.K, "> 0")
        require(self.n >= 1, "n", self.n, ">= 1")
        require(self.theta_crit > 0, "theta_crit", self.theta_crit, "> 0")
        require(self.theta_max > 1, "theta_max", self.theta_max, "> 1")

    def rate(self, theta: CF, theta_e: CF) -> CF:
        sn = _positive_power(theta_e - self.theta_crit, self.n)
        room = _macaulay((self.theta_max - theta) / (self.theta_max - 1))
        return self.k * sn / (self.K ** self.n + sn) * room


@dataclass(frozen=True)
class ConstantRateLaw:
    """Growth at a prescribed constant rate, independent of the mechanics:

    rate = r,  so theta(t) = 1 + r t

    (the cortex of section 3.7, "not mechanically coupled"). Implicit Euler integrates it
    exactly; r = 0 freezes growth.

    Parameters
    ----------
    r : float
        d theta / dt, >= 0 (1 / time unit of the scene).
    """

    r: float

    def __post_init__(self) -> None:
        require(self.r >= 0, "rate", self.r, ">= 0")

    def rate(self, theta: CF, theta_e: CF) -> CF:
        return ngs.CF(self.r)


@dataclass(frozen=True, eq=False)
class RegionalLaw:
    """One growth law per region of the mesh (a prescribed cortex on a stretch-driven
    subcortex): the rate in region r is that of ``laws[r]``.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    laws : dict
        Region name -> :class:`GrowthLaw`; every region of the mesh needs one.
    """

    mesh: ngs.Mesh
    laws: dict

    def __post_init__(self) -> None:
        regions = set(self.mesh.GetMaterials())
        require(set(self.laws) == regions, "laws", sorted(self.laws),
                f"one law for each region: {', '.join(sorted(regions))}")

    def rate(self, theta: CF, theta_e: CF) -> CF:
        return self.mesh.MaterialCF({r: law.rate(theta, theta_e)
                                     for r, law in self.laws.items()})


def euler_residual(law: GrowthLaw, theta: CF, theta_old: CF, dt: CF | float,
                   theta_total: CF) -> CF:
    """R^g of eq. (48) with theta_e = theta_total / theta."""
    return theta - theta_old - dt * law.rate(theta, theta_total / theta)
