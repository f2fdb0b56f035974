"""Stages of a load history: prescribed growth in parts, the coupled stage's loads, and its
checkpoints."""

from types import SimpleNamespace

import ngsolve as ngs
import numpy as np
import pytest
from conftest import cube_problem

from geometries import cube
from ngincompat.errors import ParameterError
from ngincompat.fem.coupled import CoupledProblem
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stages import (
    CoupledStage,
    PrescribedGrowthStage,
    restore_checkpoint,
    save_checkpoint,
)
from ngincompat.fem.terms import GrowthEnergy, VolumeConstraint
from ngincompat.mechanics.laws import StrainDrivenLaw
from ngincompat.mechanics.materials import NeoHookean
from ngincompat.progress import SILENT


def test_growth_in_two_stages_reaches_the_state_of_one():
    """t from 0 to 1 in one stage, or from 0 to 0.4 then 0.4 to 1: the same equilibrium."""
    problem, time = cube_problem(order=2)
    PrescribedGrowthStage("growth", problem, time).run(SILENT)
    one = problem.strain_energy()
    problem, time = cube_problem(order=2)
    first = PrescribedGrowthStage("first", problem, time, t_end=0.4).run(SILENT)
    assert first.t_reached == pytest.approx(0.4) and time.Get() == pytest.approx(0.4)
    second = PrescribedGrowthStage("second", problem, time, t_start=0.4).run(SILENT)
    assert second.converged
    assert [(s.t, s.dt) for s in second.steps] == [(1.0, pytest.approx(0.6))]
    assert problem.strain_energy() == pytest.approx(one, rel=1e-9)
    assert one > 1e-8


def test_growth_from_a_start_state_is_solved_at_once_and_falls_back_to_load_steps():
    """With a start, the equilibrium at t_end is solved from it at once: the unique
    equilibrium of the load-stepped path, in one step. Where Newton fails from the start,
    the state before the stage is restored and the growth applied in load steps."""
    problem, time = cube_problem(order=2)
    stepped = PrescribedGrowthStage("growth", problem, time).run(SILENT)
    reference = problem.u.vec.CreateVector()
    reference.data = problem.u.vec

    # a start near the equilibrium: 90 % of its displacement; the rigid-body pins keep
    # the start's values, so the two states are compared by C = F^T F
    equilibrium = ngs.GridFunction(problem.u.space)
    equilibrium.vec.data = reference
    start = ngs.GridFunction(problem.u.space)
    start.vec.data = 0.9 * reference
    problem.u.vec[:] = 0.0
    time.Set(0.0)
    direct = PrescribedGrowthStage("growth", problem, time, start=start).run(SILENT)
    assert direct.converged and len(direct.steps) == 1
    assert direct.steps[0].t == 1.0 and direct.steps[0].dt == 1.0

    def cauchy_green(u):
        F = ngs.Id(3) + ngs.Grad(u)
        return F.trans * F

    change = cauchy_green(problem.u) - cauchy_green(equilibrium)
    strain = cauchy_green(equilibrium) - ngs.Id(3)
    mesh = problem.u.space.mesh
    assert ngs.Integrate(ngs.InnerProduct(change, change), mesh) <= \
        1e-16 * ngs.Integrate(ngs.InnerProduct(strain, strain), mesh)

    # Newton limited to one iteration cannot converge from u = 0 at full growth
    problem, time = cube_problem(order=2)
    zero = ngs.CoefficientFunction((0, 0, 0))
    fallback = PrescribedGrowthStage("growth", problem, time, start=zero,
                                     start_options=NewtonOptions(max_iter=1)).run(SILENT)
    assert not fallback.steps[0].converged and fallback.steps[0].dt == 1.0
    assert fallback.converged and fallback.t_reached == pytest.approx(1.0)
    assert [(s.t, s.iterations) for s in fallback.steps[1:]] == \
        [(s.t, s.iterations) for s in stepped.steps]
    difference = problem.u.vec.CreateVector()
    difference.data = problem.u.vec - reference
    assert difference.Norm() <= 1e-12 * reference.Norm()


def _holder():
    """A stand-in for a term that holds a volume: its target and the lifts asked for."""
    holder = SimpleNamespace(target=ngs.Parameter(0.0), lifts=[])

    def set_target(volume, lift=False):
        holder.target.Set(volume)
        holder.lifts.append(lift)

    holder.set_target = set_target
    return holder


def test_coupled_stage_drives_the_volume_linearly_and_freezes_growth():
    problem, holder = SimpleNamespace(dt=ngs.Parameter(0.25)), _holder()
    stage = CoupledStage("inflation", problem, t_end=3.0, dt=1.0, t_start=1.0, grow=False,
                         volume=(10.0, 50.0), holder=holder)
    for t, expected in ((1.0, 10.0), (2.0, 30.0), (2.5, 40.0), (3.0, 50.0)):
        stage.load(t)
        assert holder.target.Get() == pytest.approx(expected)
    assert problem.dt.Get() == 0.0
    # the state moves with the expander only going forward, not back after a failed step
    stage.load(2.0)
    assert holder.lifts == [False, True, True, True, False]
    growing = SimpleNamespace(dt=ngs.Parameter(0.25))
    CoupledStage("hold", growing, t_end=7.0, dt=0.5).load(3.0)
    assert growing.dt.Get() == 0.25


def test_coupled_stage_ramps_a_dead_traction_after_its_start():
    """``traction`` scales the problem's dead load linearly over the stage (the contact
    expander's deflation: 1 -> 0), and ``start`` runs once, before the first load."""
    problem = SimpleNamespace(dt=ngs.Parameter(0.25))
    load = SimpleNamespace(scale=ngs.Parameter(0.0))
    started = []

    class Started(Exception):
        pass

    def start():
        started.append(load.scale.Get())
        raise Started

    stage = CoupledStage("deflation", problem, t_end=1.0, dt=0.25, grow=False,
                         traction=(1.0, 0.0), dead_load=load, start=start)
    with pytest.raises(Started):
        stage.run(SILENT)
    assert started == [0.0]
    for t, expected in ((0.0, 1.0), (0.25, 0.75), (0.6, 0.4), (1.0, 0.0)):
        stage.load(t)
        assert load.scale.Get() == pytest.approx(expected)


@pytest.mark.parametrize("missing", [dict(volume=(0.0, 1.0)), dict(traction=(1.0, 0.0))])
def test_a_coupled_stage_that_drives_a_load_needs_its_term(missing):
    with pytest.raises(ParameterError, match="^holder = None|^dead_load = None"):
        CoupledStage("stage", SimpleNamespace(dt=ngs.Parameter(0.0)), t_end=1.0, dt=1.0,
                     **missing)


def _coupled(mesh, order=1):
    """A coupled problem with growth and a volume held under the cube's bottom face."""
    growth = GrowthEnergy("isotropic", None, StrainDrivenLaw(tau=1.0, theta_max=2.0),
                          NeoHookean.from_nu(1.0, 0.3))
    volume = VolumeConstraint("bottom")
    return CoupledProblem(mesh, [growth, volume], order=order, dirichlet="left"), growth, volume


def test_checkpoint_restores_the_state_and_refuses_another_mesh(tmp_path):
    mesh = cube(maxh=1.0)
    problem, growth, volume = _coupled(mesh)
    rng = np.random.default_rng(0)
    problem.state.vec.FV().NumPy()[:] = rng.normal(size=problem.fes.ndof)
    growth.theta_old.vec.FV().NumPy()[:] = 1 + rng.uniform(size=growth.theta_old.space.ndof)
    volume.target.Set(41.5)
    path = tmp_path / "checkpoint.npz"
    assert restore_checkpoint(problem, path) is None
    save_checkpoint(problem, path, 2.5)
    fresh, fresh_growth, fresh_volume = _coupled(mesh)
    assert restore_checkpoint(fresh, path) == 2.5
    assert fresh_volume.target.Get() == 41.5     # an expander's controlled size
    np.testing.assert_array_equal(fresh.state.vec.FV().NumPy(), problem.state.vec.FV().NumPy())
    np.testing.assert_array_equal(fresh_growth.theta_old.vec.FV().NumPy(),
                                  growth.theta_old.vec.FV().NumPy())
    with pytest.raises(ParameterError, match="does not fit this mesh and order"):
        restore_checkpoint(_coupled(mesh, order=2)[0], path)
