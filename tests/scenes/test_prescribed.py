"""ngincompat.scenes.prescribed: the case of every prescribed-growth scene: its Newton solve,
incompatibility without mechanics, its figures, and the locking warning."""

import json

import pytest

from ngincompat.cli import main
from ngincompat.scenes import CubeScene, get_scene
from ngincompat.scenes.prescribed import LOCKING_NU, LOW_ORDER_LOCKING_NU, _axis, _figures


@pytest.mark.slow
@pytest.mark.parametrize("name, settings", [
    ("cube", {}), ("hemisphere", {}), ("hemisphere", {"profile": "concave"}),
    ("hemisphere", {"profile": "convex"}), ("hemisphere", {"flat_face": "symmetry"}),
    ("disc", {}), ("disc", {"fibers": "circumferential"}), ("cylinder", {})])
def test_default_settings_need_at_most_five_newton_iterations_per_load_step(name, settings,
                                                                             ):
    """The solver target of the idealized scenes at their defaults, with a fresh tangent per
    iteration (the default reuses it, trading iterations for tangents; about 4 minutes)."""
    results = get_scene(name)(reuse_tangent=False, **settings).run()
    steps = [s for s in results.solver["growth"].steps if s.converged]
    assert results.converged and steps
    assert max(s.iterations for s in steps) <= 5, [s.iterations for s in steps]


def test_incompatibility_only_builds_no_mechanics(tmp_path, monkeypatch):
    """G depends on Fg alone: asking only for incompatibility never builds the mechanics."""
    from ngincompat.scenes import prescribed

    def forbidden(*args, **kwargs):
        raise AssertionError("a mechanics problem was built")

    monkeypatch.setattr(prescribed, "GrowthMechanics", forbidden)
    code = main(["run", "cube", "--out", str(tmp_path), "--outputs", "incompatibility",
                 "--maxh", "0.5", "-q"])
    assert code == 0
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["solver"] == {} and "strain_energy" not in results["metrics"]
    assert results["metrics"]["G_error_L2_rel"] < 1e-6
    assert results["params"]["mechanics"] is False
    assert "Psi" not in results["profiles"]["line"]
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]
    with pytest.raises(AssertionError, match="mechanics problem was built"):
        main(["run", "cube", "--out", str(tmp_path), "--maxh", "0.5", "-q", "--overwrite"])


@pytest.mark.parametrize("order, nu, warns", [(4, 0.45, False), (4, 0.49, False),
                                              (4, 0.499, True), (4, 0.49999, True),
                                              (2, 0.45, False), (2, 0.49, True)])
def test_the_displacement_formulation_warns_of_locking(order, nu, warns):
    scene = CubeScene(nu=nu, order=order, elements="hex")
    assert bool(scene.trust(None)) == warns
    assert not CubeScene(nu=nu, order=order, formulation="mixed", elements="hex").trust(None)


@pytest.fixture(scope="module")
def coarse_cube_case():
    return CubeScene(maxh=1.0, order=1, g_order=2).build()


def test_the_figures_with_and_without_mechanics(coarse_cube_case):
    """With mechanics: Psi beside Curl Fg : Curl Fg, the Burgers vectors on every plane and
    the stress components, floored at 1e-6 mu and 1e-3 mu; without: the incompatibility
    alone."""
    case = coarse_cube_case
    mu = case.material.mu
    solved = {f.file: f for f in _figures(case.scene, "X1", case, True)}
    assert list(solved) == ["profile.png", "burgers.png", "stress.png"]
    assert solved["profile.png"].curves == {r"$\Psi$": "Psi"}
    assert solved["profile.png"].right == {"Curl Fg : Curl Fg": "curlFg_sq"}
    assert solved["profile.png"].floor == pytest.approx(1e-6 * mu)
    assert solved["stress.png"].floor == pytest.approx(1e-3 * mu)
    assert set(solved["stress.png"].curves) == set(case.components)
    assert set(solved["burgers.png"].curves.values()) == {f"|b_{p}|" for p in case.planes}
    assert solved["burgers.png"].ylabel == "|b| [1/mm]"
    incompatibility = {f.file: f for f in _figures(case.scene, "X1", case, False)}
    assert list(incompatibility) == ["profile.png", "burgers.png"]
    assert incompatibility["profile.png"].curves == {"Curl Fg : Curl Fg": "curlFg_sq"}
    assert incompatibility["profile.png"].title.endswith(": incompatibility")


def test_no_locking_warning_without_mechanics():
    """The locking warning is about the displacement's stress: with the incompatibility alone
    (mechanics = false) there is none, whatever nu."""
    assert CubeScene(nu=0.49999, order=4).trust(None)
    assert CubeScene(nu=0.49999, order=4, mechanics=False).trust(None) == []
    (line,) = CubeScene(nu=0.495, order=3).trust(None)
    assert line.startswith(f"nu = 0.495 >= {LOW_ORDER_LOCKING_NU} in the displacement "
                           "formulation at order 3")
    (line,) = CubeScene(nu=LOCKING_NU, order=4).trust(None)
    assert "--set formulation=mixed" in line


@pytest.mark.parametrize("start, end, axis", [((0, 0.5, 0.5), (1, 0.5, 0.5), 0),
                                              ((0.5, 0, 0.5), (0.5, 2, 0.5), 1),
                                              ((0, 0, 0), (0.3, 0.3, 1), 2)])
def test_the_profile_coordinate_is_the_axis_the_line_runs_along_most(start, end, axis):
    assert _axis(start, end) == axis
