"""ngincompat.mechanics.laws: growth rates of eq. (45)-(46) and the Euler residual of eq. (48)."""

import ngsolve as ngs
import numpy as np
import pytest
from fem.test_coupled import _stretched_bar

from geometries import bilayer, cube
from ngincompat.errors import ParameterError
from ngincompat.fem.stepping import solve_coupled
from ngincompat.mechanics.laws import (
    ConstantRateLaw,
    HillLaw,
    RegionalLaw,
    StrainDrivenLaw,
    euler_residual,
)


@pytest.fixture(scope="module")
def point():
    """A point at which to evaluate constant CoefficientFunctions (its mesh kept alive while
    the point is used)."""
    mesh = cube(maxh=1.0)
    yield mesh(0.5, 0.5, 0.5)
    del mesh


def _rate(law, theta, theta_e, point):
    return law.rate(ngs.CF(theta), ngs.CF(theta_e))(point)


def test_growth_saturates_at_theta_max():
    law = HillLaw(k=5.0, K=0.05, n=2, theta_crit=1.0, theta_max=1.3)
    problem, growth = _stretched_bar(law, stretch=1.5)
    solve_coupled(problem, t_end=3.0, dt=0.5)
    pts = problem.mesh(0.5, 0.5, 0.5)
    assert growth.theta(pts) == pytest.approx(1.3, abs=2e-2)
    assert growth.theta(pts) <= 1.3 + 1e-2


def test_no_growth_below_the_critical_stretch():
    problem, growth = _stretched_bar(StrainDrivenLaw(tau=1.0, theta_max=2.0, theta_crit=1.3))
    solve_coupled(problem, t_end=1.0, dt=0.5)
    assert ngs.Integrate(growth.theta, problem.mesh) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("law, name", [
    (lambda: StrainDrivenLaw(tau=0, theta_max=2), "tau"),
    (lambda: StrainDrivenLaw(tau=1, theta_max=0.9), "theta_max"),
    (lambda: HillLaw(k=-1, K=0.1), "k"),
    (lambda: HillLaw(k=1, K=0.1, n=0.5), "n"),
])
def test_growth_laws_reject_bad_parameters(law, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        law()


def test_the_strain_driven_rate_of_eq_45(point):
    """(1/tau) ((theta_max - theta) / (theta_max - 1))^gamma <theta_e - theta_crit>: with
    tau = 2, theta_max = 1.5, gamma = 2, theta_crit = 1.05 at theta = 1.2, theta_e = 1.25 it
    is 0.5 x 0.6^2 x 0.2 = 0.036; nothing below theta_crit, nothing at or past theta_max."""
    law = StrainDrivenLaw(tau=2.0, theta_max=1.5, gamma=2.0, theta_crit=1.05)
    assert _rate(law, 1.2, 1.25, point) == pytest.approx(0.036, rel=1e-14)
    assert _rate(law, 1.2, 1.0, point) == 0.0
    assert _rate(law, 1.5, 1.25, point) == 0.0
    assert _rate(law, 1.6, 1.25, point) == 0.0
    flat = StrainDrivenLaw(tau=1.0, theta_max=1.5, gamma=0.0)       # no saturation factor
    assert _rate(flat, 1.4, 1.3, point) == pytest.approx(0.3, rel=1e-14)
    assert _rate(flat, 1.6, 1.3, point) == 0.0


def test_the_hill_rate_of_eq_46(point):
    """k s^n / (K^n + s^n) <(theta_max - theta) / (theta_max - 1)>, s = <theta_e - theta_crit>:
    at s = K half the largest rate, times the room left (0.75 at theta = 1.5 of 3)."""
    law = HillLaw(k=0.2, K=0.1, n=2.0, theta_crit=1.0, theta_max=3.0)
    assert _rate(law, 1.5, 1.1, point) == pytest.approx(0.2 * 0.5 * 0.75, rel=1e-13)
    assert _rate(law, 1.0, 1e6, point) == pytest.approx(0.2, rel=1e-9)   # saturated stimulus
    assert _rate(law, 1.5, 0.9, point) == 0.0
    assert _rate(law, 3.2, 1.5, point) == 0.0


def test_the_tangent_of_the_strain_driven_rate(point):
    """d rate / d theta_e = (1/tau) room^gamma above theta_crit (the part of c^g, eq. 49,
    from the stimulus); finite, and zero, where growth has saturated with gamma = 1.5."""
    law = StrainDrivenLaw(tau=2.0, theta_max=1.5, gamma=1.5, theta_crit=1.0)
    theta, theta_e = ngs.Parameter(1.2), ngs.Parameter(1.1)
    rate = law.rate(theta, theta_e)
    room = (0.3 / 0.5) ** 1.5
    assert rate.Diff(theta_e)(point) == pytest.approx(0.5 * room, rel=1e-13)
    assert rate.Diff(theta)(point) == pytest.approx(-0.5 * 1.5 * 0.6 ** 0.5 / 0.5 * 0.1,
                                                    rel=1e-13)
    theta.Set(1.5)
    assert np.isfinite(rate.Diff(theta)(point)) and rate.Diff(theta)(point) == 0.0


def test_a_constant_rate_is_integrated_exactly_by_implicit_euler(point):
    """rate = r, so the residual theta - theta_n - dt r vanishes at theta_n + r dt: the
    implicit Euler step is theta(t) = 1 + r t exactly."""
    law = ConstantRateLaw(0.3)
    assert _rate(law, 1.7, 0.2, point) == pytest.approx(0.3)
    residual = euler_residual(law, ngs.CF(1.0 + 0.3 * 0.5), ngs.CF(1.0), 0.5, ngs.CF(1.4))
    assert residual(point) == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(ParameterError, match="^rate = -0.1 "):
        ConstantRateLaw(-0.1)


def test_the_euler_residual_takes_the_elastic_stretch_from_the_total(point):
    """R^g = theta - theta_n - dt rate(theta, theta_total / theta), eq. (48)."""
    law = StrainDrivenLaw(tau=1.0, theta_max=2.0, gamma=1.0, theta_crit=1.0)
    theta, old, dt, total = 1.2, 1.1, 0.5, 1.5
    expected = theta - old - dt * (2.0 - theta) / 1.0 * (total / theta - 1.0)
    got = euler_residual(law, ngs.CF(theta), ngs.CF(old), dt, ngs.CF(total))(point)
    assert got == pytest.approx(expected, rel=1e-14)


def test_a_regional_law_takes_each_regions_rate():
    """A prescribed cortex on a stretch-driven subcortex: each region's rate is its law's;
    a law for every region, and only for them, is required."""
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    law = RegionalLaw(mesh, {"cortex": ConstantRateLaw(0.4),
                             "subcortex": StrainDrivenLaw(tau=1.0, theta_max=2.0, gamma=0.0)})
    rate = law.rate(ngs.CF(1.1), ngs.CF(1.3))
    assert rate(mesh(0.5, 0.45)) == pytest.approx(0.4)
    assert rate(mesh(0.5, 0.1)) == pytest.approx(0.3)
    with pytest.raises(ParameterError, match=r"^laws = \['cortex'\] .*cortex, subcortex"):
        RegionalLaw(mesh, {"cortex": ConstantRateLaw(0.4)})
    with pytest.raises(ParameterError, match="^laws = "):
        RegionalLaw(mesh, {"cortex": ConstantRateLaw(0.4), "subcortex": ConstantRateLaw(0),
                           "skull": ConstantRateLaw(0)})


@pytest.mark.parametrize("law, name", [
    (lambda: StrainDrivenLaw(tau=1, theta_max=2, gamma=-1), "gamma"),
    (lambda: StrainDrivenLaw(tau=1, theta_max=2, theta_crit=0), "theta_crit"),
    (lambda: HillLaw(k=1, K=0), "K"),
    (lambda: HillLaw(k=1, K=0.1, theta_crit=-1), "theta_crit"),
    (lambda: HillLaw(k=1, K=0.1, theta_max=1), "theta_max"),
])
def test_the_other_parameters_out_of_range_are_named(law, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        law()
