"""ngincompat.scenes.atrophy.figures: the figures of a run with and without mechanics, in the
scene's units, reading the series the case records."""

import pytest
from scenes.atrophy.test_scene import SMALL

from ngincompat.scenes import AtrophyScene
from ngincompat.scenes.atrophy.figures import figures
from ngincompat.scenes.atrophy.tissues import PLANES


def by_file(scene, mechanics):
    return {f.file: f for f in figures(scene, mechanics)}


def test_without_mechanics_only_transport_growth_and_incompatibility_are_drawn():
    scene = AtrophyScene(seed="uniform")
    assert list(by_file(scene, False)) == ["spreading.png", "volume_theta.png", "profile.png",
                                           "sections.png"]
    assert list(by_file(scene, True)) == ["spreading.png", "volume_theta.png", "profile.png",
                                          "volume_loss.png", "stress.png", "brain.png",
                                          "depth.png", "sections.png"]


@pytest.mark.parametrize("mechanics", [False, True])
def test_the_sections_map_each_plane_with_arrows_for_its_burgers_vector(mechanics):
    """Three planes through the centre, theta and |b| on each (the largest principal stress
    with mechanics); the arrows on the |b| maps are b's in-plane components."""
    maps = by_file(AtrophyScene(), mechanics)["sections.png"]
    keys = ("theta", "|b|", "sigma_max_principal") if mechanics else ("theta", "|b|")
    assert sorted(maps.curves.values()) == sorted(f"{p}_{k}" for p in PLANES for k in keys)
    assert sorted(maps.arrows.values()) == [f"{p}_b_inplane" for p in PLANES]
    for label, key in maps.arrows.items():
        assert maps.curves[label].endswith("|b|") and maps.curves[label][:2] == key[:2]
    assert all(label.endswith("through the centre") for label in maps.curves)
    assert "[1/cm]" in next(iter(maps.arrows))


def test_the_front_is_drawn_only_for_a_seed_with_a_centre():
    assert by_file(AtrophyScene(seed="uniform"), False)["spreading.png"].right == {}
    seeded = by_file(AtrophyScene(), False)["spreading.png"]
    assert seeded.right == {"front radius": "front_radius"}
    assert seeded.right_label == "front radius (c >= 1/2) [cm]"
    assert seeded.xlabel == "t [yr]" and seeded.ylabel == "int c dV [cm$^3$]"


def test_the_surface_is_seen_from_the_side_of_its_hemisphere():
    assert by_file(AtrophyScene(), True)["brain.png"].view == (10.0, 90.0)
    right = AtrophyScene(geometry="mni152", seed="uniform", hemisphere="right")
    assert by_file(right, True)["brain.png"].view == (10.0, -90.0)


def test_the_stress_floor_follows_the_softer_tissue():
    scene = AtrophyScene(mu_gray=2.0, mu_white=0.5)
    assert by_file(scene, True)["stress.png"].floor == pytest.approx(5e-4)


def test_the_time_series_figures_read_what_the_case_records():
    """The series the case records from its first state on: int c dV, the front radius and
    the volume loss from theta per tissue and in total."""
    case = AtrophyScene(maxh=2.0, seed="0,0,-1.5", **SMALL).build()
    figs = by_file(case.scene, False)
    for name in ("spreading.png", "volume_theta.png"):
        fig = figs[name]
        assert fig.profile == "series"
        assert {*fig.curves.values(), *fig.right.values()} <= set(case.series)
    assert set(figs["volume_theta.png"].curves.values()) == {
        "total_volume_loss_theta", "gray_volume_loss_theta", "white_volume_loss_theta"}
