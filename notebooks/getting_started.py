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
# Build a geometry, prescribe a growth field theta(X, t), and get the incompatibility tensor
# G = (1/Jg) Fg Curl Fg (eq. 10 of Lee et al., JMPS 146 (2021) 104177), a Burgers vector
# b = G^T n (eq. 11) and the residual stress, with the public Python API. Units: mm, MPa.
#
# Here a 1 mm cube (tetrahedra), traction-free, neo-Hookean (mu = 0.55 MPa, nu = 0.4), grows
# isotropically, by up to 30 % in volume, in a Gaussian bump around the centre of its top face
# X3 = 1. With `NGINCOMPAT_COARSE=1` (the tests) the mesh and the displacement order are
# coarser.

# %%
import os

import ngsolve as ngs
from ngsolve.webgui import Draw

from geometries import cube
from ngincompat import incompatibility as inc
from ngincompat import postprocess
from ngincompat.growth import IsotropicGrowth
from ngincompat.materials import NeoHookean
from ngincompat.problem import GrowthMechanics
from ngincompat.solver import solve_growth

maxh, order = (0.5, 2) if os.environ.get("NGINCOMPAT_COARSE") == "1" else (0.2, 3)

# %% [markdown]
# The ten lines. `t` is the growth time: theta depends on it, and the solver drives it from 0
# to 1. G depends on Fg alone; b is reported on the plane whose normal is Fg e3 / |Fg e3|.

# %%
t = ngs.Parameter(0.0)
mesh = cube(maxh=maxh, elements="tet")
r2 = (ngs.x - 0.5) ** 2 + (ngs.y - 0.5) ** 2 + (ngs.z - 1) ** 2
growth = IsotropicGrowth(1 + 0.3 * t * ngs.exp(-r2 / 0.2))
problem = GrowthMechanics(mesh, growth, NeoHookean.from_nu(0.55, 0.4), order=order)
history = solve_growth(problem, t)  # traction-free, t = 0 -> 1
curl_Fg, _ = inc.curl_projected(growth.Fg, mesh, order=6)
G = inc.incompatibility_tensor(growth.Fg, curl_Fg)
b3 = inc.burgers_vector(G, inc.lattice_normals(growth.Fg)[2])
stress = postprocess.stresses(problem.energy_density, problem.u)  # P, S, sigma, W

# %%
print(f"{mesh.ne} tets, {problem.ndof} dofs, {history.newton_iterations} Newton iterations")
print(f"strain energy {problem.strain_energy():.4e} N mm")
print(f"max |b| on n3: {postprocess.maximum(ngs.Norm(b3), mesh):.4f} 1/mm")
sigma_max = postprocess.principal_values(stress["sigma"])[2]
print(f"largest principal Cauchy stress {postprocess.maximum(sigma_max, mesh):.3e} MPa")
bump_view = Draw(ngs.Norm(b3), mesh, "|b| on n3", deformation=problem.u)

# %% [markdown]
# G against its closed form for isotropic growth, eq. (16), with the gradient of your theta
# taken symbolically. The projected G converges with the mesh and the interpolation order (~3e-3
# on the coarse mesh, ~2e-5 at the defaults); a wrong Curl convention would be off by O(1).

# %%
error = inc.relative_l2_error(G, inc.closed_form_G(growth), mesh)
print(f"relative L2 error of G: {error:.1e}")
assert error < 1e-2, error
