"""Brain atrophy (section 3.5): misfolded-protein spreading drives gray/white shrinkage.

Per time step, staggered and one-way (the mechanics does not act back on the transport):

1. **transport**: the misfolded-protein concentration c on the reference brain follows the
   Fisher-KPP equation (:mod:`ngincompat.fem.transport`), D = d_ext I + d_axn n (x) n with n
   radial in white matter (axons) and d_axn = 0 in gray, no flux through the surface, a smooth
   seed c0 exp(-|X - Xs|^2 / (2 s^2)) or a uniform c0;
2. **atrophy**: theta of isotropic growth Fg = theta^(1/3) I (eq. 13) decreases where c is,
   faster in gray than in white matter, towards theta_min (:mod:`ngincompat.mechanics.atrophy`;
   exact update, so theta never passes theta_min);
3. **mechanics**: quasi-static, traction-free (rigid-body motions removed), neo-Hookean per
   tissue, nearly incompressible through the mixed formulation, whose constraint acts on
   Je = J / theta (so J -> theta, not 1).

Because the coupling is one-way and the material is hyperelastic, the equilibrium at a time
depends only on theta at that time: it is solved at ``snapshots`` equally spaced times or at
the chosen ``times`` (each a stage of the pipeline, started from the previous equilibrium
with theta ramped between them), while c and theta are marched with ``dt``; with VTK output
each of these times is also a frame of the time series ``fields.pvd``. Volumes: total,
gray and white volume loss 1 - int J dV / V0 at the snapshots; 1 - int theta dV / V0 and
int c dV at every step.

Geometry: the idealized ellipsoid with a gray shell (tetrahedra), a hemisphere of fsaverage
(the cortex as layers of prisms between its white and pial surfaces,
:mod:`geometries.fsaverage_brain`), the MNI152 template or a user's NIfTI label image
(hexahedra on coarsened voxels, or six tetrahedra per voxel with ``elements = tet``,
:mod:`geometries.voxel_brain`), or a user's Netgen mesh with materials gray and white. On a
real brain the axons of d_axn are still radial from the origin (no tractography); d_axn = 0
by default.

Parameters and their sources (the paper gives none; every value is a choice, see
docs of the brain scenes): d_ext = 1.5 mm^2/yr and alpha = 0.6 /yr as used in
reimplementations of Weickenmeier, Jucker, Goriely & Kuhl, J. Mech. Phys. Solids 124 (2019)
264; c0 = 0.1 in the seed as in that paper's 1-D test; theta_min = 0.7 from the paper's
"maximum volume loss about 30 %"; rate_gray = 0.03 /yr (about 29 % gray loss in 40 years) and
rate_white = 0.001 /yr ("white matter undergoes almost no shrinkage"); mu = 1 kPa in both
tissues (stresses then read in units of mu) and nu = 0.49 (nearly incompressible).

Modules: :mod:`~ngincompat.scenes.atrophy.scene` (the parameters),
:mod:`~ngincompat.scenes.atrophy.case` (the stages and the measures),
:mod:`~ngincompat.scenes.atrophy.tissues` and :mod:`~ngincompat.scenes.atrophy.figures`.
"""

from ngincompat.scenes.atrophy.case import AtrophyCase
from ngincompat.scenes.atrophy.scene import GEOMETRIES, AtrophyScene

__all__ = ["GEOMETRIES", "AtrophyCase", "AtrophyScene"]
