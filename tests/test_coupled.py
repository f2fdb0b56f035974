"""Mechanically coupled growth: growth laws (eq. 45-46), implicit Euler (eq. 48) and the
consistent tangent (eq. 49)."""

import os
import shutil
import sys
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
from scipy.optimize import brentq

from geometries import cube, skin_patch
from ngincompat.errors import ParameterError
from ngincompat.fem.problem import CoupledGrowth, euler_residual, find_compiler
from ngincompat.fem.solver import NewtonOptions, solve_coupled
from ngincompat.fem.stages import CoupledStage
from ngincompat.mechanics import fields, kinematics
from ngincompat.mechanics.growth import IsotropicGrowth
from ngincompat.mechanics.laws import ConstantRateLaw, HillLaw, StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.progress import SILENT

LAW = StrainDrivenLaw(tau=1.0, theta_max=1.5, gamma=2.0, theta_crit=1.0)


def _stretched_bar(law, kind="fiber", stretch=1.2):
    """Unit cube held at a fiber stretch ``stretch`` along e1, free laterally."""
    problem = CoupledGrowth(cube(maxh=0.5), kind, fields.constant("e1"), law,
                            NeoHookean.from_nu(1.0, 0.3), order=2,
                            symmetry={"left": "x", "right": "x"})
    problem.u.Set(ngs.CF(((stretch - 1) * ngs.x, 0, 0)))
    return problem


def test_homogeneous_growth_follows_the_scalar_implicit_euler_update():
    """With the fiber stretch held at 1.2, theta follows the scalar eq. (48) step by step."""
    problem = _stretched_bar(LAW)
    history = solve_coupled(problem, t_end=2.0, dt=0.25)
    assert history.converged
    theta = 1.0
    for step in (s for s in history.steps if s.converged):
        def residual(T, dt=step.dt, old=theta):
            return T - old - dt * max((1.5 - T) / 0.5, 0) ** 2 * max(1.2 / T - 1, 0)
        theta = brentq(residual, 0.9, 1.5)
    mean = ngs.Integrate(problem.theta, problem.mesh)
    assert theta > 1.1
    assert mean == pytest.approx(theta, rel=1e-4)


def test_global_newton_converges_quadratically_with_coupled_growth():
    """The tangent includes c^g (eq. 49): the recorded residuals fall quadratically."""
    problem = _stretched_bar(LAW)
    history = solve_coupled(problem, t_end=0.5, dt=0.5,
                            options=NewtonOptions(max_iter=20, rtol=1e-13))
    res = np.asarray(history.steps[0].residuals)
    assert res[-1] < 1e-10 * res[0]
    above = res[res > 1e-15 * res[0]]
    orders = np.diff(np.log(above))[1:] / np.diff(np.log(above))[:-1]
    assert max(orders[-2:]) > 1.7, (res, orders)


def test_ngscxx_is_found_beside_the_interpreter_of_an_unactivated_environment(monkeypatch):
    """``.venv/bin/ngincompat`` runs without ``.venv/bin`` on PATH, where NGSolve's wheels put
    its compiler script: :func:`~ngincompat.fem.problem.find_compiler` puts it there."""
    beside = Path(sys.executable).parent / "ngscxx"
    if not beside.is_file():
        pytest.skip("NGSolve's ngscxx is not installed beside this interpreter")
    monkeypatch.setenv("PATH", "/nonexistent")
    assert shutil.which("ngscxx") is None
    assert find_compiler() == str(beside)
    assert os.environ["PATH"].split(os.pathsep)[0] == str(beside.parent)


def test_residual_compiled_to_cpp_gives_the_same_residual_and_tangent(caplog):
    """The C++-compiled residual (the default from REALCOMPILE_NDOF dofs on) is the same
    function as NGSolve's own compilation, and so is its linearisation. Where a C++
    compiler is installed the compilation must not have fallen back to NGSolve's own."""
    problem = _stretched_bar(LAW)
    problem.dt.Set(0.25)
    problem.theta.Set(1.0 + 0.1 * ngs.y)
    x = problem.state.vec
    plain = CoupledGrowth(problem.mesh, "fiber", fields.constant("e1"), LAW,
                          NeoHookean.from_nu(1.0, 0.3), order=2,
                          symmetry={"left": "x", "right": "x"}, realcompile=False)
    native = CoupledGrowth(problem.mesh, "fiber", fields.constant("e1"), LAW,
                           NeoHookean.from_nu(1.0, 0.3), order=2,
                           symmetry={"left": "x", "right": "x"}, realcompile=True)
    results = []
    for p in (plain, native):
        p.dt.Set(0.25)
        r = x.CreateVector()
        p.form.Apply(x, r)
        p.form.AssembleLinearization(x)
        w = x.CreateVector()
        w.FV().NumPy()[:] = np.linspace(-1, 1, len(w))
        Kw = x.CreateVector()
        Kw.data = p.form.mat * w
        results.append((r.FV().NumPy().copy(), Kw.FV().NumPy().copy()))
    for a, b in zip(*results, strict=True):
        assert np.linalg.norm(a) > 1e-3
        assert np.linalg.norm(a - b) <= 1e-11 * np.linalg.norm(a)
    if shutil.which("c++") and find_compiler():
        assert "compiling the residual to C++ failed" not in caplog.text


def test_growth_saturates_at_theta_max():
    law = HillLaw(k=5.0, K=0.05, n=2, theta_crit=1.0, theta_max=1.3)
    problem = _stretched_bar(law, stretch=1.5)
    solve_coupled(problem, t_end=3.0, dt=0.5)
    pts = problem.mesh(0.5, 0.5, 0.5)
    assert problem.theta(pts) == pytest.approx(1.3, abs=2e-2)
    assert problem.theta(pts) <= 1.3 + 1e-2


def test_no_growth_below_the_critical_stretch():
    problem = _stretched_bar(StrainDrivenLaw(tau=1.0, theta_max=2.0, theta_crit=1.3))
    solve_coupled(problem, t_end=1.0, dt=0.5)
    assert ngs.Integrate(problem.theta, problem.mesh) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("law, name", [
    (lambda: StrainDrivenLaw(tau=0, theta_max=2), "tau"),
    (lambda: StrainDrivenLaw(tau=1, theta_max=0.9), "theta_max"),
    (lambda: HillLaw(k=-1, K=0.1), "k"),
    (lambda: HillLaw(k=1, K=0.1, n=0.5), "n"),
])
def test_growth_laws_reject_bad_parameters(law, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        law()


def test_coupled_growth_names_the_registered_kinds():
    """An unknown kind is refused with the registry's kinds; a kind given as its class works
    like its name; a kind that needs a direction refuses to go without."""
    mesh = cube(maxh=1.0)
    material = NeoHookean.from_nu(1.0, 0.3)
    with pytest.raises(ParameterError, match="growth = 'volume' is unknown: allowed isotropic, "
                                             "area, fiber"):
        CoupledGrowth(mesh, "volume", None, LAW, material)
    with pytest.raises(ParameterError, match=r"area growth needs a direction \(N0\)"):
        CoupledGrowth(mesh, "area", None, LAW, material)
    assert CoupledGrowth(mesh, IsotropicGrowth, None, LAW, material).kind == "isotropic"


def test_volume_constraint_meets_its_target():
    """The pressure is the unknown conjugate to the enclosed volume: the target is met."""
    mesh = skin_patch(footprint="circle", maxh=2.5, curve_order=1)
    problem = CoupledGrowth(mesh, "area", fields.constant("e3"),
                            HillLaw(k=0.1, K=0.2), NeoHookean.from_nu(0.18, 0.4), order=2,
                            dirichlet="periphery", symmetry={"bottom": "z"},
                            volume="footprint")

    def schedule(t):
        problem.dt.Set(0.0)
        problem.volume_target.Set(5.0 * t)

    solve_coupled(problem, t_end=1.0, dt=0.5, schedule=schedule)
    assert problem.volume() == pytest.approx(5.0, rel=1e-8)
    assert problem.pressure() > 0


def _computed_growth_G_error(maxh, growth_order, g_order):
    """G from a growth field known only as an L2 function of ``growth_order`` (as a computed
    field is), through the projected path with H1 of ``g_order``, against eq. (20)."""
    from ngincompat.incompatibility import operators as inc
    from ngincompat.mechanics.growth import AreaGrowth

    mesh = cube(maxh=maxh, elements="tet")
    theta = 1 + 0.25 * ngs.sin(ngs.x + 0.5 * ngs.y)
    N0 = fields.constant("e3")
    theta_h = ngs.GridFunction(ngs.L2(mesh, order=growth_order))
    theta_h.Set(theta)
    growth = AreaGrowth(theta_h, N0)
    curl_Fg, _ = inc.curl_projected(growth.Fg, mesh, g_order)
    return inc.relative_l2_error(inc.incompatibility_tensor(growth.Fg, curl_Fg),
                                 AreaGrowth(theta, N0).closed_form_G(), mesh)


def test_G_of_a_computed_growth_field_meets_its_target():
    """The projection path on a field whose G is known (eq. 20): the error is set by the
    order of the growth field (h^q) and the default (growth order 3, H1 order 4) meets 1e-4 at
    maxh 0.25; a growth order lower by one misses it."""
    assert _computed_growth_G_error(0.25, 3, 4) < 1e-4
    assert _computed_growth_G_error(0.25, 2, 3) > 1e-3
    coarse, fine = _computed_growth_G_error(0.5, 2, 3), _computed_growth_G_error(0.25, 2, 3)
    assert fine < 0.3 * coarse


def test_a_march_ends_where_on_step_says_so():
    """on_step returning True (an instability detected) ends the march there, converged."""
    problem = _stretched_bar(LAW)
    seen = []

    def on_step(t):
        seen.append(t)
        return t >= 0.5

    history = solve_coupled(problem, t_end=2.0, dt=0.25, on_step=on_step)
    assert history.converged and history.t_reached == pytest.approx(0.5)
    assert seen == pytest.approx([0.25, 0.5])


def test_viscous_regularisation_lags_and_a_frozen_step_removes_it():
    """Fiber growth at a constant rate in a cube on rollers at one end: with the viscous term
    eta / dt int (u - u_n) . v dV a step ends short of equilibrium (the displacement lags);
    a step at frozen growth (dt = 0, which switches the viscous term off) then reaches the
    state of the march without it, to the Newton tolerance."""
    def grown(viscosity):
        problem = CoupledGrowth(cube(maxh=0.5), "fiber", fields.constant("e1"),
                                ConstantRateLaw(0.2), NeoHookean.from_nu(1.0, 0.3), order=2,
                                symmetry={"left": "x"}, viscous=True)
        problem.viscosity.Set(viscosity)
        CoupledStage("growth", problem, t_end=1.0, dt=1.0).run(SILENT)
        return problem

    def end_displacement(problem):
        return problem.u(problem.mesh(1.0, 0.5, 0.5))[0]

    plain = grown(0.0)
    assert end_displacement(plain) == pytest.approx(0.2, rel=1e-6)   # theta = 1.2 exactly
    problem = grown(10.0)
    assert 0 < end_displacement(problem) < 0.5 * end_displacement(plain)
    CoupledStage("equilibrium", problem, t_end=1.0, dt=1.0, grow=False).run(SILENT)
    np.testing.assert_allclose(problem.u.vec.FV().NumPy(), plain.u.vec.FV().NumPy(),
                               atol=1e-9)


def test_stress_form_equals_the_symbolic_derivative_in_u():
    """The residual written as P : Grad v with P = dW/dF gives the residual and tangent of
    the form dW/du . v differentiated symbolically in u (built here independently), growth
    unknowns included, to round-off."""
    problem = CoupledGrowth(cube(maxh=0.5), "area", fields.constant("e3"), LAW,
                            NeoHookean.from_nu(1.0, 0.3), order=3)
    problem.dt.Set(0.1)
    (u, theta), (v, eta) = (list(t)[:2] for t in problem.fes.TnT())
    F = kinematics.deformation_gradient(u)
    growth = euler_residual(LAW, theta, problem.theta_old, problem.dt,
                            problem._growth(theta).stretch(F))
    symbolic = ngs.BilinearForm(problem.fes, condense=True)
    symbolic += (problem._energy_density(F, theta).Diff(u, v) + growth * eta) * ngs.dx
    x = problem.state.vec.CreateVector()
    x.data = problem.state.vec
    x.FV().NumPy()[:] += 0.01 * np.random.default_rng(1).standard_normal(len(x))
    r, r_symbolic = x.CreateVector(), x.CreateVector()
    problem.form.Apply(x, r)
    symbolic.Apply(x, r_symbolic)
    assert r.Norm() > 1e-3
    r_symbolic.data -= r
    assert r_symbolic.Norm() < 1e-12 * r.Norm()
    problem.form.AssembleLinearization(x)
    symbolic.AssembleLinearization(x)
    K, K_symbolic = (np.array(f.mat.COO()[2]) for f in (problem.form, symbolic))
    assert np.abs(K - K_symbolic).max() < 1e-12 * np.abs(K).max()


@pytest.mark.parametrize("loaded", [False, True], ids=["frozen", "viscous-traction"])
def test_the_potential_is_the_energy_of_the_frozen_residual(loaded):
    """At frozen growth the coupled residual is the derivative of the step's energy in u:
    the strain energy int Jg Psi dV (dt = 0), and with a viscous pseudo-time step and a dead
    traction Phi = int Jg Psi dV + eta / (2 dt) int |u - u_n|^2 dV - s int t . u dA
    (:meth:`~ngincompat.fem.problem.CoupledGrowth.potential`). Its central difference along a
    displacement w equals R(u) . w. This is what lets the frozen Newton solves of
    :mod:`ngincompat.fem.stages` test their line search on the energy."""
    if loaded:
        problem = CoupledGrowth(cube(maxh=0.5), "fiber", fields.constant("e1"), LAW,
                                NeoHookean.from_nu(1.0, 0.3), order=2,
                                symmetry={"left": "x"}, viscous=True, traction="right|top")
        problem.traction_field.Set(ngs.CF((0.3 + ngs.y, 0.2 * ngs.z, -0.1)))
        problem.load_scale.Set(0.7)
        problem.u_old.Set(ngs.CF((0.02 * ngs.y, 0.01, -0.03 * ngs.x)))
        problem.viscosity.Set(5.0)
        problem.growing.Set(0.0)
        problem.dt.Set(0.25)
    else:
        problem = _stretched_bar(LAW, stretch=1.1)
        problem.dt.Set(0.0)
    problem.theta.Set(1.0 + 0.1 * ngs.x)
    problem.theta_old.vec.data = problem.theta.vec
    problem.u.Set(ngs.CF((0.1 * ngs.x + 0.05 * ngs.y * ngs.z, 0.03 * ngs.x * ngs.y, 0)))
    w = problem.state.vec.CreateVector()
    direction = ngs.GridFunction(problem.fes)
    direction.components[0].Set(ngs.CF((ngs.y * ngs.z, 0.5 * ngs.x * ngs.x, ngs.y)))
    w.data = direction.vec
    w.FV().NumPy()[[not free for free in problem.fes.FreeDofs()]] = 0.0
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    u0 = problem.state.vec.CreateVector()
    u0.data = problem.state.vec
    eps = 1e-5
    problem.state.vec.data = u0 + eps * w
    plus = problem.potential()
    problem.state.vec.data = u0 - eps * w
    minus = problem.potential()
    slope = ngs.InnerProduct(residual, w)
    assert abs(slope) > 1e-3
    assert (plus - minus) / (2 * eps) == pytest.approx(slope, rel=1e-6)
    if loaded:      # each term counts: without the viscous and the load terms it fails
        problem.state.vec.data = u0 + eps * w
        plus = problem.strain_energy()
        problem.state.vec.data = u0 - eps * w
        minus = problem.strain_energy()
        assert (plus - minus) / (2 * eps) != pytest.approx(slope, rel=1e-3)


def test_the_potential_of_a_volume_constraint_is_refused():
    problem = CoupledGrowth(skin_patch(footprint="circle", maxh=2.5, curve_order=1), "area",
                            fields.constant("e3"), LAW, NeoHookean.from_nu(0.18, 0.4),
                            order=1, dirichlet="periphery", volume="footprint")
    with pytest.raises(ParameterError, match="volume"):
        problem.potential()
