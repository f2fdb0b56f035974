"""ngincompat.scenes.skin.case: the stages of section 3.6 with the pressure model, on coarse
meshes: the pressure is the volume's Lagrange multiplier, so these checks hold it to the volume and
follow it through the deflation (the contact model, the default, is tests/fem/test_contact.py's)."""

import json
import math

import ngsolve as ngs
import numpy as np
import pytest

from ngincompat.errors import ConvergenceError
from ngincompat.fem import buckling
from ngincompat.fem.problem import GrowthMechanics, pin_reactions
from ngincompat.fem.solver import NewtonSolver
from ngincompat.fem.stages import PrescribedGrowthStage
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics.growth import AreaGrowth
from ngincompat.progress import SILENT
from ngincompat.sampling import element_points
from ngincompat.scenes import SkinExpansionScene
from ngincompat.scenes.skin import CLAMP

#: The circle 7 cm across that these checks were set up on (base 38.5 cm^2, not the default),
#: pushed by a uniform pressure (not the default expander).
COARSE = dict(expander="pressure", maxh=2.5, order=2, growth_order=2, g_order=3,
              inflation_steps=5, outputs="none", footprint_area=math.pi * 3.5**2)


@pytest.fixture(scope="module")
def expanded_case():
    """The coarse circle's results and its case (the problems of every stage)."""
    cases = []
    build = SkinExpansionScene.build
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(SkinExpansionScene, "build", lambda scene: cases.append(build(scene))
                      or cases[-1])
        results = SkinExpansionScene(footprint="circle", hold_days=2.0, **COARSE).run()
    return results, cases[0]


@pytest.fixture(scope="module")
def expanded(expanded_case):
    return expanded_case[0]


def test_inflation_meets_the_target_volume(expanded):
    results = expanded
    m = results.metrics
    assert m["volume_error_rel"] < 1e-3
    assert m["pressure_inflated"] > 0
    assert results.solver["inflation"].converged


def test_skin_grows_where_it_is_stretched_and_keeps_residual_stress(expanded):
    results = expanded
    m = results.metrics
    assert m["theta_max"] > 1.05 and m["theta_mean_footprint"] > 1.0
    assert m["burgers_max"] > 10 * m["burgers_apex"]
    assert m["max_principal_stress_released"] > 0
    assert m["strain_energy_released"] < m["strain_energy_clamped"]
    line = results.profile("line")
    theta = np.asarray(line["theta"])
    assert theta[len(theta) // 2] > theta[0] + 0.01  # growth over the expander, not at the edge


def test_the_end_of_hold_field_is_the_held_skin(expanded):
    """``u_end_of_hold`` is the skin at the end of the hold: the volume under it is the
    volume the pressure held (eq. of the enclosed volume, to the volume control's
    tolerance), not the deflated skin's (the clamped state's, a fraction of it)."""
    import ngsolve as ngs

    from ngincompat.fem.terms import enclosed_volume_density

    fields = expanded.fields
    mesh = fields["u_end_of_hold"].space.mesh
    footprint = mesh.Boundaries("footprint")

    def volume(u):
        return ngs.Integrate(enclosed_volume_density(u), mesh, ngs.BND, definedon=footprint)

    held = expanded.params["volume"]
    assert volume(fields["u_end_of_hold"]) == pytest.approx(held, rel=1e-3)
    assert volume(fields["u_clamped"]) < 0.5 * held


def test_interrupted_hold_keeps_its_state_and_resumes(tmp_path, monkeypatch):
    """A step that fails during the hold ends the run with the last converged state on disk;
    running again with resume=true continues from it to the end of the hold."""
    original = NewtonSolver.minimise
    calls = {"hold": 0}

    def failing(self, record):
        if getattr(self.problem, "dt", None) is not None and self.problem.dt.Get() > 0:
            calls["hold"] += 1
            if calls["hold"] > 1:
                record.reason = "simulated failure"
                return False
        return original(self, record)

    monkeypatch.setattr(NewtonSolver, "minimise", failing)
    scene = SkinExpansionScene(footprint="circle", hold_days=2.0, **COARSE)
    with pytest.raises(ConvergenceError, match="simulated failure") as failed:
        scene.run(tmp_path)
    assert failed.value.results.status == "not converged"
    saved = np.load(tmp_path / "checkpoint.npz")
    assert float(saved["t"]) == pytest.approx(1.0)
    written = json.loads((tmp_path / "results.json").read_text())
    assert "resume=true" in written["error"] and written["status"] == "not converged"
    monkeypatch.setattr(NewtonSolver, "minimise", original)
    resumed = SkinExpansionScene(footprint="circle", hold_days=2.0, resume=True,
                                 **COARSE).run(tmp_path)
    hold = resumed.solver["hold"]
    assert hold.converged and hold.t_reached == pytest.approx(2.0)
    assert "inflation" not in resumed.solver
    assert hold.steps[0].t == pytest.approx(2.0)


def test_clamped_and_released_states_are_found_from_the_deflated_one(expanded_case):
    """The expander emptied quasi-statically, then taken out, with the clamp or without: each
    equilibrium found at once from the deflated state. The clamped skin stays bulged above its
    base, in the state that applying the grown field in load steps from u = 0 reaches too (an
    independent path to the same equilibrium); the released skin is self-equilibrated and
    stable."""
    results, case = expanded_case
    # the volume lowered until the pressure no longer holds it, short of an empty expander;
    # what is measured of the inflated skin is the state at the end of the hold
    deflation = results.solver["deflation"]
    assert deflation.converged and 0 < deflation.t_reached < 1
    assert case.holder.pressure() == results.metrics["pressure_end_of_hold"] > 0
    for stage in ("deflation_clamped", "deflation_released"):
        steps = results.solver[stage].steps
        assert len(steps) == 1 and steps[0].converged and steps[0].dt == 1.0
    clamped, released = case.relaxed["clamped"], case.relaxed["released"]
    centre = case.mesh(1e-6, 1e-6, 0.0)
    assert clamped.u(centre)[2] > 0.5
    stepped = GrowthMechanics(case.mesh, clamped.growth, case.material,
                              order=case.scene.order, **CLAMP)
    case.ramp.Set(0.0)
    assert PrescribedGrowthStage("stepped", stepped, case.ramp).run(SILENT).converged
    assert stepped.u(centre)[2] == pytest.approx(clamped.u(centre)[2], rel=1e-6)
    assert stepped.strain_energy() == pytest.approx(clamped.strain_energy(), rel=1e-8)

    # released: the pins hold nothing of the forces removed at once (the residual of the free
    # patch in the deflated state) and no direction lowers the energy
    removed = results.solver["deflation_released"].steps[0].residuals[0]
    assert np.linalg.norm(pin_reactions(released)) <= 1e-8 * removed
    values, _ = buckling.smallest_eigenpairs(released)
    assert values[0] > 0
    assert results.metrics["strain_energy_released"] == pytest.approx(
        released.strain_energy(), rel=1e-12)


def test_the_largest_burgers_vector_is_located_where_it_is_largest(expanded_case):
    """burgers_max_radius is the distance from the centre of the point where |b| takes the
    value burgers_max (it once was that of the largest |b| on the bottom face only, while the
    largest sits on the top surface)."""
    results, case = expanded_case
    m = results.metrics
    G, _, _ = inc.incompatibility_projected(AreaGrowth(case.growth.theta, case.N0).Fg,
                                            case.mesh, COARSE["g_order"])
    b_norm = ngs.Norm(inc.burgers_vector(G, case.N0.cf))
    points = element_points(case.mesh)
    values = np.asarray(b_norm(points)).ravel()
    xyz = np.asarray(ngs.CF((ngs.x, ngs.y, ngs.z))(points)).reshape(-1, 3)
    ring = np.abs(np.hypot(xyz[:, 0], xyz[:, 1]) - m["burgers_max_radius"]) < 1e-9
    assert ring.any()
    assert np.max(values[ring]) == pytest.approx(m["burgers_max"], rel=1e-9)
