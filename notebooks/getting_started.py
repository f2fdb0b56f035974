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
# # Getting started: your own growth field in ten lines
#
# Prescribe a growth field theta(X, t) on a geometry and get the incompatibility tensor
# G = (1/Jg) Fg Curl Fg (eq. 10 of Lee et al., JMPS 146 (2021) 104177), the Burgers vectors
# b = G^T n (eq. 11) and the residual stress, with the public Python API. Units: mm, MPa.
#
# Here a 1 mm cube, traction-free, neo-Hookean (mu = 0.55 MPa, nu = 0.4), grows isotropically,
# by up to 30 % in volume, in a Gaussian bump around the centre of its top face X3 = 1. The
# `custom` scene takes theta as a formula in X1, X2, X3 and the growth time t in [0, 1]
# (`ngincompat run custom --set theta=...` from the command line does the same). With
# `NGINCOMPAT_COARSE=1` (the tests) the mesh and the displacement order are coarser.

# %%
import os

from IPython.display import display
from ngsolve.webgui import Draw

from ngincompat.scenes import CustomScene
from ngincompat.workflow import plots

# %matplotlib inline
maxh, order = (0.5, 2) if os.environ.get("NGINCOMPAT_COARSE") == "1" else (0.2, 3)

# %% [markdown]
# The ten lines. `growth` is `isotropic`, `area` or `fiber` (with a `direction`); `geometry`
# any of the package's geometries; `run()` solves (t = 0 -> 1), computes G and b, the stresses
# and their profiles, and returns them; nothing is written unless you pass an output folder.

# %%
bump = "exp(-((X1-0.5)*(X1-0.5) + (X2-0.5)*(X2-0.5) + (X3-1)*(X3-1)) / 0.2)"
scene = CustomScene(geometry="cube", growth="isotropic", theta=f"1 + 0.3*t*{bump}",
                    maxh=maxh, order=order)
results = scene.run()

m, units = results.metrics, results.units
print(f"{results.domain.ne} elements, {results.mesh.ndof} dofs, "
      f"{results.newton_iterations} Newton iterations")
print(f"strain energy {m['strain_energy']:.4e} {units['energy']}")
print(f"largest |b| {m['burgers_max']:.4f} 1/{units['length']}")
print(f"largest principal Cauchy stress {m['max_principal_stress']:.3e} {units['stress']}")
bump_view = Draw(results.fields["|b_n3|"], results.domain, "|b| on n3",
                 deformation=results.fields["u"])

# %% [markdown]
# `results.fields` holds every field as an NGSolve CoefficientFunction (theta, G, b on the
# planes n_i = Fg e_i / |Fg e_i|, the displacement u, the stresses), `results.profiles` the
# fields sampled along the X1 centre line, `results.figures` the specifications of the
# scene's figures (`ngincompat.workflow.plots.figure(results, spec)` draws one), `results.solver`
# the
# Newton history. `scene.run("out")` also writes results.json, VTK and the figures into the
# folder `out`.

# %%
print(", ".join(results.fields))

# %% [markdown]
# The scene's own figures, drawn from `results.figures`: here |b| on the three planes along
# the X1 centre line (X2 = X3 = 0.5 mm), below the bump.

# %%
figures = {spec.file: spec for spec in results.figures}
display(plots.figure(results, figures["burgers.png"]))

# %% [markdown]
# G against its closed form for isotropic growth, eq. (16), with the gradient of your theta
# taken symbolically (`GrowthModel.closed_form_G`). The program's G is evaluated from the
# same growth expression, not projected onto the mesh, so the two agree to round-off at any
# resolution; a wrong Curl convention would be off by O(1).

# %%
error = m["G_error_L2_rel"]
print(f"relative L2 error of G: {error:.1e}")
assert error < 1e-10, error
