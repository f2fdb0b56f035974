"""Linear bifurcation of a growing stiff layer on a soft substrate, in plane strain: the
independent oracle of the cortical-folding scene's onset (section 3.7 of Lee et al. 2021).

The body is the bilayer of :func:`geometries.bilayer`: X1 along the length, X3 vertical (the
paper's e2), X2 out of plane (the paper's e3, held: plane strain); a cortex of thickness ``t``
on top of a substrate, the bottom X3 = 0 on rollers (u3 = 0), the ends X1 = 0 and X1 = L on
rollers (u1 = 0). Both layers are compressible neo-Hookean (eq. 36),

    Psi(Fe) = mu/2 (tr Fe^T Fe - 3 - 2 ln Je) + lam/2 ln^2 Je,    P = Jg dPsi/dFe Fg^-T,

and the cortex grows along e1, Fg = I + (theta - 1) e1 (x) e1 (eq. 23).

**Homogeneous state.** The ends hold the length, so the substrate stays undeformed (F = I,
stress-free) and the cortex is F = diag(1, 1, lambda3) with lambda3 from a traction-free top,
P33 = 0 (:func:`prebuckled_cortex`).

**Incremental problem.** A perturbation u1 = U1(X3) sin(k X1), u3 = U3(X3) cos(k X1) satisfies
both roller ends exactly for k = n pi / L. With the moduli A_iJkL = dP_iJ/dF_kL of each layer
(constant in it), equilibrium Div(A : Grad u) = 0 becomes z' = K z for the Stroh vector
z = (U1, U3, T1, T3) of displacements and tractions on X3 = const (:func:`stroh_matrix`). The
rollers at the bottom leave z(0) = (a, 0, 0, b); the transfer matrices exp(K h) of substrate
and cortex carry it to the top, which must be traction-free: a non-trivial (a, b) exists where
the 2 x 2 determinant :func:`determinant` vanishes. The smallest growth at which it vanishes,
over the admissible k, is the onset (:func:`onset`); the wavelength is 2 pi / k.

The moduli are computed by complex-step differentiation of P (exact to round-off), the roots
in theta by bracketing and Brent's method.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm
from scipy.optimize import brentq

from ngincompat.errors import require

#: In-plane indices of the 3-D tensors: X1 (along the length) and X3 (vertical).
_X, _Y = 0, 2
_STEP = 1e-30  # complex step


def nominal_stress(F: np.ndarray, Fg: np.ndarray, mu: float, lam: float) -> np.ndarray:
    """First Piola-Kirchhoff stress P = Jg P^e(Fe) Fg^-T of the neo-Hookean energy (eq. 36).

    Works on complex arrays (for the complex-step moduli).
    """
    Fe = F @ np.linalg.inv(Fg)
    Je = np.linalg.det(Fe)
    FeinvT = np.linalg.inv(Fe).T
    Pe = mu * (Fe - FeinvT) + lam * np.log(Je) * FeinvT
    return np.linalg.det(Fg) * Pe @ np.linalg.inv(Fg).T


def moduli(F: np.ndarray, Fg: np.ndarray, mu: float, lam: float) -> np.ndarray:
    """A[i, J, k, L] = dP_iJ / dF_kL at F (complex step: exact to round-off)."""
    A = np.empty((3, 3, 3, 3))
    for k in range(3):
        for L in range(3):
            dF = np.zeros((3, 3), complex)
            dF[k, L] = 1j * _STEP
            A[:, :, k, L] = nominal_stress(F + dF, Fg, mu, lam).imag / _STEP
    return A


@dataclass(frozen=True)
class Prebuckled:
    """The homogeneous state of the grown cortex: F = diag(1, 1, lambda3).

    Attributes
    ----------
    lambda3 : float
        Vertical stretch (the top rises by t (lambda3 - 1)).
    sigma11, sigma22 : float
        Cauchy stress along the length and out of plane (sigma33 = 0).
    """

    lambda3: float
    sigma11: float
    sigma22: float


def growth_tensor(theta: float) -> np.ndarray:
    """Fg = I + (theta - 1) e1 (x) e1 (eq. 23 with f0 = e1)."""
    return np.diag([theta, 1.0, 1.0])


def prebuckled_cortex(theta: float, mu: float, lam: float) -> Prebuckled:
    """The cortex grown by ``theta`` along e1 between fixed ends, traction-free on top."""
    Fg = growth_tensor(theta)

    def p33(stretch: float) -> float:
        return nominal_stress(np.diag([1.0, 1.0, stretch]), Fg, mu, lam)[2, 2]

    stretch = brentq(p33, 0.2, 5.0, xtol=1e-15, rtol=1e-15)
    F = np.diag([1.0, 1.0, stretch])
    sigma = nominal_stress(F, Fg, mu, lam) @ F.T / np.linalg.det(F)
    return Prebuckled(stretch, sigma[0, 0], sigma[1, 1])


def stroh_matrix(A: np.ndarray, k: float) -> np.ndarray:
    """K with z' = K z for z = (U1, U3, T1, T3) (see the module docstring).

    With x = X1 and y = X3, the tractions on X3 = const are T1 sin(k X1) and T3 cos(k X1),
    T1 = A_xyxy U1' - k A_xyyx U3 and T3 = k A_yyxx U1 + A_yyyy U3'; equilibrium gives
    T1' = k^2 A_xxxx U1 + k A_xxyy U3' and T3' = k^2 A_yxyx U3 - k A_yxxy U1'. The moduli of
    a diagonal state of an isotropic material with a diagonal Fg couple nothing else.
    """
    x, y = _X, _Y
    a_xxxx, a_yyyy = A[x, x, x, x], A[y, y, y, y]
    a_xyxy, a_yxyx = A[x, y, x, y], A[y, x, y, x]
    a_xxyy, a_xyyx = A[x, x, y, y], A[x, y, y, x]
    dU1 = np.array([0.0, k * a_xyyx, 1.0, 0.0]) / a_xyxy
    dU3 = np.array([-k * a_xxyy, 0.0, 0.0, 1.0]) / a_yyyy
    dT1 = k * k * a_xxxx * np.eye(4)[0] + k * a_xxyy * dU3
    dT3 = k * k * a_yxyx * np.eye(4)[1] - k * a_xyyx * dU1
    return np.array([dU1, dU3, dT1, dT3])


@dataclass(frozen=True)
class Bilayer:
    """Geometry (cm) and materials of the bifurcation problem.

    Attributes
    ----------
    height, cortex : float
        Total height and cortical thickness.
    mu_cortex, lam_cortex, mu_sub, lam_sub : float
        Lame parameters of cortex and substrate.
    """

    height: float
    cortex: float
    mu_cortex: float
    lam_cortex: float
    mu_sub: float
    lam_sub: float

    def __post_init__(self) -> None:
        require(self.height > 0, "height", self.height, "> 0")
        require(0 < self.cortex <= self.height, "cortex", self.cortex,
                f"in (0, height = {self.height:g}]")
        for name in ("mu_cortex", "mu_sub"):
            require(getattr(self, name) > 0, name, getattr(self, name), "> 0")
        for mu, name in ((self.mu_cortex, "lam_cortex"), (self.mu_sub, "lam_sub")):
            require(getattr(self, name) > -2 * mu / 3, name, getattr(self, name),
                    "> -2 mu / 3")

    @functools.lru_cache(maxsize=4096)  # noqa: B019 - frozen, few instances, pure
    def cortex_moduli(self, theta: float) -> np.ndarray:
        """Moduli of the cortex in its homogeneous state at growth theta."""
        state = prebuckled_cortex(theta, self.mu_cortex, self.lam_cortex)
        F = np.diag([1.0, 1.0, state.lambda3])
        return moduli(F, growth_tensor(theta), self.mu_cortex, self.lam_cortex)

    @functools.lru_cache(maxsize=1024)  # noqa: B019 - frozen, few instances, pure
    def substrate_basis(self, k: float) -> tuple[np.ndarray, float]:
        """The two solutions that satisfy the rollers at the bottom, carried to the
        interface: an orthonormal 4 x 2 basis and the sign that keeps the determinant's."""
        Z = np.eye(4)[:, [0, 3]]  # the rollers: z(0) = a e_U1 + b e_T3
        depth = self.height - self.cortex
        if depth == 0:
            return Z, 1.0
        A = moduli(np.eye(3), np.eye(3), self.mu_sub, self.lam_sub)
        return _propagate(stroh_matrix(A, k), depth, Z)


#: Depth, in e-foldings of the gap between the growing and the decaying solutions, past which
#: a layer is carried no further (:func:`_propagate`): e^-40, below double precision.
SATURATION = 40.0


def _propagate(K: np.ndarray, h: float, Z: np.ndarray) -> tuple[np.ndarray, float]:
    """exp(K h) Z in sub-steps with orthonormalisation after each (the growing solutions would
    otherwise swamp each other); returns the basis and the sign of the determinant of the
    discarded triangular factors, so that det(top rows) keeps the sign of the exact one.

    A layer deeper than :data:`SATURATION` / gap (gap: the real parts' distance from the two
    decaying solutions to the two growing ones, 2k in the unstressed substrate) is carried
    over that depth only: there exp(K h') Z = Q' R' spans the growing solutions' invariant
    subspace to machine precision, and the rest of the layer maps it to itself by
    Q' M with det M > 0 (M is an exponential), which changes neither the span nor the sign
    of det(top rows) det(R). The cost of a short wavelength in a thick layer (k h in the
    thousands) is then that of a few wavelengths' depth.
    """
    rates = np.sort(np.linalg.eigvals(K).real)
    gap = rates[2] - rates[1]
    if gap > 0:
        h = min(h, SATURATION / gap)
    steps = max(1, int(np.ceil(max(abs(rates[0]), abs(rates[-1])) * h)))
    transfer = expm(K * (h / steps))
    sign = 1.0
    for _ in range(steps):
        Z, R = np.linalg.qr(transfer @ Z)
        sign *= np.sign(np.linalg.det(R))
    return Z, sign


def determinant(bilayer: Bilayer, k: float, theta: float) -> float:
    """A function of (k, theta) with the sign of the 2 x 2 determinant of the tractions at
    the top and the same zeros: the mode k bifurcates where it vanishes."""
    Z, sign = bilayer.substrate_basis(k)
    Z, sign_cortex = _propagate(stroh_matrix(bilayer.cortex_moduli(theta), k),
                                bilayer.cortex, Z)
    return sign * sign_cortex * np.linalg.det(Z[2:, :])


def critical_growth(bilayer: Bilayer, k: float, theta_min: float = 1.0, theta_max: float = 3.0,
                    resolution: float = 0.005) -> float:
    """The smallest theta in (theta_min, theta_max] at which wavenumber k bifurcates, or inf.

    theta is scanned in steps of ``resolution`` for a sign change of :func:`determinant`,
    then refined by Brent's method to 1e-12.
    """
    require(k > 0, "k", k, "> 0 (wavenumber, 1/cm)")
    return _first_roots(bilayer, [k], theta_min, theta_max, resolution)[0]


def _first_roots(bilayer: Bilayer, ks: list[float], theta_min: float, theta_max: float,
                 resolution: float, first_only: bool = False) -> np.ndarray:
    """The first root in theta of every k (inf where there is none); with ``first_only``
    the scan stops at the first theta interval where any k has one (the others are inf)."""
    thetas = np.arange(theta_min, theta_max + resolution / 2, resolution)
    if thetas[0] == 1.0:
        thetas[0] = 1.0 + resolution / 10  # theta = 1 is the unstressed state
    roots = np.full(len(ks), np.inf)
    previous = np.array([determinant(bilayer, k, thetas[0]) for k in ks])
    for lo, hi in zip(thetas[:-1], thetas[1:], strict=True):
        pending = np.isinf(roots)
        if not pending.any():
            break
        values = np.array([determinant(bilayer, k, hi) if todo else 0.0
                           for k, todo in zip(ks, pending, strict=True)])
        for i in np.flatnonzero(pending & (np.sign(values) != np.sign(previous))):
            roots[i] = brentq(lambda t, k=ks[i]: determinant(bilayer, k, t), lo, hi,
                              xtol=1e-12)
        if first_only and np.isfinite(roots).any():
            break
        previous = values
    return roots


@dataclass(frozen=True)
class Onset:
    """The first bifurcation of the bilayer.

    Attributes
    ----------
    growth : float
        Cortical growth theta at the onset.
    wavelength : float
        2 pi / k of the critical mode (reference length, cm).
    mode : int or None
        n of k = n pi / L for a finite length, None for a continuous k.
    """

    growth: float
    wavelength: float
    mode: int | None


def onset(bilayer: Bilayer, length: float | None = None, modes: Sequence[int] = range(1, 81),
          k_range: tuple[float, float] | None = None, theta_max: float = 3.0,
          resolution: float = 0.005) -> Onset:
    """The onset: the smallest critical growth over the admissible wavenumbers.

    With ``length`` the ends are rollers and k = n pi / length for n in ``modes``; without,
    k is continuous in ``k_range`` = (k_min, k_max) (an unbounded layer): 40 log-spaced
    wavenumbers bracket the critical one, a golden-section search refines it.
    """
    if length is not None:
        require(length > 0, "length", length, "> 0")
        modes = list(modes)
        ks = [n * np.pi / length for n in modes]
    else:
        require(k_range is not None, "k_range", k_range, "(k_min, k_max) without a length")
        ks = list(np.geomspace(k_range[0], k_range[1], 40))  # type: ignore[index]  # required
    roots = _first_roots(bilayer, ks, 1.0, theta_max, resolution, first_only=True)
    i = int(np.argmin(roots))
    if not np.isfinite(roots[i]):
        raise ValueError(f"no bifurcation up to theta = {theta_max:g}")
    if length is not None:
        return Onset(roots[i], 2 * np.pi / ks[i], modes[i])
    start = roots[i] - resolution

    def theta_c(k: float) -> float:
        return critical_growth(bilayer, k, start, theta_max, resolution)

    a, b = ks[max(i - 1, 0)], ks[min(i + 1, len(ks) - 1)]
    golden = (np.sqrt(5) - 1) / 2
    while b - a > 1e-4 * b:
        c, d = b - golden * (b - a), a + golden * (b - a)
        if theta_c(c) < theta_c(d):
            b = d
        else:
            a = c
    k = (a + b) / 2
    return Onset(theta_c(k), 2 * np.pi / k, None)


def thin_film(mu_film: float, mu_sub: float, thickness: float) -> tuple[float, float]:
    """The classical thin-film estimate for an incompressible stiff film on a half-space:
    critical compressive strain (1/4) (3 mu_s / mu_f)^(2/3) and wavelength
    2 pi t (mu_f / (3 mu_s))^(1/3); as growth, theta = 1 / (1 - strain)."""
    strain = 0.25 * (3 * mu_sub / mu_film) ** (2 / 3)
    return 1 / (1 - strain), 2 * np.pi * thickness * (mu_film / (3 * mu_sub)) ** (1 / 3)
