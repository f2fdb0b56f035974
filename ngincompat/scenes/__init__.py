"""Scenes: one per section of the paper (a module, or a package split by concern where the
scene is large: its parameters, its case, its figures), each a frozen dataclass of
parameters with ``run(out)``."""

from ngincompat.errors import ParameterError
from ngincompat.scenes.atrophy import AtrophyScene
from ngincompat.scenes.base import Scene
from ngincompat.scenes.cube import CubeScene
from ngincompat.scenes.custom import CustomScene
from ngincompat.scenes.cylinder import CylinderScene
from ngincompat.scenes.disc import DiscScene
from ngincompat.scenes.folding import FoldingScene
from ngincompat.scenes.hemisphere import HemisphereScene
from ngincompat.scenes.skin import SkinExpansionScene

#: The scene classes by name (``ngincompat run NAME``).
SCENES = {cls.name: cls for cls in (CubeScene, HemisphereScene, DiscScene, CylinderScene,
                                    SkinExpansionScene, FoldingScene, CustomScene,
                                    AtrophyScene)}


def get_scene(name: str) -> type[Scene]:
    """The scene class registered under ``name``."""
    if name not in SCENES:
        raise ParameterError(f"unknown scene {name!r}: allowed {', '.join(sorted(SCENES))}")
    return SCENES[name]


__all__ = ["SCENES", "AtrophyScene", "CubeScene", "CustomScene", "CylinderScene", "DiscScene",
           "FoldingScene",
           "HemisphereScene", "SkinExpansionScene", "get_scene"]
