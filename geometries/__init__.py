"""Geometry builders: one typed function per geometry, returning an NGSolve mesh whose
boundaries and materials all carry names.

Lengths are in the unit of the scene (mm for the paper's idealized scenes).
"""

from .cube import cube

BUILDERS = {"cube": cube}

__all__ = ["BUILDERS", "cube"]
