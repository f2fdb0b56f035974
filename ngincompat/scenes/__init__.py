"""Scenes: one module per scene, each a frozen dataclass of parameters with ``run(out)``."""

from ..errors import ParameterError
from .cube import CubeScene
from .custom import CustomScene

SCENES = {cls.name: cls for cls in (CubeScene, CustomScene)}


def get_scene(name):
    """The scene class registered under ``name``."""
    if name not in SCENES:
        raise ParameterError(f"unknown scene {name!r}: allowed {', '.join(sorted(SCENES))}")
    return SCENES[name]


__all__ = ["SCENES", "CubeScene", "CustomScene", "get_scene"]
