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
# # Cortical folding (section 3.7)
#
# A thin cortex grows along its length (fiber growth along e1, theta_c = 1 + 0.008 t, t in
# days) on a softer subcortex (mu_gray / mu_white = 3) whose axons grow when stretched
# (eq. 45: d theta_a/dt = G_axn <lambda_e - 1>). The ends are on rollers, the bottom too, and
# the bilayer is in plane strain, solved on its section. At a critical growth the flat state
# loses stability: the bilayer buckles into folds. Axes: the paper's, X1 along the length,
# X2 vertical, X3 out of plane.
#
# One call runs the `folding` scene for each axon field (`ngincompat folding`): the flat
# branch with the smallest eigenvalue of the tangent after every step, the onset where it
# crosses zero, then the folds, grown from the buckling mode with a viscous regularisation;
# then the incompatibility of the grown state. With `NGINCOMPAT_COARSE=1` (the tests) it is
# one axon field on a 1 x 0.6 cm bilayer with a 0.1 cm cortex (two quadratic elements across
# it), a coarse subcortex and 10-day steps, grown to 42 days, just past the onset, without the
# release; without, the three axon fields at the scene's defaults: the paper's 3 x 1 cm
# bilayer with its 0.05 cm cortex grown for the paper's 75 days and released at the end
# (minutes per axon field: docs/measurements/folding.md, "The paper's 75 days").

# %%
import os

from IPython.display import Markdown, display

from ngincompat.references.bifurcation import onset
from ngincompat.scenes.folding import FoldingScene
from ngincompat.studies import folding
from ngincompat.workflow import plots, tables

# %matplotlib inline
COARSE = os.environ.get("NGINCOMPAT_COARSE") == "1"
settings = (dict(length=1.0, height=0.6, cortex_thickness=0.1, cortex_maxh=0.05, maxh=0.3,
                 t_end=42.0, dt=10.0, onset_dt=10.0, release=False) if COARSE else
            {})
axons = ("curved",) if COARSE else folding.AXON_FIELDS
scene = FoldingScene(**settings)
print(scene.describe())

rows, results = folding.run_all(axons=axons, **settings)  # nothing written without a folder
display(Markdown(folding.summary_markdown(rows)))

# %% [markdown]
# ## The onset against the bifurcation analysis
#
# `ngincompat.references.bifurcation` is an independent linear bifurcation analysis of a growing
# stiff
# layer on a soft substrate (neo-Hookean, plane strain, the same moduli; roller ends, so the
# modes are sin(n pi X1 / L)). Its onset is the smallest critical growth over n. The scene
# finds the onset where the smallest eigenvalue of its tangent crosses zero (interpolated
# between steps) and the wavelength from the zero crossings of the eigenmode along the top.
# Neighbouring modes buckle at nearly the same growth (the minimum over n is flat), so the
# mode found may be a neighbour of the analysis' one.

# %%
oracle = onset(scene.bifurcation_bilayer(), length=scene.length)
comparison = [{"axons": a, "onset_growth": r.metrics.get("onset_growth"),
               "analysis": oracle.growth,
               "difference": r.metrics.get("onset_growth", float("nan")) / oracle.growth - 1,
               "onset_wavelength": r.metrics.get("onset_wavelength"),
               "analysis_wavelength": oracle.wavelength}
              for a, r in results.items()]
display(Markdown(tables.markdown(comparison, units={"onset_wavelength": "cm",
                                                   "analysis_wavelength": "cm"})))

# %% [markdown]
# The smallest eigenvalue on the flat branch, and after the onset the fold amplitude (half
# the peak-to-peak vertical displacement of the top) with the eigenvalue of the folded state.

# %%
first = results[axons[0]]
specs = {spec.file: spec for spec in first.figures}
display(plots.figure(first, specs["eigenvalue.png"]))
display(plots.figure(first, specs["folds.png"]))

# %% [markdown]
# ## Growth, incompatibility and stress on the deformed bilayer (Fig. 7 a-c)
#
# One row per axon field, one column per field, drawn on the deformed section (true scale):
# the axon growth theta_a, |b| = |G^T e3| on the plane normal to the paper's e3 (G = Fg Curl Fg
# / Jg, eq. 10-11, Curl Fg of the H1 interpolant of Fg) and the largest principal Cauchy
# stress. Fg jumps at the interface (the cortex grows along e1, the subcortex along the
# axons), so |b| concentrates there; the interpolant spreads the jump over the elements at
# the interface.

# %%
display(folding.fields_figure(results, scene))

# %% [markdown]
# Through the middle of the bilayer, |b| and theta_a against the depth below the top.

# %%
display(plots.figure(first, specs["depth.png"]))
for a, r in results.items():
    m = r.metrics
    print(f"{a:10s}: |b| largest {m['burgers_max']:.3f} 1/cm at {m['burgers_max_depth']:.3f} "
          f"cm below the top (cortex {scene.cortex_thickness:g} cm), theta_a up to "
          f"{m['theta_a_max']:.4f}")

# %% [markdown]
# The flat branch buckles within 2 % of the analysis' onset, even on this mesh.

# %%
assert all(abs(row["difference"]) < 0.02 for row in comparison), comparison
