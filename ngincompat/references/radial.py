"""An independent 1-D reference: spherically symmetric isotropic growth of a neo-Hookean ball.

Written separately from the finite element code (numpy and scipy only) so that it can verify
it: the hemisphere in symmetry mode is exactly half of this ball.

With r(R) the deformed radius, the stretches are lambda_r = r' and lambda_t = r / R, the
elastic stretches e_i = lambda_i theta^(-1/3) (eq. 13), and with the neo-Hookean energy of
eq. (36) per intermediate volume the nominal stresses of W = theta Psi are

    P_i = theta^(2/3) (mu e_i - (mu - lam ln Je) / e_i),   Je = e_r e_t^2.

Equilibrium without body force (eq. 30) in spherical symmetry is
dP_r/dR + 2 (P_r - P_t) / R = 0 with r(0) = 0 and P_r(R0) = 0 (traction-free surface); the
Cauchy stresses are sigma_rr = P_r / lambda_t^2 and sigma_tt = P_t / (lambda_r lambda_t).
The system y = (r, P_r) is integrated outward from the isotropic state r = l0 R at R = eps
(:func:`scipy.integrate.solve_ivp`, DOP853) and the central stretch l0 is found by shooting
(:func:`scipy.optimize.brentq`) on P_r(R0) = 0.
"""

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


@dataclass(frozen=True)
class RadialSolution:
    """The 1-D solution as dense output in the reference radius R."""

    R0: float
    mu: float
    lam: float
    theta: Callable[[float | np.ndarray], float | np.ndarray]
    _sol: Any

    def radius(self, R: float | np.ndarray) -> np.ndarray:
        return self._sol.sol(np.asarray(R, float))[0]

    def cauchy(self, R: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(sigma_rr, sigma_tt) at reference radii R (sigma_tt = sigma_pp by symmetry)."""
        R = np.asarray(R, float)
        r, P = self._sol.sol(R)
        lr = _radial_stretch(self.theta(R), r / R, P, self.mu, self.lam)
        lt = r / R
        Pt = _nominal(self.theta(R), lt, lr, lt, self.mu, self.lam)
        return P / lt ** 2, Pt / (lr * lt)


def _nominal(theta: float | np.ndarray, l_i: float | np.ndarray, l_a: float | np.ndarray,
             l_b: float | np.ndarray, mu: float, lam: float) -> float | np.ndarray:
    """Nominal stress along stretch l_i with the other two stretches l_a, l_b."""
    c = theta ** (-1.0 / 3.0)
    e = l_i * c
    lnJ = np.log(l_i * l_a * l_b * c ** 3)
    return theta ** (2.0 / 3.0) * (mu * e - (mu - lam * lnJ) / e)


def _radial_stretch(theta: float | np.ndarray, lt: float | np.ndarray, P: float | np.ndarray,
                    mu: float, lam: float) -> np.ndarray:
    """Invert P_r(lambda_r; lambda_t) for lambda_r by Newton's method (P_r is increasing)."""
    c = theta ** (-1.0 / 3.0)
    et = lt * c
    target = P / theta ** (2.0 / 3.0)
    e = np.array(et, dtype=float, copy=True)
    for _ in range(100):
        with np.errstate(invalid="ignore", divide="ignore"):
            lnJ = np.log(e * et * et)
        g = mu * e - (mu - lam * lnJ) / e - target
        dg = mu + (mu - lam * lnJ) / e ** 2 + lam / e ** 2
        step = g / dg
        e = np.maximum(e - step, 0.5 * e)
        if np.max(np.abs(step)) < 1e-15:
            break
    return e / c


def solve_radial(theta: Callable[[float | np.ndarray], float | np.ndarray], mu: float, lam: float,
                 R0: float = 1.0, eps: float = 1e-6, rtol: float = 1e-12) -> RadialSolution:
    """Solve the spherically symmetric growth problem by shooting on the central stretch.

    Parameters
    ----------
    theta : callable
        theta(R), vectorised over numpy arrays.
    mu, lam : float
        Lame parameters of the neo-Hookean material (eq. 36).
    R0 : float
        Outer radius.

    Returns
    -------
    RadialSolution
    """

    def rhs(R: float, y: np.ndarray) -> list[float]:
        r, P = y
        th = theta(R)
        lt = r / R
        lr = _radial_stretch(th, lt, P, mu, lam)
        Pt = _nominal(th, lt, lr, lt, mu, lam)
        return [lr, -2.0 * (P - Pt) / R]

    def shoot(l0: float, dense: bool = False) -> Any:
        th0 = theta(np.array(eps))
        y0 = [l0 * eps, float(_nominal(th0, l0, l0, l0, mu, lam))]
        return solve_ivp(rhs, (eps, R0), y0, method="DOP853", rtol=rtol, atol=1e-14,
                         dense_output=dense)

    guess = float(np.cbrt(theta(np.array(eps))))
    l0 = brentq(lambda l: shoot(l).y[1, -1], 0.5 * guess, 2.0 * guess, xtol=1e-15, rtol=1e-15)
    sol = shoot(l0, dense=True)
    if not sol.success:
        raise RuntimeError(f"radial reference solution failed: {sol.message}")
    return RadialSolution(R0, mu, lam, theta, sol)
