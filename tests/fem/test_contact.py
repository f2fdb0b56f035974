"""The expander as a rigid dome in frictionless penalty contact with the skin."""

import math

import numpy as np
import pytest

from geometries import FOOTPRINTS, footprint_size
from ngincompat import config
from ngincompat.errors import ParameterError
from ngincompat.fem import contact
from ngincompat.fem.contact import Expander
from ngincompat.fem.solver import NewtonSolver
from ngincompat.scenes import SkinExpansionScene

#: A coarse run of the contact model: a low dome (3 cc), inflated in one step, half a day of
#: hold, deflation and release.
COARSE = dict(footprint="circle", maxh=3.0, order=1, growth_order=0, g_order=2,
              inflation_steps=1, volume=3.0, hold_days=0.5, dt=0.5, outputs="none")


@pytest.mark.parametrize("footprint", FOOTPRINTS)
def test_dome_is_one_at_its_top_zero_on_the_edge_and_outside(footprint):
    dome = Expander(footprint, footprint_size(footprint, 24.5), 1.0)
    pts = dome.points(dome.size / 200)
    phi, dx, dy = dome.shape(pts[:, 0], pts[:, 1])
    assert np.max(phi) == pytest.approx(1.0, abs=1e-4) and np.all(phi > 0)
    # the footprint's area from the grid, and nothing outside it
    assert len(pts) * (dome.size / 200) ** 2 == pytest.approx(24.5, rel=2e-2)
    far = dome.shape(np.array([dome.size, 0.0]), np.array([0.0, dome.size]))
    assert np.all(np.concatenate(far) == 0)
    # the gradient is that of phi (central differences, away from the edge's kink)
    pts, dx, dy = pts[phi > 1e-3], dx[phi > 1e-3], dy[phi > 1e-3]
    h = 1e-6
    fx = (dome.shape(pts[:, 0] + h, pts[:, 1])[0] - dome.shape(pts[:, 0] - h, pts[:, 1])[0])
    fy = (dome.shape(pts[:, 0], pts[:, 1] + h)[0] - dome.shape(pts[:, 0], pts[:, 1] - h)[0])
    np.testing.assert_allclose(fx / (2 * h), dx, atol=1e-5)
    np.testing.assert_allclose(fy / (2 * h), dy, atol=1e-5)


def test_circular_dome_is_the_inflated_membrane():
    """-Lap phi is constant (4 / R^2 at top 1) and phi = 0 on the circle: the membrane's
    shape under uniform pressure."""
    R = 2.5
    dome = Expander("circle", 2 * R, 1.0)
    rng = np.random.default_rng(1)
    r, a = R * np.sqrt(rng.uniform(0, 0.8, 50)), rng.uniform(0, 2 * np.pi, 50)
    x, y, h = r * np.cos(a), r * np.sin(a), 1e-3
    lap = (dome.shape(x + h, y)[0] + dome.shape(x - h, y)[0] + dome.shape(x, y + h)[0]
           + dome.shape(x, y - h)[0] - 4 * dome.shape(x, y)[0]) / h**2
    np.testing.assert_allclose(-lap, 4 / R**2, rtol=1e-6)
    edge = dome.shape(R * np.cos(a) * (1 - 1e-12), R * np.sin(a) * (1 - 1e-12))[0]
    np.testing.assert_allclose(edge, 0, atol=1e-10)


def test_pressure_is_zero_where_the_gap_is_open_and_grows_with_penetration():
    """The plain penalty (width 0): p = kappa max(-g, 0), energy kappa min(g, 0)^2 / 2."""
    dome = Expander("square", 4.0, 50.0)
    x = np.zeros(5), np.zeros(5), np.array([-0.2, -0.1, 0.0, 0.1, 2.0])
    gap = dome.gap(x, 1.0)                   # dome top at 1: flat there, g = x3 - 1
    np.testing.assert_allclose(gap, x[2] - 1.0)
    np.testing.assert_allclose(dome.pressure(x, 1.0), [60.0, 55.0, 50.0, 45.0, 0.0])
    np.testing.assert_allclose(dome.energy(x, 1.0), 25.0 * np.minimum(gap, 0) ** 2)


def test_rounded_ramp_is_the_quadratic_blend_and_the_energy_its_integral():
    """r(s) = 0, s^2 / (2 eps), s - eps / 2 on s <= 0, (0, eps), >= eps; R' = r and r' is
    continuous (0 at s = 0, 1 at s = eps); a pressure p >= kappa eps / 2 has the penetration
    p / kappa + eps / 2."""
    eps, kappa = 0.01, 300.0
    dome = Expander("circle", 4.0, kappa, eps)
    s = np.array([-0.5, -1e-9, 0.0, 0.25 * eps, 0.5 * eps, eps, 3 * eps, 1.0])
    r, R = dome.ramp(s)
    np.testing.assert_allclose(r, [0, 0, 0, eps / 32, eps / 8, eps / 2, 2.5 * eps, 1 - eps / 2],
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(R[-1], 0.5 - eps / 2 + eps**2 / 6, rtol=1e-12)
    grid = np.linspace(-2 * eps, 4 * eps, 6001)
    r, R = dome.ramp(grid)
    np.testing.assert_allclose(np.gradient(R, grid)[1:-1], r[1:-1], atol=1e-8)
    slope = np.diff(r) / np.diff(grid)          # r' jumps nowhere by more than a grid step
    assert np.max(np.abs(np.diff(slope))) < 2 * (grid[1] - grid[0]) / eps
    assert slope[0] == 0 and slope[-1] == pytest.approx(1.0)
    # pressure against penetration on the flat top of the dome (H = 1, g = x3 - 1)
    p = np.array([2.0, 5.0, 40.0])
    x = np.zeros(3), np.zeros(3), 1 - (p / kappa + eps / 2)
    np.testing.assert_allclose(dome.pressure(x, 1.0), p, rtol=1e-12)


def test_circular_dome_volume_is_half_the_cylinder():
    """H int phi dA = H pi R^2 / 2 over the disc (the paraboloid's volume)."""
    R = footprint_size("circle", 24.5) / 2
    dome = Expander("circle", 2 * R, 1.0)
    h = dome.size / 1000
    pts = dome.points(h)
    volume = np.sum(dome.shape(pts[:, 0], pts[:, 1])[0]) * h * h
    assert volume == pytest.approx(math.pi * R * R / 2, rel=2e-3)


def test_membrane_stretched_over_the_dome_presses_with_its_tension_times_curvature():
    """A membrane of tension T on the disc of radius R, held at w = 0 on the circle and
    pulled down by its tension onto the circular dome H phi (the penalty on the expander's
    gap at x = (x, y, w)): the dome is superharmonic, so the membrane touches it everywhere
    and the contact pressure is p = -T Lap(H phi) = 4 T H / R^2 (a finite element solve with
    the smoothed penalty, checked against that closed form and the penetration it implies)."""
    import ngsolve as ngs
    from netgen.geom2d import SplineGeometry

    R, T, H, kappa, eps = 1.0, 2.0, 0.05, 1e4, 1e-4
    disc = SplineGeometry()
    disc.AddCircle((0, 0), R, bc="edge")
    mesh = ngs.Mesh(disc.GenerateMesh(maxh=0.1))
    mesh.Curve(2)
    dome = Expander("circle", 2 * R, kappa, eps)
    fes = ngs.H1(mesh, order=2, dirichlet=".*")
    w, v = fes.TnT()
    x = (ngs.x, ngs.y, w)
    a = ngs.BilinearForm(fes)
    a += (T * ngs.grad(w) * ngs.grad(v) + dome.energy(x, H).Diff(w, v)) * ngs.dx(bonus_intorder=2)
    gf = ngs.GridFunction(fes)
    phi = dome.shape(ngs.x, ngs.y)[0]
    gf.Set(H * phi)
    free = np.array(list(fes.FreeDofs()))
    for _ in range(20):
        residual = gf.vec.CreateVector()
        a.Apply(gf.vec, residual)
        residual.FV().NumPy()[~free] = 0
        a.AssembleLinearization(gf.vec)
        gf.vec.data -= a.mat.Inverse(fes.FreeDofs()) * residual
        if residual.Norm() < 1e-11:
            break
    assert residual.Norm() < 1e-11
    pressure = dome.pressure((ngs.x, ngs.y, gf), H)
    inner = [mesh(0.6 * R * math.cos(t), 0.6 * R * math.sin(t)) for t in np.linspace(0, 6, 7)]
    values = np.array([pressure(p) for p in [mesh(0.0, 0.0), *inner]])
    expected = 4 * T * H / R**2
    np.testing.assert_allclose(values, expected, rtol=2e-2)
    gap = np.array([dome.gap((ngs.x, ngs.y, gf), H)(mesh(0.0, 0.0))])
    assert -gap[0] == pytest.approx(expected / kappa + eps / 2, rel=2e-2)


@pytest.mark.parametrize("kwargs, name", [
    (dict(footprint="star"), "footprint"), (dict(size=0.0), "footprint_size"),
    (dict(penalty=0.0), "penalty"), (dict(penalty=math.inf), "penalty"),
])
def test_bad_expanders_are_clear_errors(kwargs, name):
    args = {"footprint": "circle", "size": 5.0, "penalty": 1.0, **kwargs}
    with pytest.raises(ParameterError, match=f"^{name} = "):
        Expander(**args)


@pytest.mark.parametrize("kwargs, name", [
    (dict(expander="balloon"), "expander"), (dict(penalty=-1.0), "penalty"),
    (dict(footprint_area=0.0), "footprint_area"), (dict(footprint_area=90.0), "footprint_area"),
])
def test_bad_scene_settings_are_clear_errors(kwargs, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        SkinExpansionScene(**kwargs).build()


@pytest.fixture(scope="module")
def inflated():
    """The coarse contact run (a mesh of 3 cm: the skin touches the dome near its top)."""
    return SkinExpansionScene(expander="contact", penalty=1000.0, **COARSE).run()


def test_expander_holds_its_volume_and_the_skin_rests_on_it(inflated):
    m = inflated.metrics
    assert inflated.status == "done"
    assert list(inflated.solver) == ["inflation", "contact", "hold", "deflation",
                                     "deflation_clamped", "deflation_released"]
    # the volume under the skin is the target: the expander's size was controlled to it
    assert m["volume_inflated"] == pytest.approx(3.0, rel=1e-4)
    assert m["volume_error_rel"] <= 1e-4
    assert inflated.solver["contact"].converged
    # the dome keeps its height through the hold, and the skin stays on it
    assert m["expander_height_end_of_hold"] == m["expander_height_inflated"]
    assert m["contact_area_end_of_hold"] > 0
    # the skin bridges the dome where it does not touch it, so the expander's own volume
    # H int phi dA = H pi R^2 / 2 is less than the volume under the skin
    R = footprint_size("circle", 24.5) / 2
    own = m["expander_height_inflated"] * math.pi * R * R / 2
    assert 0.5 * 3.0 < own < 3.0
    assert 0 < m["contact_area_inflated"] < 24.5
    # the largest pressure is the penalty times the rounded ramp of the largest penetration
    dome = SkinExpansionScene(expander="contact", penalty=1000.0, **COARSE).expander_body()
    assert m["penetration_max_inflated"] > 0
    assert m["contact_pressure_max_inflated"] == pytest.approx(
        1000.0 * dome.ramp(m["penetration_max_inflated"])[0], rel=1e-9)
    assert 0 < m["contact_pressure_mean_inflated"] <= m["contact_pressure_max_inflated"]


def test_contact_pressure_is_zero_where_the_gap_is_open(inflated):
    dome = SkinExpansionScene(expander="contact", penalty=1000.0, **COARSE).expander_body()
    _, values = contact.sample(inflated.domain, dome,
                               {k: inflated.fields[k] for k in ("gap", "contact_pressure")},
                               dome.size / 40)
    gap, pressure = values["gap"], values["contact_pressure"]
    assert np.any(gap < 0) and np.any(gap > 0)
    assert np.all(pressure[gap >= 0] == 0)
    np.testing.assert_allclose(pressure[gap < 0], 1000.0 * dome.ramp(-gap[gap < 0])[0],
                               rtol=1e-12)


#: The penalty study: the low dome (3 cc) on the order-2 mesh of 1.5 cm, no hold.
STUDY = dict(footprint="circle", maxh=1.5, order=2, growth_order=0, g_order=2, volume=3.0,
             hold_days=0.0, outputs="none")


@pytest.mark.slow
def test_controlled_expander_converges_as_the_penalty_grows():
    """Penalty refinement on the low dome (3 cc) on order 2, the ramp's width eps = 5 / kappa
    (rounded over 5 MPa of pressure): at every penalty the volume under the skin is the
    target, the largest pressure is kappa r(largest penetration), the largest penetration
    falls, and the dome's height that gives the volume converges (each change under half the
    one before, for a penalty 3.3 times larger)."""
    heights, penetrations = [], []
    for penalty in (300.0, 1000.0, 3000.0):
        scene = SkinExpansionScene(expander="contact", penalty=penalty,
                                   contact_width=5.0 / penalty, **STUDY)
        m = scene.run().metrics
        assert m["volume_error_rel"] <= 1e-4
        assert m["contact_pressure_max_inflated"] == pytest.approx(
            penalty * scene.expander_body().ramp(m["penetration_max_inflated"])[0], rel=1e-9)
        heights.append(m["expander_height_inflated"])
        penetrations.append(m["penetration_max_inflated"])
    first, second = abs(heights[0] - heights[1]), abs(heights[1] - heights[2])
    assert second < 0.5 * first
    assert penetrations[0] > penetrations[1] > penetrations[2]


def test_released_maps_and_the_compression_of_the_former_contact_zone(inflated):
    """The mid-thickness maps (Fig. 6 a-c) hold every field inside the patch, the smallest
    principal stress is below the largest, and the contact zone's compression is the
    smallest principal stress sampled where the expander pressed."""
    m, grid = inflated.metrics, inflated.profiles["map"]
    for key in ("theta", "|b|", "sigma_max_released", "sigma_min_released"):
        assert grid[f"mid_{key}"].shape == (81, 81)
        assert np.isfinite(grid[f"mid_{key}"][1:-1, 1:-1]).all()
    assert np.all(grid["mid_sigma_min_released"] <= grid["mid_sigma_max_released"] + 1e-12)
    dome = SkinExpansionScene(expander="contact", penalty=1000.0, **COARSE).expander_body()
    _, values = contact.sample(inflated.domain, dome,
                               {"p": inflated.fields["contact_pressure"],
                                "s": inflated.fields["sigma_min_released"]}, 0.1)
    touched = values["s"][values["p"] > 0]
    assert m["min_principal_stress_contact_zone"] == pytest.approx(np.min(touched))
    assert m["min_principal_stress_contact_zone_mean"] == pytest.approx(np.mean(touched))


def test_smallest_principal_value_is_the_largest_of_the_negated_tensor():
    import ngsolve as ngs

    from ngincompat.fem.postprocess import largest_principal_value

    rng = np.random.default_rng(3)
    A = rng.normal(size=(3, 3))
    T = A + A.T
    cf = ngs.CoefficientFunction(tuple(T.ravel()), dims=(3, 3))
    mesh = ngs.Mesh(ngs.unit_cube.GenerateMesh(maxh=1.0))
    smallest = -largest_principal_value(-cf)
    assert smallest(mesh(0.5, 0.5, 0.5)) == pytest.approx(np.linalg.eigvalsh(T)[0], abs=1e-10)


def test_expander_handed_over_to_its_dead_traction_keeps_the_equilibrium():
    """The deflation's first act: the dome's contact force becomes a dead traction and the
    dome is lowered under the skin; the inflated state stays an equilibrium and nothing
    touches the dome any more."""
    import ngsolve as ngs

    from ngincompat.workflow.pipeline import solve_stages

    case = SkinExpansionScene(expander="contact", penalty=1000.0, **COARSE).build()
    problem, expander = case.problem, case.holder
    with config.task_manager():
        solve_stages([s for s in case.stages(None, None) if s.name in ("inflation", "contact")])
    footprint = case.mesh.Boundaries("footprint")
    pushed = ngs.Integrate(expander.contact_pressure(), case.mesh, ngs.BND, definedon=footprint)
    volume = expander.volume()
    force = case.expander_to_traction()
    assert pushed > 0 and force > 0
    assert expander.expander_height() == 0.0 and case.traction.scale.Get() == 1.0
    assert ngs.Integrate(expander.contact_pressure(), case.mesh, ngs.BND,
                         definedon=footprint) == 0.0
    assert expander.volume() == volume
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    free = np.array(problem.freedofs, dtype=bool)[:problem.u.space.ndof]
    assert np.linalg.norm(residual.FV().NumPy()[:problem.u.space.ndof][free]) <= 1e-8 * force


def test_only_an_expander_in_contact_is_handed_over_to_a_traction():
    case = SkinExpansionScene(**{**COARSE, "expander": "pressure"}).build()   # no expander
    with pytest.raises(ParameterError, match="^expander = 'pressure'"):
        case.expander_to_traction()


def test_lift_keeps_every_point_at_its_height_above_the_raised_dome():
    """The inflation's predictor: raising the dome by dH lifts each point of the skin by
    dH phi at its current place (x = X + u), so x3 - H phi(x1, x2) does not change. The skin
    here is drawn in by a fifth, where phi at the reference place would miss by up to 18 %
    of dH; what is left is the interpolation of the order-2 lift (1 %)."""
    import ngsolve as ngs

    scene = SkinExpansionScene(expander="contact", **{**COARSE, "maxh": 1.5, "order": 2})
    case = scene.build()
    expander, mesh, dome = case.holder, case.mesh, scene.expander_body()
    expander.u.Set(ngs.CoefficientFunction((-0.2 * ngs.x, -0.2 * ngs.y,
                                            0.3 * dome.shape(ngs.x, ngs.y)[0])))
    R = dome.size / 2
    points = [mesh(r * math.cos(a), r * math.sin(a), 0.0)
              for r in np.linspace(0, 0.7 * R, 8) for a in np.linspace(0, 2 * math.pi, 7)[:-1]]

    def above():
        x = ngs.CoefficientFunction((ngs.x, ngs.y, ngs.z)) + expander.u
        height = x[2] - expander.expander_height() * dome.shape(x[0], x[1])[0]
        return np.array([height(p) for p in points])

    expander.set_target(2.0)
    before, H = above(), expander.expander_height()
    expander.set_target(3.0, lift=True)
    dH = expander.expander_height() - H
    assert dH > 0
    assert np.max(np.abs(above() - before)) <= 0.02 * dH


def test_frozen_growth_is_the_coupled_problem_on_the_displacement_alone():
    """At frozen growth the coupled residual's displacement rows are the derivative of the
    terms' energies held at the current theta (growth, contact, dead traction): the
    displacement-only problem (the energy's Variation, a different formulation from the
    coupled P : Grad v and Diff) has the same residual, by the same rule also with theta of
    a higher order than u, and a symmetric tangent whose Newton direction is the coupled
    one's. The pressure model (a multiplier) has none."""
    import ngsolve as ngs

    scene = SkinExpansionScene(expander="contact", **{**COARSE, "maxh": 2.0, "order": 2,
                                                      "growth_order": 3})
    case = scene.build()
    problem = case.problem
    dome = scene.expander_body().shape(ngs.x, ngs.y)[0]
    problem.u.Set(ngs.CoefficientFunction((0.01 * ngs.x * ngs.y, 0.02 * ngs.y * ngs.z,
                                           0.5 * dome)))
    case.growth.theta.Set(1.1 + 0.02 * ngs.x)
    problem.accept_step()                           # theta_n = theta, as after a step
    case.holder.target.Set(6.0)                     # pressed into the dome
    case.traction.field.Set(ngs.CoefficientFunction((0.0, 0.0, 0.01)))
    case.traction.scale.Set(0.5)
    problem.dt.Set(0.0)
    frozen = problem.frozen()
    n = problem.space.ndof
    free = np.array(frozen.freedofs, dtype=bool)
    assert np.array_equal(free, np.array(problem.freedofs, dtype=bool)[:n])
    assert frozen.inverse == "sparsecholesky" and problem.inverse != frozen.inverse
    directions = []
    with config.task_manager():
        assert ngs.Integrate(case.holder.contact_pressure(), case.mesh, ngs.BND,
                             definedon=case.mesh.Boundaries("footprint")) > 0
        for p in (problem, frozen):
            solver = NewtonSolver(p)
            residual = solver.residual().FV().NumPy()[:n][free].copy()
            solver.factorise()
            directions.append((residual, solver.direction().FV().NumPy()[:n][free].copy()))
    (r, du), (r_alone, du_alone) = directions
    assert np.linalg.norm(r_alone - r) <= 1e-9 * np.linalg.norm(r)
    assert np.linalg.norm(du_alone - du) <= 1e-9 * np.linalg.norm(du)
    pressure = SkinExpansionScene(**{**COARSE, "expander": "pressure"}).build().problem
    assert pressure.frozen() is None
