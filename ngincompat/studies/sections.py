"""The paper's result sections 3.1-3.7 and the runs each of them needs (``ngincompat
paper``, its figures and its report)."""

from __future__ import annotations

from dataclasses import dataclass

from ngincompat import names
from ngincompat.scenes import (
    AtrophyScene,
    CubeScene,
    CylinderScene,
    DiscScene,
    FoldingScene,
    HemisphereScene,
    SkinExpansionScene,
)


@dataclass(frozen=True)
class Section:
    """A result section of the paper: its number, title, and the cases it runs as
    (label, scene class, settings of the variant)."""

    number: str
    title: str
    cases: tuple


SECTIONS = (
    Section("3.1", "Isotropic volume growth driven by a unidirectional field",
            (("cube", CubeScene, {}),)),
    Section("3.2", "Isotropic volume growth driven by a multi-directional vector field",
            (("hemisphere-linear", HemisphereScene, dict(profile="linear")),
             ("hemisphere-concave", HemisphereScene, dict(profile="concave")),
             ("hemisphere-convex", HemisphereScene, dict(profile="convex")),
             ("hemisphere-linear-symmetry", HemisphereScene,
              dict(profile="linear", flat_face="symmetry")))),
    Section("3.3", "Transversely isotropic area growth",
            (("disc-radial", DiscScene, dict(fibers="radial")),
             ("disc-circumferential", DiscScene, dict(fibers="circumferential")))),
    Section("3.4", "Uniaxial fiber growth", (("cylinder", CylinderScene, {}),)),
    Section("3.5", "Brain atrophy", (("atrophy", AtrophyScene, {}),)),
    Section("3.6", "Area growth induced by skin expansion",
            tuple((f"skin-{f}", SkinExpansionScene, dict(footprint=f))
                  for f in names.FOOTPRINTS)),
    Section("3.7", "Axon growth in brain development",
            tuple((f"folding-{a}", FoldingScene, dict(axons=a))
                  for a in names.AXONS)),
)
NUMBERS = tuple(s.number for s in SECTIONS)
