"""Scenes: one module per scene, each a frozen dataclass of parameters with ``run(out)``."""

from ..errors import ParameterError
from .atrophy import AtrophyScene
from .cube import CubeScene
from .custom import CustomScene
from .cylinder import CylinderScene
from .disc import DiscScene
from .folding import FoldingScene
from .hemisphere import HemisphereScene
from .skin import SkinExpansionScene

SCENES = {cls.name: cls for cls in (CubeScene, HemisphereScene, DiscScene, CylinderScene,
                                    SkinExpansionScene, FoldingScene, CustomScene,
                                    AtrophyScene)}


def get_scene(name):
    """The scene class registered under ``name``."""
    if name not in SCENES:
        raise ParameterError(f"unknown scene {name!r}: allowed {', '.join(sorted(SCENES))}")
    return SCENES[name]


__all__ = ["SCENES", "AtrophyScene", "CubeScene", "CustomScene", "CylinderScene", "DiscScene",
           "FoldingScene",
           "HemisphereScene", "SkinExpansionScene", "get_scene"]
