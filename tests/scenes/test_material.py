"""ngincompat.scenes.material: the shared material declarations, their ranges at the edges,
and the narrower range a material checks when a scene builds it."""

from dataclasses import dataclass

import pytest

from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene, CustomScene, DiscScene
from ngincompat.scenes.material import MU, Elastic, Fibers


def test_the_blocks_default_to_the_papers_idealized_material():
    """mu = 0.55 MPa, nu = 0.4 (sections 3.1-3.4); GOH fibers k1 = k2 = 1, aligned."""
    assert (Elastic().mu, Elastic().nu) == (0.55, 0.4)
    assert (Fibers().k1, Fibers().k2, Fibers().kappa) == (1.0, 1.0, 0.0)


def test_a_scene_with_its_own_default_keeps_the_declarations_help_unit_and_range():
    """The disc calls MU(0.003): its default differs, what the declaration says does not."""
    cube, disc = CubeScene.declarations()["mu"], DiscScene.declarations()["mu"]
    assert (cube.default, disc.default) == (0.55, 0.003)
    assert cube.help == disc.help == MU.help == "shear modulus"
    assert cube.unit == disc.unit == "stress"
    assert CubeScene.unit_of(cube.unit) == "MPa"
    assert cube.allowed() == disc.allowed() == "in [1e-06, 1e6]"


def test_a_dataclass_inheriting_the_block_has_its_fields():
    @dataclass(frozen=True)
    class Block(Elastic):
        other: int = 1

    block = Block(nu=0.3)
    assert (block.mu, block.nu, block.other) == (0.55, 0.3, 1)


@pytest.mark.parametrize("cls, setting", [
    (CubeScene, dict(nu=-0.99)),            # the closed lower end of nu
    (CubeScene, dict(nu=0.4999)),           # just below the open upper end
    (CubeScene, dict(mu=1e-6)),             # MODULUS_FLOOR
    (DiscScene, dict(kappa=1 / 3)),         # isotropic dispersion
    (DiscScene, dict(k2=100.0)),
    (DiscScene, dict(k1=0.0)),              # no fibers
])
def test_values_at_the_ends_of_the_ranges_are_accepted(cls, setting):
    scene = cls(**setting)
    for key, value in setting.items():
        assert getattr(scene, key) == value


@pytest.mark.parametrize("cls, setting, message", [
    (CubeScene, dict(nu=-0.991), r"^nu = -0.991 is out of range: allowed in \[-0.99, 0.5\)"),
    (CubeScene, dict(nu=0.5), r"^nu = 0.5 is out of range"),
    (CubeScene, dict(mu=9.9e-7), r"^mu = 9.9e-07 is out of range: allowed in \[1e-06, 1e6\]"),
    (DiscScene, dict(kappa=0.334), r"^kappa = 0.334 is out of range: allowed in \[0, 1/3\]"),
    (DiscScene, dict(k2=100.01), r"^k2 = 100.01 is out of range"),
    (DiscScene, dict(k1=-1e-9), r"^k1 = -1e-09 is out of range"),
])
def test_values_just_past_the_ends_are_refused_naming_the_parameter(cls, setting, message):
    with pytest.raises(ParameterError, match=message):
        cls(**setting)


def test_goh_allows_less_than_the_declaration_and_says_so_when_built():
    """NU allows negative ratios; GOH (the disc's default material, custom's on request) only
    (0, 0.5), checked in ``__post_init__``; neo-Hookean keeps the declared range."""
    assert CubeScene(nu=-0.5).nu == -0.5
    assert DiscScene(material="neo-hookean", nu=-0.5).nu == -0.5
    for make in (lambda: DiscScene(nu=-0.5), lambda: DiscScene(nu=0.0),
                 lambda: CustomScene(material="goh", nu=-0.5)):
        with pytest.raises(ParameterError, match=r"nu = .* allowed in \(0, 0.5\) for GOH"):
            make()
