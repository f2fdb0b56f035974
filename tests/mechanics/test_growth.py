"""Growth tensors (eq. 13, 18, 23), their stretch measures and closed forms, the registry of
growth kinds and the positivity check of theta."""

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from geometries import cube
from ngincompat.errors import ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.stepping import solve_coupled, solve_growth
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics import fields
from ngincompat.mechanics import growth as growth_module
from ngincompat.mechanics.growth import (
    KINDS,
    AreaGrowth,
    FiberGrowth,
    GrowthKind,
    GrowthModel,
    IsotropicGrowth,
    TensorGrowth,
    check_positive,
    growth_kind,
    make_growth,
)
from ngincompat.mechanics.laws import StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean

THETA = 1 + 0.5 * ngs.x + 0.2 * ngs.y


@pytest.mark.parametrize("growth", [
    IsotropicGrowth(THETA),
    AreaGrowth(THETA, fields.constant((1.0, 1.0, 0.0))),
    FiberGrowth(THETA, fields.constant((0.0, 2.0, 1.0))),
])
def test_volume_change_is_theta(growth, unit_cube_hex):
    """det Fg = theta for each of the three kinds (section 2.3)."""
    pts = random_points(10)
    np.testing.assert_allclose(values_at(ngs.Det(growth.Fg), unit_cube_hex, pts),
                               values_at(growth.theta, unit_cube_hex, pts), rtol=1e-13)


def test_growth_tensor_forms(unit_cube_hex):
    """Fg maps N0 to N0 for area growth (thickness unchanged), stretches f0 by theta for fiber
    growth and every direction by theta^(1/3) for isotropic growth."""
    pts = random_points(5)
    theta = values_at(THETA, unit_cube_hex, pts)[:, 0]
    n = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    area = AreaGrowth(THETA, fields.constant(n)).Fg
    np.testing.assert_allclose(values_at(area * ngs.CF(tuple(n)), unit_cube_hex, pts),
                               np.tile(n, (5, 1)), atol=1e-14)
    s = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    np.testing.assert_allclose(values_at(area * ngs.CF(tuple(s)), unit_cube_hex, pts),
                               np.sqrt(theta)[:, None] * s, rtol=1e-13)
    f = np.array([0.0, 2.0, 1.0]) / np.sqrt(5)
    fiber = FiberGrowth(THETA, fields.constant(f)).Fg
    np.testing.assert_allclose(values_at(fiber * ngs.CF(tuple(f)), unit_cube_hex, pts),
                               theta[:, None] * f, rtol=1e-13)
    iso = IsotropicGrowth(THETA).Fg
    np.testing.assert_allclose(values_at(iso, unit_cube_hex, pts),
                               np.cbrt(theta)[:, None] * np.eye(3).ravel(), rtol=1e-13)


def test_tensor_growth_takes_theta_from_the_determinant(unit_cube_hex):
    Fg = ngs.CF((1 + ngs.x, 0, 0, 0, 2, 0, 0, 0, 1), dims=(3, 3))
    growth = TensorGrowth(Fg)
    pts = random_points(5)
    np.testing.assert_allclose(values_at(growth.theta, unit_cube_hex, pts)[:, 0],
                               2 * (1 + pts[:, 0]), rtol=1e-14)
    with pytest.raises(ParameterError, match="3x3"):
        TensorGrowth(ngs.CF((1, 2, 3)))


def test_make_growth_by_name():
    assert make_growth("isotropic", THETA).kind == "isotropic"
    assert make_growth("area", THETA, fields.constant("e3")).kind == "area"
    with pytest.raises(ParameterError, match="growth = 'volume' is unknown"):
        make_growth("volume", THETA)
    with pytest.raises(ParameterError, match="needs a direction"):
        make_growth("fiber", THETA)


def test_registry_holds_the_three_kinds_and_names_them_in_errors():
    assert list(KINDS)[:3] == ["isotropic", "area", "fiber"]
    assert growth_kind("area") is AreaGrowth
    assert all(isinstance(make_growth(k, THETA, fields.constant("e2")), GrowthModel)
               for k in ("isotropic", "area", "fiber"))
    assert isinstance(TensorGrowth(ngs.Id(3)), GrowthModel)
    with pytest.raises(ParameterError, match="allowed isotropic, area, fiber"):
        growth_kind("volume")
    with pytest.raises(ParameterError, match=r"^area growth needs a direction \(N0\)$"):
        AreaGrowth.from_theta(THETA)
    with pytest.raises(ParameterError, match=r"^fiber growth needs a direction \(f0\)$"):
        FiberGrowth.from_theta(THETA)
    iso = IsotropicGrowth.from_theta(THETA, fields.constant("e1"))
    assert type(iso) is IsotropicGrowth and iso.theta is THETA
    fiber = FiberGrowth.from_theta(THETA, fields.constant("e1"))
    assert fiber.fiber.name == "e1"


#: A manufactured deformation gradient, far from the identity and with det F > 0 in the cube.
F_MANUFACTURED = ngs.CF((1.2 + 0.1 * ngs.y, 0.3 * ngs.z, 0.1,
                         -0.2 * ngs.x, 0.9, 0.25 * ngs.y,
                         0.05, 0.1 * ngs.x * ngs.z, 1.1 + 0.2 * ngs.x), dims=(3, 3))
OBLIQUE = (0.3, -0.5, 1.0)


@pytest.mark.parametrize("growth, measure", [
    (IsotropicGrowth(THETA), "volume"),
    (TensorGrowth(ngs.CF((1.2, 0.1, 0, 0, 0.9, 0, 0.3, 0, 1.1), dims=(3, 3))), "volume"),
    (AreaGrowth(THETA, fields.constant(OBLIQUE)), "area"),
    (AreaGrowth(THETA, fields.radial(center=(0.5, 0.5, -1.0))), "area"),
    (FiberGrowth(THETA, fields.constant(OBLIQUE)), "fiber"),
    (FiberGrowth(THETA, fields.circumferential(center=(0.5, 0.5, 0.0))), "fiber"),
], ids=["isotropic", "tensor", "area-oblique", "area-radial", "fiber-oblique", "fiber-circ"])
def test_stretch_is_the_total_stretch_of_section_2_6(growth, measure, unit_cube_hex):
    """stretch(F) at points against det F, det F |F^-T N0| (Nanson) and |F f0| in numpy."""
    pts = random_points(12, seed=3)
    F = values_at(F_MANUFACTURED, unit_cube_hex, pts).reshape(-1, 3, 3)
    J = np.linalg.det(F)
    if measure == "volume":
        expected = J
    else:
        d = values_at(growth.normal.cf if measure == "area" else growth.fiber.cf,
                      unit_cube_hex, pts)
        if measure == "area":
            FinvT_d = np.linalg.solve(np.swapaxes(F, 1, 2), d[..., None])[..., 0]
            expected = J * np.linalg.norm(FinvT_d, axis=1)
        else:
            expected = np.linalg.norm(np.einsum("nij,nj->ni", F, d), axis=1)
        assert np.max(np.abs(expected - J)) > 0.05      # not the volume stretch
    assert np.ptp(expected) > 0.02                       # varies in space
    np.testing.assert_allclose(values_at(growth.stretch(F_MANUFACTURED), unit_cube_hex, pts)[:, 0],
                               expected, rtol=1e-13)


@pytest.mark.parametrize("growth, formula, direction", [
    (IsotropicGrowth(THETA), inc.G_isotropic_closed_form, None),
    (AreaGrowth(THETA, fields.constant(OBLIQUE)), inc.G_area_closed_form, OBLIQUE),
    (AreaGrowth(THETA, fields.constant("e3")), inc.G_area_closed_form, (0, 0, 1.0)),
    (FiberGrowth(THETA, fields.constant(OBLIQUE)), inc.G_fiber_closed_form, OBLIQUE),
    (FiberGrowth(THETA, fields.constant("e1")), inc.G_fiber_closed_form, (1.0, 0, 0)),
], ids=["isotropic", "area-oblique", "area-e3", "fiber-oblique", "fiber-e1"])
def test_closed_form_G_is_the_formula_of_the_kind(growth, formula, direction, unit_cube_hex):
    """Eq. (16), (20), (25) with the unit direction and the symbolic gradient of theta; the
    growth model's closed_form_G gives the same."""
    args = (THETA, inc.grad_scalar(THETA))
    if direction is not None:
        args += (ngs.CF(tuple(np.asarray(direction) / np.linalg.norm(direction))),)
    pts = random_points(8, seed=4)
    expected = values_at(formula(*args), unit_cube_hex, pts)
    assert np.max(np.abs(expected)) > 1e-2
    np.testing.assert_allclose(values_at(growth.closed_form_G(), unit_cube_hex, pts), expected,
                               rtol=1e-13, atol=1e-15)


def test_no_closed_form_G_without_a_constant_direction():
    assert AreaGrowth(THETA, fields.radial()).closed_form_G() is None
    assert FiberGrowth(THETA, fields.circumferential()).closed_form_G() is None
    assert TensorGrowth(ngs.Id(3)).closed_form_G() is None


@pytest.fixture
def restore_kinds():
    """Removes the growth kinds a test registers, so the registry is the same afterwards."""
    saved = dict(growth_module._KINDS)
    yield
    growth_module._KINDS.clear()
    growth_module._KINDS.update(saved)


def _axial_kind():
    """A growth kind defined outside the package: growth along e1 alone, Fg = diag(theta, 1, 1),
    which is fiber growth with f0 = e1 written without a direction field."""

    @dataclass(frozen=True, eq=False)
    class AxialGrowth(GrowthKind):
        theta: ngs.CoefficientFunction
        kind = "axial-e1"

        @property
        def Fg(self):
            return ngs.CF((self.theta, 0, 0, 0, 1, 0, 0, 0, 1), dims=(3, 3))

        def stretch(self, F):
            return ngs.Norm(F[:, 0])

    return AxialGrowth


def test_a_new_kind_is_one_class_found_by_name(restore_kinds, unit_cube_hex):
    AxialGrowth = _axial_kind()
    assert "axial-e1" in KINDS
    growth = make_growth("axial-e1", THETA)
    assert type(growth) is AxialGrowth and isinstance(growth, GrowthModel)
    assert growth.closed_form_G() is None
    pts = random_points(5)
    np.testing.assert_allclose(values_at(growth.Jg, unit_cube_hex, pts),
                               values_at(ngs.Det(growth.Fg), unit_cube_hex, pts), rtol=1e-14)
    with pytest.raises(ParameterError, match="allowed isotropic, area, fiber, axial-e1"):
        make_growth("axial", THETA)


def test_registry_rejects_a_taken_name_and_an_incomplete_kind(restore_kinds):
    with pytest.raises(TypeError, match="'isotropic' is already registered by IsotropicGrowth"):
        class Again(IsotropicGrowth):
            kind = "isotropic"
    with pytest.raises(TypeError, match="lacks stretch"):
        class NoStretch(GrowthKind):
            kind = "no-stretch"
            Fg = ngs.Id(3)
    assert "no-stretch" not in KINDS
    assert growth_kind("isotropic") is IsotropicGrowth


def test_a_new_kind_works_in_growth_mechanics(restore_kinds):
    """The axial kind and fiber growth along e1 are the same Fg: the same energy (theta
    varies across the fibers, so the growth is incompatible and the energy is not zero)."""
    _axial_kind()
    energies = []
    for kind, direction in (("axial-e1", None), ("fiber", fields.constant("e1"))):
        time = ngs.Parameter(0.0)
        growth = make_growth(kind, 1 + 0.3 * ngs.y * time, direction)
        problem = GrowthMechanics(cube(maxh=0.5), growth, NeoHookean.paper_idealized(), order=2)
        assert solve_growth(problem, time).converged
        energies.append(problem.strain_energy())
    assert energies[1] > 1e-7
    assert energies[0] == pytest.approx(energies[1], rel=1e-10)


def test_a_new_kind_works_in_coupled_growth_by_name(restore_kinds):
    """Coupled growth of the axial kind (by name, no direction) follows fiber growth along e1
    (given as its class) step for step: the kind's stretch drives its growth law."""
    _axial_kind()
    thetas = []
    for kind, direction in (("axial-e1", None), (FiberGrowth, fields.constant("e1"))):
        growth = GrowthEnergy(kind, direction, StrainDrivenLaw(tau=1.0, theta_max=1.5),
                              NeoHookean.from_nu(1.0, 0.3))
        problem = CoupledProblem(cube(maxh=1.0), [growth], order=2,
                                 symmetry={"left": "x", "right": "x"})
        problem.u.Set(ngs.CF((0.2 * ngs.x, 0, 0)))
        assert solve_coupled(problem, t_end=1.0, dt=0.5).converged
        thetas.append(growth.theta.vec.FV().NumPy().copy())
    assert growth.kind == "fiber"
    assert ngs.Integrate(growth.theta, problem.mesh) > 1.05
    np.testing.assert_allclose(thetas[0], thetas[1], rtol=0, atol=1e-12)


def test_non_positive_theta_is_an_error_that_names_where(unit_cube_hex):
    time = ngs.Parameter(0.0)
    check_positive(1 + ngs.x * time, unit_cube_hex, time)
    with pytest.raises(ParameterError, match=r"theta = 0 at X = \(1, [0-9.]+, [0-9.]+\), t = 0.5:"):
        check_positive(1 - 2 * ngs.x * time, unit_cube_hex, time)
    assert time.Get() == 0.0  # the caller's time is restored
    with pytest.raises(ParameterError, match="positive"):
        check_positive(ngs.log(ngs.x), unit_cube_hex)
    # a dip below zero between the quarter times (theta < 0 for 7/48 < t < 11/48) is found,
    # at the first check time in it, 19/128: theta = 1 - 2 sin(3 pi / 16)
    with pytest.raises(ParameterError, match=r"theta = -0.1111 at .*, t = 0.148438:"):
        check_positive(1 + 2 * ngs.sin(8 * ngs.pi * time), unit_cube_hex, time)
