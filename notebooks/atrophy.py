# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Brain atrophy: misfolded protein spreads, gray matter shrinks
#
# Lee, Holland, Weickenmeier, Gosain, Buganza Tepole, *The Geometry of Incompatibility in
# Growing Soft Tissues*, J. Mech. Phys. Solids 146 (2021) 104177, section 3.5 and Fig. 5.
#
# A misfolded protein, seeded at the base of an idealized brain (an ellipsoid of white matter
# in a 3 mm shell of gray matter), spreads and multiplies by the Fisher-Kolmogorov equation
# dc/dt = Div(D Grad c) + alpha c (1 - c). Where it is, tissue is lost: isotropic growth
# Fg = theta^(1/3) I (eq. 13) with theta < 1, gray matter up to thirty times faster than
# white, never below theta_min = 0.7 (the paper's "maximum volume loss about 30 %"). The
# loss differs across the gray/white interface, so the shrinkage is incompatible: the body
# keeps a residual stress although nothing loads it, and the Burgers vectors b = G^T n
# (eq. 11) concentrate at the interface.
#
# The paper gives no parameters for this scene: each value is a documented choice (see the
# scene's docstring and `ngincompat list -v`). One call runs the `atrophy` scene (the same as
# `ngincompat run atrophy`); with `NGINCOMPAT_COARSE=1` (the tests) it runs a smaller brain
# for ten years instead of the adult brain for forty.

# %%
import os

from IPython.display import display

from ngincompat.scenes import AtrophyScene
from ngincompat.workflow import plots

# %matplotlib inline
COARSE = os.environ.get("NGINCOMPAT_COARSE") == "1"
scene = (AtrophyScene(semi_axes="3,2.5,2", gray_thickness=0.5, seed="0,0,-2", d_ext=0.05,
                      t_end=10.0, dt=1.0, snapshots=1, g_order=2)
         if COARSE else AtrophyScene())
print(scene.describe())

results = scene.run()  # transport, atrophy, equilibria, G and b, stresses: nothing is written

# %% [markdown]
# The metrics, in the scene's units (cm, years, kPa with mu = 1 kPa: stresses read in units
# of the shear modulus):

# %%
m = results.metrics
for key, value in m.items():
    print(f"  {key:28s} {value:11.4e}")
figures = {spec.file: spec for spec in results.figures}

# %% [markdown]
# ## Spreading and volume loss over time
#
# The protein mass int c dV grows logistically while the front (c >= 1/2) moves away from
# the seed; the volume loss 1 - int J dV / V0 is largest in gray matter and stays small in
# white.

# %%
display(plots.figure(results, figures["spreading.png"]))
display(plots.figure(results, figures["volume_loss.png"]))

# %% [markdown]
# ## Fig. 5: three sections
#
# theta, the largest |b| over the planes normal to e1, e2, e3, and the maximum principal
# Cauchy stress on the sections X1 = 0, X2 = 0 and X3 = 0. |b| and the stress sit at the
# gray/white interface, where theta jumps.

# %%
display(plots.figure(results, figures["sections.png"]))

# %% [markdown]
# ## Along +X1 from the centre
#
# The same key names as the hemisphere's profile: R, theta, sigma_rr, sigma_thetatheta,
# burgers (here with c).

# %%
display(plots.figure(results, figures["profile.png"]))
display(plots.figure(results, figures["stress.png"]))

# %% [markdown]
# ## Checks
#
# The released body carries no net force: int sigma dv vanishes relative to int |sigma| dv;
# the volume from J agrees with the volume from theta up to the elastic volume change
# |Je - 1|, which the nearly incompressible material keeps small; gray matter loses far more
# than white.

# %%
print(f"|int sigma dv| / int |sigma| dv = {m['equilibrium_residual_rel']:.2e}")
print(f"|int J - int theta| / V0 = {m['volume_bookkeeping_error']:.2e} "
      f"<= max |Je - 1| = {m['Je_deviation_max']:.2e}")
assert m["gray_volume_loss"] > 5 * m["white_volume_loss"] > 0
assert m["volume_bookkeeping_error"] <= m["Je_deviation_max"]
assert m["c_min"] >= 0 and m["theta_min_reached"] > scene.theta_min

# %% [markdown]
# ## The anatomical brain: fsaverage
#
# The left hemisphere of FreeSurfer's fsaverage (its pial and white surfaces ship with
# nilearn, `pip install -e ".[brain]"`): the cortex is two layers of prisms between the
# white and pial triangles, so it is resolved by construction; the white matter is filled by
# Netgen. Tau is seeded in the entorhinal cortex, where the tangles of Alzheimer's disease
# first appear (Braak & Braak 1991). The depth profile compares the mean stress at the
# gray/white interface with that at the outer surface, the paper's finding (Fig. 5e). With
# `NGINCOMPAT_COARSE=1` only four years are run and the mechanics is left out (the mesh has
# no coarser version).

# %%
brain = (AtrophyScene(geometry="fsaverage", t_end=4.0, dt=1.0, snapshots=1, mechanics=False)
         if COARSE else AtrophyScene(geometry="fsaverage"))
anatomy = brain.run()
a = anatomy.metrics
print(f"gray {a['gray_volume']:.1f} cm^3, white {a['white_volume']:.1f} cm^3, "
      f"off the surfaces' volumes by {a['volume_surface_deviation']:.1e}")
print(f"elements across the cortex: min {a['cortex_elements_across_min']:.2f}, "
      f"median {a['cortex_elements_across_median']:.2f}")
print(f"share of int |b| within one cortical thickness ({a['cortex_thickness']:.3f} cm) of "
      f"the interface: {a['burgers_interface_fraction']:.3f} "
      f"(of the volume: {a['interface_band_volume_fraction']:.3f})")
if "stress_interface_over_surface" in a:
    print(f"mean stress at the interface / at the surface: "
          f"{a['stress_interface_over_surface']:.2f}")
shown = {spec.file: spec for spec in anatomy.figures}
for name in ("brain.png", "depth.png", "sections.png"):
    if name in shown:
        display(plots.figure(anatomy, shown[name]))
assert a["volume_surface_deviation"] < 0.02 and a["cortex_elements_across_median"] >= 2
