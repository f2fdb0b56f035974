"""ngincompat.scenes.folding.case: the coupled bilayer's stages, the records of its growth, the
onset, the march, the release and the measures of the top surface."""

import dataclasses

import ngsolve as ngs
import numpy as np
import pytest
from scenes.folding.test_scene import CREASING, SMALL

from geometries import bilayer, cube
from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.fem import buckling
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.shape import circle_curvature
from ngincompat.fem.terms import GrowthEnergy
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import ConstantRateLaw, RegionalLaw, StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean, Regional
from ngincompat.progress import SILENT
from ngincompat.references.bifurcation import critical_growth, onset
from ngincompat.scenes.folding import CREASE_STRETCH, SNAP_STEP, FoldingScene
from ngincompat.scenes.folding import case as folding_case
from ngincompat.workflow.pipeline import Solution


def test_regional_material_and_law_need_every_region():
    mesh = bilayer(maxh=1.0)
    with pytest.raises(ParameterError, match="materials.*cortex, subcortex"):
        Regional(mesh, {"cortex": NeoHookean(1.0, 1.0)})
    with pytest.raises(ParameterError, match="laws.*cortex, subcortex"):
        RegionalLaw(mesh, {"subcortex": ConstantRateLaw(0.1)})
    with pytest.raises(ParameterError, match="rate = -1"):
        ConstantRateLaw(-1.0)


def test_wavelength_of_sampled_data():
    x = np.linspace(0, 3, 400)
    assert buckling.wavelength(x, np.cos(2 * np.pi * x / 0.35 + 0.3)) == pytest.approx(
        0.35, rel=2e-3)
    assert np.isnan(buckling.wavelength(x, 1 + x))


def coupled_block(mesh, order=2):
    """A nearly incompressible coupled body in a smooth state, its growth held: the growth
    theta = 1.2 + 0.2 X1 along e1 taken up by u1 = int (theta - 1) dX1, plus a bend. (A
    state that does not take the growth up is compressed by lambda (1 - 1 / theta), 20 times
    mu: its tangent had 418 negative eigenvalues, down to -2e6 on the mesh's scale.)"""
    law = StrainDrivenLaw(tau=10.0, theta_max=3.0, gamma=0.0, theta_crit=1.0)
    growth = GrowthEnergy("fiber", fields.constant("e1"), law, NeoHookean(1.0, 100.0),
                          growth_order=order - 1)
    problem = CoupledProblem(mesh, [growth], order=order)
    x, z = ngs.x, (ngs.x, ngs.y, ngs.z)[mesh.dim - 1]    # z: the vertical
    along, down = 0.2 * x + 0.1 * x * x + 0.02 * x * z, -0.03 * x * x
    problem.u.Set(ngs.CF((along, 0.0, down) if mesh.dim == 3 else (along, down)))
    growth.theta.Set(1.2 + 0.2 * ngs.x)
    growth.theta_old.vec.data = growth.theta.vec
    return problem


def test_eigenpairs_are_those_of_the_residuals_derivative():
    """omega = w . K w for a mode of unit L2 norm, with K the derivative of the residual the
    coupled problem solves (central differences). A Hessian of the energy on u alone
    (NGSolve integrates it more coarsely on tetrahedra) was off by 8e-5 on this test's former
    state (compressed, :func:`coupled_block`) and had modes of its own at a folded
    equilibrium (-1.49 at one that is stable)."""
    problem = coupled_block(bilayer(length=0.4, height=0.2, cortex=0.05,
                                    maxh=0.1, cortex_maxh=0.025))
    problem.dt.Set(1.0)                 # a step's dt: the tangent is taken at frozen growth
    values, modes = buckling.smallest_eigenpairs(problem, count=2)
    assert problem.dt.Get() == 1.0
    problem.dt.Set(0.0)
    residual = problem.state.vec.CreateVector()

    def slope(mode, h):
        """w . (r(u + h w) - r(u - h w)) / 2h."""
        w = mode.vec.FV().NumPy()
        ends = []
        for step in (h, -h):
            problem.u.vec.data += step * mode.vec
            problem.form.Apply(problem.state.vec, residual)
            ends.append(residual.FV().NumPy()[:len(w)] @ w)
            problem.u.vec.data -= step * mode.vec
        return (ends[0] - ends[1]) / (2 * h)

    for value, mode in zip(values, modes, strict=True):
        curvature = (4 * slope(mode, 5e-8) - slope(mode, 1e-7)) / 3     # Richardson: O(h^4)
        assert curvature == pytest.approx(value, rel=1e-7)


def test_eigenpairs_fall_back_to_lu_when_a_factorisation_gives_inaccurate_pairs(monkeypatch):
    """A shift-invert operator whose pairs are not those of K (here K^-1 scaled by 1.001, as
    an inaccurate factorisation of an indefinite K could give) is rejected by the pairs'
    residual and the next factorisation is used; with none left the call raises."""
    problem = coupled_block(bilayer(length=0.4, height=0.2, cortex=0.05,
                                    maxh=0.1, cortex_maxh=0.025))
    exact, _ = buckling.smallest_eigenpairs(problem, count=2)
    operator = buckling._inverse_operator
    used = []

    def inaccurate(matrix, inverse, lu):
        used.append(inverse)
        good = operator(matrix, inverse, lu)
        if inverse != "superlu":
            return good
        return buckling.LinearOperator(good.shape, matvec=lambda b: 1.001 * good.matvec(b),
                                       dtype=float)

    monkeypatch.setattr(buckling, "_inverse_operator", inaccurate)
    values, _ = buckling.smallest_eigenpairs(problem, count=2)
    assert used == ["superlu", "sparsecholesky"]
    np.testing.assert_allclose(values, exact, rtol=1e-8)
    used.clear()
    monkeypatch.setattr(buckling, "INVERSES", ("superlu", "umfpack"))
    np.testing.assert_allclose(buckling.smallest_eigenpairs(problem, count=2)[0], exact,
                               rtol=1e-8)
    assert used == ["superlu", "umfpack"]
    monkeypatch.setattr(buckling, "INVERSES", ("superlu",))
    with pytest.raises(ConvergenceError, match="residual"):
        buckling.smallest_eigenpairs(problem, count=2)


def test_eigenpairs_are_reproducible_and_signed():
    """The same state gives the same modes, each with its largest dof positive (a mode seeds
    the buckled branch: with a random sign the folds' phase changed from run to run)."""
    problem = coupled_block(bilayer(length=0.4, height=0.2, cortex=0.05,
                                    maxh=0.1, cortex_maxh=0.025))
    first, second = (buckling.smallest_eigenpairs(problem, count=3) for _ in range(2))
    np.testing.assert_array_equal(first[0], second[0])
    for a, b in zip(first[1], second[1], strict=True):
        w = a.vec.FV().NumPy()
        np.testing.assert_allclose(w, b.vec.FV().NumPy(), rtol=0, atol=1e-12 * np.abs(w).max())
        assert w[np.argmax(np.abs(w))] > 0


def test_eigenpairs_need_a_space_without_condensed_displacement_dofs():
    with pytest.raises(ParameterError, match="order"):
        buckling.smallest_eigenpairs(coupled_block(cube(maxh=1.0)))     # hexahedra, order 2


def test_the_short_steps_start_two_onset_steps_before_the_analysis_onset():
    """The perfect branch: ``approach`` up to 2 onset_dt before the analysis' onset (the
    small bilayer's: theta_c = 1.2802688, n = 6), in steps up to ``approach_dt``, then
    ``perfect``; no approach where it would not hold two long steps or passes t_end."""
    scene = FoldingScene(**SMALL)
    case = scene.build()
    near = (1.2802688 - 1) / scene.cortex_rate - 2 * scene.onset_dt
    assert case.approach_end() == pytest.approx(near, rel=1e-6)
    approach, perfect = case.stages()
    assert (approach.name, approach.t_start, approach.t_end) == ("approach", 0.0,
                                                                  case.approach_end())
    assert approach.options.max_step == scene.approach_dt
    assert (perfect.name, perfect.t_start, perfect.options.max_step) == (
        "perfect", case.approach_end(), scene.onset_dt)
    for short in (dict(approach_dt=20.0), dict(approach_dt=1.0, onset_dt=20.0),
                  dict(t_end=30.0)):
        case = FoldingScene(**SMALL, **short).build()
        assert case.approach_end() == 0.0
        assert [(s.name, s.t_start) for s in case.stages()] == [("perfect", 0.0)]


def test_the_march_steps_are_capped_by_the_unstable_mode_and_onset_dt():
    """The viscous march starts at the onset step with steps up to eta / (2 |omega_onset|)
    (the unstable mode at most doubles per step) and ``onset_dt``; a step cut below
    ``SNAP_STEP`` of that hands the snap to a relaxation."""
    case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1}).build()
    case.series["perfect"].update(t=[35.0, 36.25], eigenvalue=[3.0, -60.0])
    stage = case.buckling_stage()
    march = stage.march
    assert (stage.name, march.t_start) == ("buckling", 36.25)
    assert march.dt == march.options.max_step == pytest.approx(case.eta / 120.0)
    assert march.options.min_step == pytest.approx(march.dt * SNAP_STEP)
    case.series["perfect"]["eigenvalue"][-1] = -6.0
    march = case.buckling_stage().march
    assert march.dt == march.options.max_step == case.scene.onset_dt
    assert march.options.min_step == pytest.approx(case.scene.onset_dt * SNAP_STEP)


def test_the_march_is_recorded_every_observe_dt_of_growth():
    """The viscous march computes its eigenpairs (and records amplitude and stretch) at its
    first step, then once ``observe_dt`` of growth has passed since the last record, and at
    t_end; ``observe_dt`` = 0 records every step."""
    for observe_dt, expected in ((1.25, [36.25, 37.6, 39.0, 40.0]),
                                 (0.0, [36.25, 36.5, 37.0, 37.6, 38.0, 39.0, 40.0])):
        case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1},
                            t_end=40.0, observe_dt=observe_dt).build()
        case._observe = lambda branch, t, case=case: case.series[branch]["t"].append(t)
        for t in (36.25, 36.5, 37.0, 37.6, 38.0, 39.0, 40.0):
            assert case._observe_buckling(t) is False
        assert case.series["buckling"]["t"] == expected


@pytest.fixture(scope="module")
def onset_run():
    """The small bilayer grown on its perfect branch until its tangent loses positive
    definiteness, then, perturbed by the buckling mode, on to theta_c = 1.4."""
    scene = FoldingScene(**SMALL, dt=5.0, onset_dt=5.0, t_end=50.0)
    case = scene.build()
    solution = Solution()
    case.solve(solution, SILENT, None)
    return scene, case, solution


@pytest.mark.slow
def test_onset_matches_the_bifurcation_oracle(onset_run):
    """Critical growth and wavelength against the Stroh analysis of the same bilayer (roller
    ends: modes k = n pi / L). The growth to 1 %; the minimum over n is flat (here n = 5, 6, 7
    buckle at 1.2837, 1.2803, 1.2867), so the mode found must be one with k = n pi / L whose
    critical growth in the analysis is within 1 % of the onset found."""
    scene, case, solution = onset_run
    assert solution.converged
    bilayer = scene.bifurcation_bilayer()
    oracle = onset(bilayer, length=scene.length)
    found = case.noted["onset_growth"]
    assert found == pytest.approx(oracle.growth, rel=0.01)
    n = 2 * scene.length / case.noted["onset_wavelength"]
    assert n == pytest.approx(round(n), abs=0.05)
    assert critical_growth(bilayer, round(n) * np.pi / scene.length) == pytest.approx(
        found, rel=0.01)


def test_without_buckling_the_run_ends_at_the_onset():
    """``buckle = false`` (the refinement study's setting): the perfect branch up to its first
    negative eigenvalue, the onset measured, and nothing after it (no viscous march, no
    equilibrium, no release) although t_end is far beyond it."""
    scene = FoldingScene(length=1.0, height=0.6, cortex_thickness=0.1, cortex_maxh=0.05,
                         maxh=0.3, axons="none", t_end=75.0, dt=10.0, onset_dt=10.0,
                         buckle=False, outputs="none")
    results = scene.run()
    assert results.status == "done", results.error
    assert set(results.solver) == {"perfect"}
    eigenvalues = results.profiles["perfect"]["eigenvalue"]
    assert eigenvalues[-1] < 0 < min(eigenvalues[:-1])
    theta = results.profiles["perfect"]["theta_c"]
    assert theta[-2] < results.metrics["onset_growth"] < theta[-1]
    assert results.metrics["onset_wavelength"] > 0
    assert "fold_amplitude" not in results.metrics
    assert "release_reaction_rel" not in results.metrics


@pytest.mark.slow
def test_perfect_branch_stays_flat_before_the_onset(onset_run):
    """Every step before the onset: no undulation of the top, a positive tangent."""
    _, case, _ = onset_run
    series = case.series["perfect"]
    assert len(series["t"]) >= 3
    assert series["eigenvalue"][-1] < 0 < min(series["eigenvalue"][:-1])
    # the top only rises uniformly: its undulation is round-off next to the rise
    assert max(series["amplitude"][:-1]) < 1e-8


@pytest.mark.slow
def test_folds_grow_after_the_onset(onset_run):
    """Past the onset the perturbed bilayer folds: the viscous march reaches t_end without
    giving up, the top is flat to round-off on the perfect branch and the fold amplitude
    grows after the onset to many times the imperfection."""
    scene, case, solution = onset_run
    assert solution.converged, solution.error
    assert solution.histories["buckling"].t_reached == pytest.approx(scene.t_end)
    amplitude = np.array(case.series["buckling"]["amplitude"])
    imperfection = scene.imperfection * scene.cortex_thickness
    assert max(case.series["perfect"]["amplitude"]) < 1e-8
    assert amplitude[-1] > 20 * imperfection
    assert amplitude[-1] > 2 * amplitude[0]


def test_circle_fit_is_exact_on_arcs_and_lines():
    """Points on arcs of radius R (both senses, short and long) give 1 / R to round-off, a
    straight line 0."""
    s = np.linspace(-0.5, 0.5, 41)
    for radius in (0.7, 14.0, -3.0, 1e4):
        x, z = 1.5 + radius * np.sin(s / radius), 1 - radius * (1 - np.cos(s / radius))
        assert circle_curvature(x, z) == pytest.approx(1 / radius, rel=1e-7)
    assert circle_curvature(s, 0.3 * s + 1) == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(ParameterError, match="points"):
        circle_curvature([0.0, 1.0], [0.0, 1.0])


def test_top_curvature_of_a_prescribed_circular_bending():
    """The displacement that bends the top line onto a circle of radius R about the middle,
    X1 -> (L/2 + R sin(s / R), H - R (1 - cos(s / R))), s = X1 - L/2, interpolated by the
    quadratic elements: the measured curvature is 1 / R to the interpolation error."""
    scene = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1})
    case = scene.build()
    radius = 0.8
    s = ngs.x - scene.length / 2
    case.problem.u.Set(ngs.CF((radius * ngs.sin(s / radius) - s,
                               -radius * (1 - ngs.cos(s / radius)))))
    assert case.top_curvature(case.problem.u) == pytest.approx(1 / radius, rel=1e-4)
    case.problem.u.Set(ngs.CF((0, 0.01 * ngs.x)))
    assert case.top_curvature(case.problem.u) == pytest.approx(0.0, abs=1e-9)


def test_top_stretch_of_prescribed_displacements():
    """The top surface's elastic stretch |F e1| / theta_c: sqrt((1 + a)^2 + c^2) / theta_c
    for u = (a X1, c X1), and 1 / theta_c for a bending onto a circle, which does not
    stretch the top line (to the interpolation error)."""
    scene = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1})
    case = scene.build()
    a, c, theta_c = -0.3, 0.2, 1.25
    case.problem.u.Set(ngs.CF((a * ngs.x, c * ngs.x)))
    assert case.top_stretch(case.problem.u, theta_c) == pytest.approx(
        np.hypot(1 + a, c) / theta_c, rel=1e-10)
    radius, s = 0.8, ngs.x - scene.length / 2
    case.problem.u.Set(ngs.CF((radius * ngs.sin(s / radius) - s,
                               -radius * (1 - ngs.cos(s / radius)))))
    assert case.top_stretch(case.problem.u, theta_c) == pytest.approx(1 / theta_c, rel=1e-4)


def test_a_failed_march_past_the_creasing_stretch_says_so():
    """A buckling march that gave up after the top's stretch fell below CREASE_STRETCH gets
    the time and growth where it did in its error; one that stayed above gets nothing."""
    case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2, "maxh": 0.1}).build()
    series = case.series["buckling"]
    series.update(t=[60.0, 62.0, 64.0], theta_c=[1.48, 1.496, 1.512],
                  stretch=[0.70, 0.55, 0.58])
    failed = Solution(status="not converged", error="buckling: the step fell below min_step")
    case._explain_crease(failed)
    assert "fell below 0.65" in failed.error and "t = 62" in failed.error
    assert "theta_c = 1.496" in failed.error and "0.58 at the last step" in failed.error
    assert "unrefined top" in failed.error and "top_refinement" in failed.error
    case.scene = dataclasses.replace(case.scene, top_refinement=4.0)   # refined: not blamed
    refined = Solution(status="not converged", error="buckling: the step fell below min_step")
    case._explain_crease(refined)
    assert "fell below 0.65" in refined.error and "unrefined" not in refined.error
    series["stretch"] = [0.8, 0.75, 0.7]
    above = Solution(status="not converged", error="buckling: the step fell below min_step")
    case._explain_crease(above)
    assert above.error == "buckling: the step fell below min_step"


def timoshenko_curvature(mismatch, cortex, substrate, stiffness_ratio):
    """Curvature of a free bilayer beam whose top layer (thickness ``cortex``) has the
    eigenstrain ``mismatch`` relative to the bottom one (``substrate``), both with the same
    Poisson ratio (Timoshenko, J. Opt. Soc. Am. 11 (1925) 233):
    kappa = 6 eps (1 + m)^2 / (h [3 (1 + m)^2 + (1 + m n) (m^2 + 1 / (m n))]),
    m = cortex / substrate, n the ratio of the (plane-strain) Young's moduli, h the total."""
    m, n, h = cortex / substrate, stiffness_ratio, cortex + substrate
    return 6 * mismatch * (1 + m) ** 2 / (h * (3 * (1 + m) ** 2 + (1 + m * n)
                                              * (m * m + 1 / (m * n))))


@pytest.mark.slow
def test_released_flat_bilayer_bends_as_a_timoshenko_bimetal():
    """Before the onset (theta_c = 1.001) the released bilayer, its cortex grown along e1
    and the substrate not at all (no axons), bends with the cortex outside. Plane strain
    with an eigenstrain along e1 alone: sigma11 = E / (1 - nu^2) (eps11 - eps*) in both
    layers, so the beam formula holds with the stiffness ratio mu_ratio (same nu). Against
    it to 0.5 % (beam theory vs a 5:1 plane-strain body over its central third: 0.07 %
    measured). The pins carry no reaction (1e-8 of the removed supports' forces); the
    peak tension is in the substrate at the interface, which the longer cortex stretches."""
    scene = FoldingScene(**{**SMALL, "height": 0.2, "maxh": 0.05}, t_end=0.125, dt=0.125)
    results = scene.run()
    expected = timoshenko_curvature(scene.cortex_rate * scene.t_end, scene.cortex_thickness,
                                    scene.height - scene.cortex_thickness, scene.mu_ratio)
    metrics = results.metrics
    assert "onset_growth" not in metrics
    assert metrics["top_curvature_released"] == pytest.approx(expected, rel=0.005)
    assert metrics["release_reaction_rel"] < 1e-8
    assert metrics["peak_tension_depth_released"] == pytest.approx(scene.cortex_thickness,
                                                                    abs=1e-6)
    assert metrics["max_principal_stress_released"] > 0
    assert {"u_released", "sigma_max", "sigma_max_released"} <= set(results.fields)


@pytest.mark.slow
def test_folded_bilayer_released_is_self_equilibrated_and_bent():
    """Grown just past the onset (the notebook's coarse bilayer), the folds relaxed to a
    stable equilibrium, then released: the supports removed at once, the released
    equilibrium stable, its pins without reaction (1e-8 of the removed supports' forces),
    the top bent with the longer cortex outside, the largest tension lower than before the
    release and no higher than the interface (as in Fig. 7c: tension below the cortex)."""
    scene = FoldingScene(length=1.0, height=0.6, cortex_thickness=0.1, cortex_maxh=0.05,
                         maxh=0.3, t_end=42.0, dt=10.0, onset_dt=10.0, outputs="none")
    results = scene.run()
    metrics = results.metrics
    assert results.status == "done", results.error
    assert metrics["equilibrium_eigenvalue"] > 0
    assert metrics["fold_amplitude"] > 10 * scene.imperfection * scene.cortex_thickness
    # the onset's mode: 1.5 waves, a sulcus inside and half of one on an end (the wavelength
    # estimated from the sampled mode, to its sampling)
    assert metrics["sulci"] == 1.5
    assert metrics["onset_wavelength"] == pytest.approx(scene.length / 1.5, rel=0.01)
    assert 0 < metrics["sulcus_depth"] <= 2 * metrics["fold_amplitude"] + 1e-12
    assert metrics["release_reaction_rel"] < 1e-8
    assert metrics["top_curvature_released"] > 0
    assert 0 < metrics["max_principal_stress_released"] < metrics["max_principal_stress"]
    assert metrics["peak_tension_depth_released"] >= scene.cortex_thickness - 1e-6


def test_a_coarse_bilayer_creases_into_self_contact_and_grows_to_75_days():
    """The paper's 75 days (theta_c = 1.6) past creasing: the top's elastic stretch falls
    below the creasing threshold, the walls of the sulci touch (a contact line) and do not
    pass through each other (penetration below 2 % of the cortex), no element inverts, the
    fold is deeper than the cortex is thick, and the normal axons grow."""
    scene = FoldingScene(**CREASING, axons="straight", release=False, outputs="none")
    results = scene.run()
    metrics = results.metrics
    assert results.status == "done", results.error
    assert metrics["t_reached"] == 75.0
    assert metrics["theta_c_reached"] == pytest.approx(1.6)
    assert metrics["top_stretch_min"] < CREASE_STRETCH
    assert metrics["self_contact_area"] > 0
    assert metrics["self_contact_penetration_max"] < 0.02 * scene.cortex_thickness
    assert metrics["Je_min"] > 0
    assert metrics["sulci"] >= 1 and metrics["sulcus_depth"] > scene.cortex_thickness
    assert metrics["theta_a_max"] > 1.1


def test_the_plan_names_the_stages_the_settings_lead_through(monkeypatch):
    """The perfect branch's stages (an approach where the analysis places an onset far
    enough ahead), then buckling and equilibrium where the run buckles, then the release."""
    onset_growth = {"value": None}
    monkeypatch.setattr(folding_case, "placing_onset",
                        lambda bilayer, length: onset_growth["value"])
    case = FoldingScene(**{**SMALL, "length": 0.6, "height": 0.2}, buckle=False).build()
    assert case.plan(case.stages()) == ["perfect", "release"]
    case.scene = dataclasses.replace(case.scene, buckle=True)
    branch = case.stages()
    assert case.plan(branch) == ["perfect", "buckling", "equilibrium", "release"]
    assert case.plan(branch, onset=False) == ["perfect", "release"]
    case.scene = dataclasses.replace(case.scene, release=False)
    assert case.plan(branch) == ["perfect", "buckling", "equilibrium"]
    onset_growth["value"] = 1.3                  # t = 37.5 at the default cortex_rate
    assert case.approach_end() == pytest.approx(0.3 / case.scene.cortex_rate
                                                - 2 * case.scene.onset_dt)
    assert case.plan(case.stages()) == ["approach", "perfect", "buckling", "equilibrium"]
