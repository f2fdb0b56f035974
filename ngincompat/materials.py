"""Hyperelastic materials: compressible neo-Hookean (eq. 36) and Gasser-Ogden-Holzapfel (eq. 39).

A material is a frozen dataclass of its parameters, validated on construction. ``energy(Fe,
fibers)`` is the strain energy density Psi per unit volume of the intermediate (grown)
configuration; the mechanics problem integrates ``Jg * Psi(Fe)`` over the reference body.
Units are those of the parameters (the paper's idealized scenes use MPa and mm).
"""

from dataclasses import dataclass

import ngsolve as ngs

from .errors import ParameterError, require


def lame_lambda(mu, nu):
    """Lame's first parameter from the shear modulus and Poisson's ratio, 2 mu nu / (1 - 2 nu)."""
    require(-1.0 < nu < 0.5, "nu", nu, "in (-1, 0.5)")
    return 2.0 * mu * nu / (1.0 - 2.0 * nu)


def _check_lame(mu, lam):
    require(mu > 0, "mu", mu, "> 0 (shear modulus)")
    require(lam > -2.0 * mu / 3.0, "lambda", lam, "> -2 mu / 3 (positive bulk modulus)")


@dataclass(frozen=True)
class NeoHookean:
    """Compressible neo-Hookean material, eq. (36).

    Parameters
    ----------
    mu : float
        Shear modulus, > 0.
    lam : float
        Lame's first parameter, > -2 mu / 3.

    Notes
    -----
    Psi = mu/2 (I1e - 3 - 2 ln Je) + lam/2 ln^2 Je, with I1e = tr Ce (eq. 36); its second
    Piola-Kirchhoff stress is eq. (37). The energy is +inf (NaN in floating point) for Je <= 0.
    """

    mu: float
    lam: float
    name = "neo-hookean"
    needs_fibers = False

    def __post_init__(self):
        _check_lame(self.mu, self.lam)

    @classmethod
    def from_nu(cls, mu, nu):
        """From the shear modulus and Poisson's ratio nu in (-1, 0.5)."""
        require(mu > 0, "mu", mu, "> 0 (shear modulus)")
        return cls(mu, lame_lambda(mu, nu))

    @classmethod
    def paper_idealized(cls):
        """mu = 0.55 MPa, nu = 0.4: the cube, hemisphere and cylinder of sections 3.1-3.4."""
        return cls.from_nu(0.55, 0.4)

    def energy(self, Fe, fibers=()):
        rest, lnJ = self.bulk_split(Fe)
        return rest + self.lam / 2 * lnJ * lnJ

    def bulk_split(self, Fe):
        """(Psi - lam/2 g^2, g) with g = ln Je: the energy without its bulk term and the
        volume measure whose square the bulk term penalises (used by the mixed formulation)."""
        lnJ = ngs.log(ngs.Det(Fe))
        return self.mu / 2 * (ngs.Trace(Fe.trans * Fe) - 3 - 2 * lnJ), lnJ


@dataclass(frozen=True)
class GOH:
    """Gasser-Ogden-Holzapfel material with dispersed fiber families, eq. (39).

    Parameters
    ----------
    mu : float
        Shear modulus of the ground matrix, > 0.
    lam : float
        Bulk parameter of the volumetric term, > 0.
    k1 : float
        Fiber stiffness, >= 0 (same unit as mu).
    k2 : float
        Dimensionless fiber nonlinearity, > 0.
    kappa : float
        Fiber dispersion in [0, 1/3]: 0 perfectly aligned, 1/3 isotropic.

    Notes
    -----
    Psi = mu/2 (I1bar - 3) + sum_a k1/(2 k2) (exp(k2 <E_a>^2) - 1) + lam/2 ((Je^2 - 1)/2 - ln Je)
    with I1bar = Je^(-2/3) tr Ce, E_a = Cbar : H_a - 1, H_a = kappa I + (1 - 3 kappa) a_a (x) a_a
    and <.> the Macaulay bracket (fibers carry no load in compression). The fiber directions
    a_a are unit vectors in the intermediate configuration, a_a = Fg a0 / |Fg a0| (eq. 39); the
    mechanics problem pushes them forward and passes them as ``fibers``.
    """

    mu: float
    lam: float
    k1: float
    k2: float
    kappa: float
    name = "goh"
    needs_fibers = True

    def __post_init__(self):
        require(self.mu > 0, "mu", self.mu, "> 0 (shear modulus)")
        require(self.lam > 0, "lambda", self.lam, "> 0 (bulk parameter)")
        require(self.k1 >= 0, "k1", self.k1, ">= 0 (fiber stiffness)")
        require(self.k2 > 0, "k2", self.k2, "> 0 (fiber nonlinearity)")
        require(0.0 <= self.kappa <= 1.0 / 3.0, "kappa", self.kappa, "in [0, 1/3]")

    @classmethod
    def from_nu(cls, mu, nu, k1, k2, kappa):
        """With lam from Poisson's ratio of the ground matrix, nu in (0, 0.5)."""
        require(0.0 < nu < 0.5, "nu", nu, "in (0, 0.5) for GOH")
        require(mu > 0, "mu", mu, "> 0 (shear modulus)")
        return cls(mu, lame_lambda(mu, nu), k1, k2, kappa)

    def energy(self, Fe, fibers=()):
        C = Fe.trans * Fe
        J = ngs.Det(Fe)
        Jm23 = J ** (-2.0 / 3.0)
        I1bar = Jm23 * ngs.Trace(C)
        psi = self.mu / 2 * (I1bar - 3) + self.lam / 2 * ((J * J - 1) / 2 - ngs.log(J))
        if self.k1 == 0:
            return psi
        for a in fibers:
            E = self.kappa * I1bar + (1 - 3 * self.kappa) * Jm23 * ngs.InnerProduct(a, C * a) - 1
            Ep = ngs.IfPos(E, E, 0)
            psi = psi + self.k1 / (2 * self.k2) * (ngs.exp(self.k2 * Ep * Ep) - 1)
        return psi


MATERIALS = ("neo-hookean", "goh")


def make_material(name, mu, nu, k1=0.0, k2=1.0, kappa=0.0):
    """A material by name from mu, Poisson's ratio nu and, for GOH, the fiber parameters
    (ignored by the neo-Hookean material)."""
    if name == "goh":
        return GOH.from_nu(mu, nu, k1, k2, kappa)
    if name == "neo-hookean":
        return NeoHookean.from_nu(mu, nu)
    raise ParameterError(f"material = {name!r} is unknown: allowed {', '.join(MATERIALS)}")
