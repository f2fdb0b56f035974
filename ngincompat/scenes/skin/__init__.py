"""Skin expansion (section 3.6): inflation, a week of area growth, deflation and release.

Stages (lengths in cm, volumes in cm^3 = cc, stresses in MPa, time in days):

1. **inflation** to ``volume`` cc, volume-controlled: with ``expander=contact`` (the
   default) the expander is a rigid dome (:mod:`ngincompat.fem.contact`) on which the skin
   rests (penalty contact, frictionless), raised until its own volume is the target, then
   (stage ``contact``) resized by secant steps until the volume under the skin is the
   target to 1e-4; with ``expander=pressure`` (kept for comparison) the expander pressure
   is the unknown conjugate to the volume under the footprint, so the target is met, not
   guessed;
2. **hold** for ``hold_days`` at that volume (the contact model: at that expander) while the
   skin grows in area about its normal N0 = e3 (Hill law, eq. 46, implicit Euler, eq. 48);
3. **deflation**: the expander is emptied, the periphery still clamped, at frozen growth,
   quasi-statically until the load that holds the skin up has mostly gone: the pressure
   model lowers the volume (the pressure follows); the contact model hands the dome's
   contact force over to a dead traction on the footprint (the dome lowered under the
   skin) and takes that traction down in proportion. The clamped patch's equilibrium
   without the expander, found from there, has the residual stress of the clamped patch;
4. **release**: the clamp is removed too (rigid-body constraints only): what stress remains is
   due to the incompatibility of the grown skin alone (found from the deflated state).

With VTK output the run is also a time series (``fields.pvd``, :mod:`ngincompat.workflow.frames`)
of the displacement, theta, J and Je = J / theta after every converged step, on one clock in
days that is the hold's time: the inflation's steps at s - 1 (s the fraction of the volume,
its end, after the contact stage's correction, at 0), the hold's at t in (0, ``hold_days``],
the deflation's at ``hold_days`` + s (s in (0, 1], the fraction of the load taken away), the
clamped equilibrium at ``hold_days`` + 2 and the released one at ``hold_days`` + 3.

The patch lies on its base: outside the footprint the bottom face keeps X3 = 0 (it may slide),
which also keeps the footprint's edge in the plane, so the enclosed volume is exactly
int x3 det(dx_a/dX_b) dA over the footprint. The contact model (the default) lifts a dome of
the footprint's shape under the skin, and the volume under the skin exceeds the dome's where
the skin bridges it and falls short by the penetration, hence the volume control; the
pressure model pushes the footprint with a uniform pressure (the expander's shape is not
modelled: growth and stress then concentrate at the footprint's edge, not at the apex). Every
footprint has the base area ``footprint_area`` (the paper's comparison of shapes).

Parameters and their sources:

* neo-Hookean skin with mu = 0.55 MPa, nu = 0.4: section 3.6 takes "the neo-Hookean model of
  our previous work [77]", the reference section 3.1 gives these values with (the deviation
  table, :mod:`ngincompat.studies.deviations`, has the effect against the earlier
  mu = 0.1786 MPa, E = 0.5 MPa of Buganza Tepole et al., J. Mech. Phys. Solids 59 (2011)
  2177);
* Hill law k = 0.1 / day, K = 0.2, n = 2, theta_crit = 1.05: our choice; k lies in the range
  0.02-0.08 / hour calibrated on porcine expansion by Tac et al. (2022, Bayesian calibration
  of tissue expansion, PMC8678288) divided by a factor that accounts for the growth stimulus
  in that model being the full elastic area stretch, and gives area growth of tens of
  percent in a week, the range the paper reports.

Modules: :mod:`~ngincompat.scenes.skin.scene` (the parameters, presets and metrics),
:mod:`~ngincompat.scenes.skin.case` (the stages), :mod:`~ngincompat.scenes.skin.measures`
(what is measured at the apex and under the expander) and
:mod:`~ngincompat.scenes.skin.figures`. What was measured of the scene and its choices:
``docs/measurements/skin.md``.
"""

from ngincompat.scenes.skin.case import CHECKPOINT, CLAMP, SkinCase
from ngincompat.scenes.skin.scene import CONTACT_METRICS, EXPANDERS, SkinExpansionScene

__all__ = ["CHECKPOINT", "CLAMP", "CONTACT_METRICS", "EXPANDERS", "SkinCase",
           "SkinExpansionScene"]
