"""Atrophy: volume loss theta < 1 driven by the misfolded-protein concentration c.

Isotropic growth Fg = theta^(1/3) I (eq. 13) with theta decreasing at a rate proportional to
the local concentration and saturating at theta_min (the largest volume loss, about 30 % in
Lee et al. 2021, section 3.5; the law is a choice, the paper gives none):

    d theta / dt = - G c (theta - theta_min) / (1 - theta_min),     theta(0) = 1,

with a rate G per tissue (gray matter faster than white). With c frozen over a time step the
update is exact,

    theta^{n+1} = theta_min + (theta^n - theta_min) exp(- G dt c^{n+1} / (1 - theta_min)),

and steps compose, so theta is a function of the *exposure* E = sum dt c^{k} (the
rectangle rule of int_0^t c ds):

    theta = theta_min + (1 - theta_min) exp(- G E / (1 - theta_min)).

Evaluated wherever it is needed (integration points, sampling points), theta therefore never
reaches theta_min, whatever the step. c enters clamped to [0, 1].
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ngincompat.errors import require

if TYPE_CHECKING:     # NGSolve is imported where a field is made
    import ngsolve as ngs


@dataclass(frozen=True)
class AtrophyLaw:
    """The atrophy law of one tissue.

    Parameters
    ----------
    rate : float
        G >= 0 [1/time]: the initial rate of volume loss at c = 1, d theta/dt = -G.
    theta_min : float
        The lower bound of theta, in (0, 1).
    name : str
        How the rate is called in error messages (the scene's parameter name).
    """

    rate: float
    theta_min: float
    name: str = "rate"

    def __post_init__(self) -> None:
        require(self.rate >= 0, self.name, self.rate, ">= 0 (rate of volume loss)")
        require(0 < self.theta_min < 1, "theta_min", self.theta_min, "in (0, 1)")

    def theta(self, exposure: np.ndarray | ngs.CoefficientFunction,
              exp: Callable[[Any], Any] = np.exp) -> np.ndarray | ngs.CoefficientFunction:
        """theta after the exposure E = int c dt (numpy array or, with ``exp=ngsolve.exp``,
        a CoefficientFunction)."""
        span = 1.0 - self.theta_min
        return self.theta_min + span * exp(-self.rate * exposure / span)

    def check_step(self, dt: float) -> None:
        """Raise ParameterError unless one step at c = 1 loses less than the whole span
        1 - theta_min at the initial rate: G dt < 1 - theta_min (a step that the explicit
        rate would carry past theta_min resolves nothing of the approach to it)."""
        span = 1.0 - self.theta_min
        require(self.rate * dt < span, self.name, self.rate,
                f"< (1 - theta_min) / dt = {span / dt:g} (one step at the initial rate would "
                "pass theta_min)")


def exposure_increment(c: np.ndarray, dt: float) -> np.ndarray:
    """dt clamp(c, 0, 1): what one step adds to the exposure (numpy array of values of c)."""
    return dt * np.clip(c, 0.0, 1.0)
