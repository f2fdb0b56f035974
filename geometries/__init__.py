"""Geometry builders: one typed function per geometry, returning an NGSolve mesh whose
boundaries and materials all carry names.

Every builder takes its dimensions as keywords with the paper's values as defaults, ``maxh``
and ``curve_order``, validates them (a :class:`ngincompat.errors.ParameterError` names the
parameter and its range) and returns a curved tetrahedral mesh; the cube can also be
hexahedral, and the bilayer is a plane section (a mesh of triangles) of a body in plane
strain. Lengths are in the unit of the scene (mm for the idealized scenes, cm for skin and
brain).
"""

from .bilayer import bilayer
from .brain import brain, brain_geometry
from .cube import cube
from .cylinder import cylinder
from .disc import disc
from .hemisphere import hemisphere
from .skin_patch import FOOTPRINTS, footprint_area, footprint_size, skin_patch

#: The geometry builders by name.
BUILDERS = {"cube": cube, "hemisphere": hemisphere, "disc": disc, "cylinder": cylinder,
            "skin_patch": skin_patch, "bilayer": bilayer, "brain": brain}

#: The builders of three-dimensional bodies (the bilayer's is a section).
SOLIDS = {name: builder for name, builder in BUILDERS.items() if name != "bilayer"}

__all__ = ["BUILDERS", "FOOTPRINTS", "SOLIDS", "bilayer", "brain", "brain_geometry", "cube",
           "cylinder", "disc", "footprint_area", "footprint_size", "hemisphere", "skin_patch"]
