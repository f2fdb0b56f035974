"""Cortical folding (section 3.7, Fig. 7): a growing cortex buckles on a subcortex whose axons
grow when stretched; then the constraints are released.

The bilayer (3 x 1 cm, cortex 0.05 cm) is a body in plane strain, solved on its section
(:func:`geometries.bilayer`, triangles): X1 along its length, X2 vertical, the displacement
(u1, u2), the tensors three-dimensional with F33 = 1; energies, forces and contact lengths
are per unit length out of plane. Growth is fiber growth, eq. (23): in the cortex along e1
at a constant rate, in the subcortex along the axons (curved outward, concentric, straight,
or none) by the stretch-driven law of eq. (45) with gamma = 0, both in one coupled problem;
both layers are neo-Hookean (eq. 36).

The stages (:class:`~ngincompat.scenes.folding.case.FoldingCase`): the perfect branch to the
first negative eigenvalue of the elastic tangent (the onset, checked against the independent
analysis of :mod:`ngincompat.references.bifurcation`); the viscous march past it, whose snaps
a relaxation at held growth passes, with the top surface in frictionless self-contact; the
equilibrium at the end; and the release of the supports, after which the remaining stress
is the incompatibility's.

Modules: :mod:`~ngincompat.scenes.folding.scene` (the parameters, presets and metrics),
:mod:`~ngincompat.scenes.folding.case` (the stages),
:mod:`~ngincompat.scenes.folding.measures` (the measures of the result),
:mod:`~ngincompat.scenes.folding.numerics` (the solver settings) and
:mod:`~ngincompat.scenes.folding.figures`. The model, the stages and the measures in full,
with what was measured of them: ``docs/measurements/folding.md``.
"""

from ngincompat.scenes.folding.case import CREASE_STRETCH, FoldingCase
from ngincompat.scenes.folding.figures import PANELS, panels
from ngincompat.scenes.folding.numerics import SNAP_STEP
from ngincompat.scenes.folding.scene import AXONS, FoldingScene

__all__ = ["AXONS", "CREASE_STRETCH", "PANELS", "SNAP_STEP", "FoldingCase", "FoldingScene",
           "panels"]
