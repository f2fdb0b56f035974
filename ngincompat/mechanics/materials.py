"""Hyperelastic materials: compressible neo-Hookean (eq. 36) and Gasser-Ogden-Holzapfel (eq. 39).

A material is anything with the shape of :class:`Material`: ``energy(Fe, fibers)`` is the
strain energy density Psi per unit volume of the intermediate (grown) configuration; the
mechanics problem integrates ``Jg * Psi(Fe)`` over the reference body. A material whose energy
has a bulk term lam/2 g(Je)^2 that it can split off (:class:`MixedMaterial`) also works in the
mixed formulation. Units are those of the parameters (the paper's idealized scenes use MPa and
mm).

The materials here are frozen dataclasses of their parameters, validated on construction.
Each subclasses :class:`MaterialKind` and names itself in the class attribute ``name``;
defining the class registers it, so :func:`make_material` finds it by that name from the
uniform parameters (mu, nu, k1, k2, kappa) of its classmethod ``from_parameters``.
"""

import dataclasses
from collections.abc import KeysView, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, Self, TypeAlias, runtime_checkable

import ngsolve as ngs

from ngincompat.errors import ParameterError, require
from ngincompat.mechanics import kinematics
from ngincompat.mechanics.fields import DirectionField
from ngincompat.mechanics.growth import GrowthModel

CF: TypeAlias = ngs.CoefficientFunction


@runtime_checkable
class Material(Protocol):
    """What the mechanics problem uses of a material."""

    @property
    def name(self) -> str:
        """A label for results and error messages."""

    @property
    def needs_fibers(self) -> bool:
        """Whether ``energy`` needs fiber directions (then the problem requires some)."""

    def energy(self, Fe: CF, fibers: Sequence[CF] = ()) -> CF:
        """Psi(Fe) per unit intermediate volume; ``fibers`` are unit fiber directions in the
        intermediate configuration (eq. 39)."""


@runtime_checkable
class MixedMaterial(Material, Protocol):
    """A material whose energy is Psi = rest + lam/2 g(Je)^2, usable in the mixed
    formulation (:class:`~ngincompat.fem.problem.GrowthMechanics`)."""

    @property
    def lam(self) -> float:
        """The bulk parameter of the term lam/2 g^2."""

    def bulk_split(self, Fe: CF) -> tuple[CF, CF]:
        """(Psi - lam/2 g^2, g): the energy without its bulk term and the volume measure g."""


#: The registered materials, name -> class, in the order of their definition.
_MATERIALS: dict[str, type["MaterialKind"]] = {}

#: The names of the registered materials: a live view, so materials defined later appear too.
MATERIALS: KeysView[str] = _MATERIALS.keys()


class MaterialKind:
    """Base of the materials built by name, registered when defined.

    A subclass that sets the class attribute ``name`` is registered under it; it must
    provide ``energy(Fe, fibers)`` (see :class:`Material`) and the classmethod
    ``from_parameters(mu, nu, k1=0.0, k2=1.0, kappa=0.0)`` that builds it from the shear
    modulus, Poisson's ratio and the fiber parameters (ignoring those it has no use for);
    its instances keep the shear modulus ``mu`` and Lame's ``lam`` (the scale of its
    stresses, and the moduli of the closed forms a scene checks against).

    Attributes
    ----------
    name : str
        The registry name (class attribute).
    needs_fibers : bool
        Whether the energy needs fiber directions (class attribute, default False).
    """

    name: ClassVar[str]
    needs_fibers: ClassVar[bool] = False

    if TYPE_CHECKING:   # what :meth:`__init_subclass__` requires of a registered material
        mu: float
        lam: float

        @classmethod
        def from_parameters(cls, mu: float, nu: float, k1: float = 0.0, k2: float = 1.0,
                            kappa: float = 0.0) -> Self: ...

        def energy(self, Fe: CF, fibers: Sequence[CF] = ()) -> CF: ...

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("name")
        if name is None:
            return
        missing = [m for m in ("energy", "from_parameters") if not hasattr(cls, m)]
        if missing:
            raise TypeError(f"material {name!r} ({cls.__qualname__}) lacks {', '.join(missing)}")
        if name in _MATERIALS:
            raise TypeError(f"material {name!r} is already registered by "
                            f"{_MATERIALS[name].__qualname__}")
        _MATERIALS[name] = cls


def material_kind(name: str) -> type[MaterialKind]:
    """The registered material called ``name``.

    Raises
    ------
    ParameterError
        If no material of that name is registered; the message lists those that are.
    """
    try:
        return _MATERIALS[name]
    except KeyError:
        raise ParameterError(
            f"material = {name!r} is unknown: allowed {', '.join(_MATERIALS)}") from None


def lame_lambda(mu: float, nu: float) -> float:
    """Lame's first parameter from the shear modulus and Poisson's ratio, 2 mu nu / (1 - 2 nu)."""
    require(-1.0 < nu < 0.5, "nu", nu, "in (-1, 0.5)")
    return 2.0 * mu * nu / (1.0 - 2.0 * nu)


def _check_lame(mu: float, lam: float) -> None:
    require(mu > 0, "mu", mu, "> 0 (shear modulus)")
    require(lam > -2.0 * mu / 3.0, "lambda", lam, "> -2 mu / 3 (positive bulk modulus)")


@dataclass(frozen=True)
class NeoHookean(MaterialKind):
    """Compressible neo-Hookean material, eq. (36).

    Parameters
    ----------
    mu : float or CoefficientFunction
        Shear modulus, > 0; a CoefficientFunction for moduli per region (:meth:`by_region`).
    lam : float or CoefficientFunction
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

    def __post_init__(self) -> None:
        # moduli per region are checked by by_region
        if not isinstance(self.mu, ngs.CoefficientFunction):
            _check_lame(self.mu, self.lam)

    @classmethod
    def from_nu(cls, mu: float, nu: float) -> Self:
        """From the shear modulus and Poisson's ratio nu in (-1, 0.5)."""
        require(mu > 0, "mu", mu, "> 0 (shear modulus)")
        return cls(mu, lame_lambda(mu, nu))

    @classmethod
    def by_region(cls, mesh: ngs.Mesh, moduli: dict[str, tuple[float, float]]) -> Self:
        """One neo-Hookean material with moduli per mesh region (material name), given as
        region -> (mu, nu); mu and lam become piecewise constant CoefficientFunctions (the
        energy is linear in both)."""
        parts = {region: cls.from_nu(mu, nu) for region, (mu, nu) in moduli.items()}
        return cls(mesh.MaterialCF({r: m.mu for r, m in parts.items()}),
                   mesh.MaterialCF({r: m.lam for r, m in parts.items()}))

    @classmethod
    def from_parameters(cls, mu: float, nu: float, k1: float = 0.0, k2: float = 1.0,
                        kappa: float = 0.0) -> Self:
        """The registry's uniform constructor: :meth:`from_nu`; the fiber parameters k1, k2
        and kappa are ignored."""
        return cls.from_nu(mu, nu)

    @classmethod
    def paper_idealized(cls) -> Self:
        """mu = 0.55 MPa, nu = 0.4: the cube, hemisphere and cylinder of sections 3.1-3.4."""
        return cls.from_nu(0.55, 0.4)

    def energy(self, Fe: CF, fibers: Sequence[CF] = ()) -> CF:
        """Psi of eq. (36); needs no fibers."""
        rest, lnJ = self.bulk_split(Fe)
        return rest + self.lam / 2 * lnJ * lnJ

    def bulk_split(self, Fe: CF) -> tuple[CF, CF]:
        """(Psi - lam/2 g^2, g) with g = ln Je: the energy without its bulk term and the
        volume measure whose square the bulk term penalises (used by the mixed formulation)."""
        lnJ = ngs.log(ngs.Det(Fe))
        return self.mu / 2 * (ngs.Trace(Fe.trans * Fe) - 3 - 2 * lnJ), lnJ


@dataclass(frozen=True)
class GOH(MaterialKind):
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

    def __post_init__(self) -> None:
        require(self.mu > 0, "mu", self.mu, "> 0 (shear modulus)")
        require(self.lam > 0, "lambda", self.lam, "> 0 (bulk parameter)")
        require(self.k1 >= 0, "k1", self.k1, ">= 0 (fiber stiffness)")
        require(self.k2 > 0, "k2", self.k2, "> 0 (fiber nonlinearity)")
        require(0.0 <= self.kappa <= 1.0 / 3.0, "kappa", self.kappa, "in [0, 1/3]")

    @classmethod
    def from_nu(cls, mu: float, nu: float, k1: float, k2: float, kappa: float) -> Self:
        """With lam from Poisson's ratio of the ground matrix, nu in (0, 0.5)."""
        require(0.0 < nu < 0.5, "nu", nu, "in (0, 0.5) for GOH")
        require(mu > 0, "mu", mu, "> 0 (shear modulus)")
        return cls(mu, lame_lambda(mu, nu), k1, k2, kappa)

    @classmethod
    def from_parameters(cls, mu: float, nu: float, k1: float = 0.0, k2: float = 1.0,
                        kappa: float = 0.0) -> Self:
        """The registry's uniform constructor: :meth:`from_nu`."""
        return cls.from_nu(mu, nu, k1, k2, kappa)

    def energy(self, Fe: CF, fibers: Sequence[CF] = ()) -> CF:
        """Psi of eq. (39) with one term per fiber direction in ``fibers``."""
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


def intermediate_fibers(Fg: CF, fibers: Sequence[DirectionField]) -> tuple[CF, ...]:
    """Fiber directions pushed to the intermediate configuration, Fg a0 / |Fg a0| (eq. 39),
    for the direction fields ``fibers`` (:class:`~ngincompat.mechanics.fields.DirectionField`)."""
    pushed = []
    for f in fibers:
        a = Fg * f.cf
        pushed.append(a / ngs.Norm(a))
    return tuple(pushed)


def grown_energy_density(F: CF, growth: GrowthModel, material: Material,
                         fibers: Sequence[DirectionField] = ()) -> CF:
    """The strain energy per reference volume of a grown body, Jg Psi(Fe) with Fe = F Fg^-1
    (eq. 1, 30), the fibers pushed to the intermediate configuration (eq. 39); ``growth`` has
    ``Fg`` and ``Jg`` (:mod:`ngincompat.mechanics.growth`)."""
    Fe = kinematics.elastic_part(F, growth.Fg)
    return growth.Jg * material.energy(Fe, intermediate_fibers(growth.Fg, fibers))


def make_material(name: str, mu: float, nu: float, k1: float = 0.0, k2: float = 1.0,
                  kappa: float = 0.0) -> MaterialKind:
    """A registered material by name (:data:`MATERIALS`) from mu, Poisson's ratio nu and, for
    GOH, the fiber parameters (ignored by the neo-Hookean material).

    Raises
    ------
    ParameterError
        For an unknown name (listing the registered ones) or parameters out of range.
    """
    return material_kind(name).from_parameters(mu, nu, k1, k2, kappa)


@dataclass(frozen=True, eq=False)
class Regional:
    """One material kind whose parameters differ between regions of the mesh (a stiff
    cortex on a soft subcortex).

    Parameters
    ----------
    mesh : ngsolve.Mesh
        The mesh whose materials (regions) are keys of ``materials``.
    materials : dict
        Region name -> a material (validated dataclass, e.g. :class:`NeoHookean`), all of
        one class; every region of the mesh needs one.

    Notes
    -----
    Psi(Fe) = Psi(Fe; p_r) in region r: the energy of the common class with each parameter
    a domain-wise CoefficientFunction p(X) = p_r. (A domain-wise energy, one expression per
    region, gives the same values but its tangent assembled three times slower.)
    """

    mesh: ngs.Mesh
    materials: dict
    name = "regional"

    def __post_init__(self) -> None:
        regions = set(self.mesh.GetMaterials())
        require(set(self.materials) == regions, "materials", sorted(self.materials),
                f"one material for each region: {', '.join(sorted(regions))}")
        kinds = {type(m) for m in self.materials.values()}
        require(len(kinds) == 1, "materials", sorted(k.__name__ for k in kinds),
                "materials of one class")

    @property
    def needs_fibers(self) -> bool:
        return any(m.needs_fibers for m in self.materials.values())

    def energy(self, Fe: CF, fibers: Sequence[CF] = ()) -> CF:
        """Psi of the common material class with domain-wise parameters."""
        kind = type(next(iter(self.materials.values())))
        # every region's parameters were validated when its material was made
        material = object.__new__(kind)
        for f in dataclasses.fields(kind):
            values = {r: getattr(m, f.name) for r, m in self.materials.items()}
            object.__setattr__(material, f.name, self.mesh.MaterialCF(values))
        return material.energy(Fe, fibers)
