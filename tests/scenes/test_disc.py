"""ngincompat.scenes.disc: area growth of the disc of section 3.3, its Burgers vector against
eq. (22) and its fibers."""

import numpy as np
import pytest

from ngincompat.errors import ParameterError
from ngincompat.scenes import DiscScene


@pytest.fixture(scope="module")
def discs():
    settings = dict(order=2, maxh=0.25)
    return {label: DiscScene(**kwargs, **settings).run() for label, kwargs in {
        "neo-hookean": dict(material="neo-hookean"),
        "radial": dict(fibers="radial"),
        "circumferential": dict(fibers="circumferential")}.items()}


def test_disc_G_does_not_depend_on_the_material(discs):
    """G depends on Fg alone (eq. 10)."""
    values = [(r.metrics["G_error_L2_rel"], r.metrics["burgers_max"])
              for r in discs.values()]
    for v in values[1:]:
        assert v == pytest.approx(values[0], rel=1e-12)
    energies = [r.metrics["strain_energy"] for r in discs.values()]
    assert len({round(e, 12) for e in energies}) == 3


def test_disc_burgers_vector_matches_eq22(discs):
    """b on the plane e3 lies in the plane, orthogonal to grad theta, as eq. (22)."""
    m = discs["radial"].metrics
    assert m["b_out_of_plane"] < 1e-12
    assert m["b_along_grad_theta"] < 0.05
    assert m["b_eq22_error"] < 0.05


def test_disc_radial_stress_vanishes_at_the_rim_and_fibers_differ(discs):
    for r in discs.values():
        assert r.metrics["sigma_r_rim_rel"] < 0.1  # 5e-4 at the scene defaults
    radial, circ = discs["radial"].metrics, discs["circumferential"].metrics
    # Section 3.3: radial fibers carry the radial tension, so stresses and energy are higher
    assert radial["strain_energy"] > circ["strain_energy"]
    assert radial["max_principal_stress"] > circ["max_principal_stress"]


@pytest.mark.parametrize("fibers, direction", [("radial", (0.6, 0.8, 0.0)),
                                               ("circumferential", (-0.8, 0.6, 0.0))])
def test_the_goh_fibers_are_radial_or_circumferential_in_the_plane(fibers, direction):
    """At (0.3, 0.4) (R = 0.5) the fiber family a0 is e_R = (0.6, 0.8, 0) or e_theta =
    (-0.8, 0.6, 0); the profile runs along the radius at mid-height."""
    case = DiscScene(fibers=fibers, maxh=0.5, order=1, g_order=2).build()
    (a0,) = case.fibers
    np.testing.assert_allclose(a0.cf(case.mesh(0.3, 0.4, 0.25)), direction, atol=1e-12)
    assert case.line == ((0.0, 0.0, 0.25), (1.0, 0.0, 0.25), "R")
    assert set(case.components) == {"sigma_r", "sigma_theta"}


def test_a_neo_hookean_disc_has_no_fibers_and_the_discs_moduli():
    case = DiscScene(material="neo-hookean", maxh=0.5, order=1, g_order=2).build()
    assert case.fibers == () and case.material.mu == 0.003
    with pytest.raises(ParameterError, match="fibers = 'spiral'"):
        DiscScene(fibers="spiral")
