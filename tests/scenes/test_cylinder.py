"""ngincompat.scenes.cylinder: fiber growth of the cylinder of section 3.4, relieved by a
stress-free rotation, and its Burgers vector against eq. (27)."""

import json

import numpy as np
import pytest

from ngincompat.cli import main
from ngincompat.scenes import CylinderScene


@pytest.fixture(scope="module")
def cylinders():
    return [CylinderScene(order=p, maxh=h).run() for p, h in ((2, 0.4), (3, 0.25))]


def test_cylinder_energy_vanishes_and_Fe_becomes_a_rotation(cylinders):
    """Section 3.4: the exact solution is stress-free, Fe a rotation about e3 by -a X1."""
    coarse, fine = (r.metrics for r in cylinders)
    assert fine["strain_energy"] < 0.05 * coarse["strain_energy"]
    assert fine["Fe_rotation_deviation"] < 0.5 * coarse["Fe_rotation_deviation"]
    assert fine["Fe_rotation_deviation"] < 1e-2
    assert fine["rotation_rate"] == pytest.approx(fine["rotation_rate_expected"], rel=1e-2)


def test_cylinder_burgers_vector_eq27(cylinders):
    """|b| on e3 = |grad theta| / theta (beta = 90 deg): 1/4 at the bottom (X2 = 0), falling as
    1/theta to 1/5 at the top."""
    r = cylinders[1]
    assert r.metrics["b_eq27_error"] < 1e-6
    line = r.profile("line")
    X2 = np.asarray(line["X2"])
    # the end points are nudged 1e-4 of their distance inward to find their element
    np.testing.assert_allclose(line["|b_e3|"], 0.25 / (1 + X2 / 4), rtol=2e-4)
    assert X2[0] == pytest.approx(0.0) and X2[-1] == pytest.approx(1.0)


def test_cylinder_without_a_gradient_is_compatible_and_unrotated():
    """a = 0: theta = 1 everywhere, so Curl Fg = 0, b = 0 (eq. 27) and Fe = I; the error of
    eq. (27) is then absolute (its scale, the largest |b|, is 0)."""
    results = CylinderScene.from_settings({"a": 0}, preset="preview").run()
    assert results.status == "done"
    m = results.metrics
    assert m["b_eq27_error"] == 0.0
    assert m["G_error_L2_rel"] == 0.0
    assert abs(m["rotation_rate"]) < 1e-12
    assert m["Fe_rotation_deviation"] < 1e-12


def test_incompatibility_only_keeps_the_scene_checks(tmp_path):
    results = main(["run", "cylinder", "--out", str(tmp_path), "--outputs", "incompatibility",
                    "--order", "2", "--maxh", "0.4", "-q"])
    assert results == 0
    metrics = json.loads((tmp_path / "results.json").read_text())["metrics"]
    assert metrics["b_eq27_error"] < 1e-6
    assert "Fe_rotation_deviation" not in metrics
