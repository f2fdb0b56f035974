"""The material parameters the scenes share, declared once.

:class:`Elastic` (mu, nu) and :class:`Fibers` (the GOH fiber parameters k1, k2, kappa) are
blocks of fields a scene inherits; their defaults are the paper's idealized material
(mu = 0.55 MPa, nu = 0.4, sections 3.1-3.4, and the skin of 3.6). A scene with other values
calls the same declaration with its own default, ``mu: float = MU(0.003)``, so help, unit and
range stay
those written here; a scene with moduli per tissue declares those itself, with ``NU`` for
their Poisson's ratio.

The ranges are those of every material (:mod:`ngincompat.mechanics.materials`); a material
that allows less (GOH: nu in (0, 0.5)) says so when the scene builds it in ``__post_init__``.
"""

from dataclasses import dataclass

from ngincompat.scenes.base import MODULUS_FLOOR, Param

#: Moduli are at most 1e6 in a scene's stress unit: past every soft tissue (kPa to MPa) and,
#: in MPa, past the shear modulus of diamond (about 5e5 MPa).
MU = Param("shear modulus", "stress", range=f"[{MODULUS_FLOOR:g}, 1e6]")
#: Poisson's ratio down to -0.99: nearer -1 the bulk modulus is below 1/450 of the shear
#: modulus, a body that changes volume for nothing (the cube at -0.999 did not converge),
#: and no tissue is that auxetic. Up to 0.5: nearly incompressible tissue takes the mixed
#: formulation (:data:`~ngincompat.fem.problem.DISPLACEMENT_NU_MAX`).
NU = Param("Poisson's ratio", range="[-0.99, 0.5)")
K1 = Param("GOH fiber stiffness", "stress", range="[0, 1e6]")
K2 = Param("GOH fiber nonlinearity (the fiber energy grows as exp(k2 (I4 - 1)^2): at k2 = "
           "100 it overflows at a fiber stretch of 1.9; at least 1e-3: a fiber that stiffens "
           "by 0.1 % at a stretch of 2 does not stiffen)", range="[1e-3, 100]")
KAPPA = Param("GOH fiber dispersion (0: aligned, 1/3: isotropic)", range="[0, 1/3]")


@dataclass(frozen=True)
class Elastic:
    """Shear modulus and Poisson's ratio of the scene's material (of the ground matrix for
    GOH)."""

    mu: float = MU(0.55)
    nu: float = NU(0.4)


@dataclass(frozen=True)
class Fibers:
    """The GOH fiber parameters (eq. 39), used when the scene's material is GOH."""

    k1: float = K1(1.0)
    k2: float = K2(1.0)
    kappa: float = KAPPA(0.0)
