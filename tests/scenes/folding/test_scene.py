"""ngincompat.scenes.folding.scene: the folding scene's parameters, their checks against each
other, the axon law and the bilayer of the bifurcation analysis it builds."""

import functools

import ngsolve as ngs
import numpy as np
import pytest
from conftest import FOLDING_CREASING
from scipy.optimize import brentq

from geometries import bilayer, cube
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.mechanics import fields
from ngincompat.mechanics.laws import ConstantRateLaw, StrainDrivenLaw, euler_residual
from ngincompat.scenes.folding import FoldingScene

#: The smallest bilayer seen to crease into self-contact (``conftest.FOLDING_CREASING``).
CREASING = {key: float(value) for key, value in
            (pair.split("=") for pair in FOLDING_CREASING[1::2])}


#: A short, shallow bilayer that buckles like the long one (its substrate is still many
#: cortical thicknesses deep) on a coarse but adequate mesh: two quadratic elements across
#: the cortex.
SMALL = dict(length=1.0, height=0.5, maxh=0.1, cortex_maxh=0.025, axons="none",
             outputs="none")


@functools.cache
def _point():
    """One integration point to evaluate the laws at (the values do not depend on it)."""
    mesh = cube(maxh=1.0)
    return mesh, mesh(0.5, 0.5, 0.5)


def axon_update(theta_old, stretch, dt, rate=0.08):
    """One implicit-Euler step of the axon law (eq. 45, gamma = 0) at a held fiber stretch,
    solved for theta from the residual the coupled problem assembles."""
    law = StrainDrivenLaw(tau=1 / rate, theta_max=3.0, gamma=0.0, theta_crit=1.0)
    point = _point()
    theta = ngs.Parameter(1.0)

    def residual(value):
        theta.Set(value)
        return euler_residual(law, theta, theta_old, dt, stretch)(point[1])

    return brentq(residual, theta_old, stretch, xtol=1e-15)


def test_axon_growth_one_step_matches_the_closed_form_update():
    """theta_{n+1} = (b + sqrt(b^2 + 4 dt G lambda)) / 2, b = theta_n - dt G lambda_crit."""
    assert axon_update(1.0, 1.2, 1.0) == pytest.approx(1.014617, abs=1e-6)
    b = 1.0 - 0.08
    assert axon_update(1.0, 1.2, 1.0) == pytest.approx((b + np.sqrt(b * b + 4 * 0.08 * 1.2)) / 2,
                                                       rel=1e-12)


def test_axon_growth_at_held_stretch_converges_at_first_order():
    """The ODE's solution at a held stretch lambda = 1.2: t(theta) = [(1 - theta) +
    lambda ln((lambda - 1) / (lambda - theta))] / G; implicit Euler approaches it as dt."""
    stretch, rate, t_end = 1.2, 0.08, 9.147
    exact = brentq(lambda th: ((1 - th) + stretch * np.log((stretch - 1) / (stretch - th)))
                   / rate - t_end, 1.0, 1.1999)
    errors = []
    for steps in (8, 16, 32):
        theta = 1.0
        for _ in range(steps):
            theta = axon_update(theta, stretch, t_end / steps, rate)
        errors.append(abs(theta - exact))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert exact == pytest.approx(1.10, abs=1e-3)
    np.testing.assert_allclose(rates, 1.0, atol=0.1)


@pytest.mark.parametrize("setting, message", [
    (dict(axons="wavy"), "axons = 'wavy'.*curved, concentric, straight, none"),
    (dict(cortex_maxh=0.04), "cortex_maxh = 0.04.*<= cortex_thickness / 2"),
    (dict(order=1), "order = 1.*allowed 2 \\(quadratic"),
    (dict(order=3), "order = 3.*allowed 2 .*element-internal dofs"),
    (dict(cortex_thickness=1.0), "cortex_thickness = 1.0.*in \\(0, height = 1\\)"),
    (dict(cortex_rate=0.0), "cortex_rate = 0.0.*in \\[1e-06, "),
    (dict(length=0.001), "length = 0.001.*>= cortex_thickness = 0.05"),
])
def test_bad_settings_name_the_parameter_and_its_range(setting, message):
    with pytest.raises(ParameterError, match=message):
        FoldingScene(**setting)


def test_the_command_line_offers_every_axon_field(capsys):
    """The command line spells the axon fields out (it imports no NGSolve to parse): the
    same as the library's, and a wrong one is refused."""
    assert main(["folding", "--help"]) == 0
    assert "all of " + ", ".join(fields.AXONS) in " ".join(capsys.readouterr().out.split())
    assert main(["folding", "--out", "x", "--axons", "spiral"]) == 2


def test_the_refined_top_is_meshed_finer_than_the_cortex_below():
    """``top_maxh`` refines the top surface: its segments are shorter than those of the
    interface by about cortex_maxh / top_maxh = 4; a size above cortex_maxh is refused."""
    def mean_length(mesh, name):
        length = ngs.Integrate(1.0, mesh, ngs.BND, definedon=mesh.Boundaries(name))
        count = sum(1 for el in mesh.Elements(ngs.BND) if mesh.GetBoundaries()[el.index] == name)
        return length / count

    mesh = bilayer(length=0.4, height=0.2, cortex=0.05, maxh=0.1,
                   cortex_maxh=0.025, top_maxh=0.00625)
    assert {el.type for el in mesh.Elements(ngs.VOL)} == {ngs.ET.TRIG}
    assert mean_length(mesh, "top") == pytest.approx(0.00625, rel=0.25)
    assert mean_length(mesh, "interface") > 3 * mean_length(mesh, "top")
    with pytest.raises(ParameterError, match="top_maxh"):
        bilayer(length=0.4, height=0.2, cortex=0.05, maxh=0.1, cortex_maxh=0.025,
                top_maxh=0.05)


def test_the_bifurcation_analysis_gets_the_same_bilayer():
    """Heights and moduli of the analysis' bilayer from the scene's: mu_gray = mu_ratio
    mu_white, lambda = lam_ratio mu in each layer."""
    scene = FoldingScene(height=0.8, cortex_thickness=0.1, cortex_maxh=0.05, mu_white=2.0,
                         mu_ratio=4.0, lam_ratio=50.0)
    assert scene.mu_gray == 8.0
    b = scene.bifurcation_bilayer()
    assert (b.height, b.cortex) == (0.8, 0.1)
    assert (b.mu_cortex, b.lam_cortex, b.mu_sub, b.lam_sub) == (8.0, 400.0, 2.0, 100.0)


def test_the_axon_law_is_stretch_driven_with_the_scenes_rates_or_none():
    law = FoldingScene(axon_rate=0.04, axon_max=2.0, stretch_crit=1.1).axon_law()
    assert isinstance(law, StrainDrivenLaw)
    assert (law.tau, law.theta_max, law.gamma, law.theta_crit) == (25.0, 2.0, 0.0, 1.1)
    assert FoldingScene(axons="none").axon_law() == ConstantRateLaw(0.0)


def test_the_top_is_refined_by_top_refinement_and_meshed_as_triangles():
    """top_maxh = cortex_maxh / top_refinement; a refined top raises the estimated mesh."""
    plain, refined = FoldingScene(), FoldingScene(top_refinement=4.0)
    assert plain.top_maxh == plain.cortex_maxh
    assert refined.top_maxh == pytest.approx(plain.cortex_maxh / 4)
    (few, shape), (more, _) = plain.mesh_estimate(), refined.mesh_estimate()
    assert shape == "triangle" and more > few


@pytest.mark.parametrize("setting, message", [
    (dict(dt=0.0074), r"^dt = 0\.0074 .* >= t_end / 10000 = 0\.0075"),
    (dict(onset_dt=0.0074), r"^onset_dt = 0\.0074 .* >= t_end / 10000"),
    (dict(approach_dt=0.001, t_end=20.0), r"^approach_dt = 0\.001 .* >= t_end / 10000 = 0\.002"),
    (dict(cortex_maxh=0.2), r"^cortex_maxh = 0\.2 .* in \(0, maxh = 0\.15\]"),
])
def test_steps_and_mesh_sizes_are_checked_against_each_other(setting, message):
    with pytest.raises(ParameterError, match=message):
        FoldingScene(**setting)


def test_observe_dt_zero_records_every_step_and_is_allowed():
    assert FoldingScene(observe_dt=0.0).observe_dt == 0.0
