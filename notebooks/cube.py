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
# # The growing cube: incompatibility from a growth gradient
#
# Lee, Holland, Weickenmeier, Gosain, Buganza Tepole, *The Geometry of Incompatibility in
# Growing Soft Tissues*, J. Mech. Phys. Solids 146 (2021) 104177, section 3.1. Equation numbers
# below are the paper's.
#
# A cube of edge 1 mm grows isotropically, Fg = theta^(1/3) I (eq. 13), by an amount that
# increases along X1 (eq. 50):
#
# $$\theta(X, t) = 1 + \frac{X_1\, t}{4}, \qquad t \in [0, 1].$$
#
# Every small piece of the cube could grow freely into a bigger cube, but the pieces would no
# longer fit together: Curl Fg does not vanish. The *incompatibility tensor*
# G = (1/Jg) Fg Curl Fg (eq. 10) measures the misfit, and the *Burgers vector*
# b = G^T n (eq. 11) is the closure failure of a small loop in the plane with normal n. To
# stay in one piece, the body deforms elastically (Fe = F Fg^-1) and keeps a residual stress,
# although no load acts on it (traction-free; neo-Hookean, mu = 0.55 MPa, nu = 0.4).
#
# The notebook follows the pipeline of the `cube` scene (`ngincompat run cube`) step by step:
# growth field -> incompatibility (G, b) -> mechanics -> residual stress -> the paper's Fig. 1g
# profile -> verification of G against its closed form, eq. (16).
#
# It runs at the scene's defaults (hexahedra, maxh 0.25 mm, displacement order 4). With the
# environment variable `NGINCOMPAT_COARSE=1` (the tests) it takes a coarse mesh instead
# (maxh 0.5 mm, order 2): the incompatibility is as accurate, the strain energy is not.

# %%
import os

import matplotlib.pyplot as plt
import ngsolve as ngs
from ngsolve.webgui import Draw

from ngincompat import incompatibility as inc
from ngincompat import postprocess
from ngincompat.problem import GrowthMechanics
from ngincompat.scenes.cube import CubeScene
from ngincompat.solver import NewtonOptions, solve_growth

# %matplotlib inline
COARSE = os.environ.get("NGINCOMPAT_COARSE") == "1"
scene = CubeScene(order=2, maxh=0.5) if COARSE else CubeScene()
print(scene.describe())

# %% [markdown]
# ## The growth field
#
# `scene.build()` returns the mesh, the growth model, the material and the growth time: an
# `ngsolve.Parameter`, so one growth law serves every instant. We look at the end of growth,
# t = 1, where theta runs from 1 at X1 = 0 to 1.25 at X1 = 1.

# %%
case = scene.build()
mesh, growth, time = case.mesh, case.growth, case.time
print(f"{mesh.ne} elements, {mesh.nv} vertices")

time.Set(1.0)
theta_view = Draw(growth.theta, mesh, "theta")

# %% [markdown]
# ## Incompatibility: Curl Fg, G and Burgers vectors
#
# G depends on Fg alone, so it is known before any mechanics is solved. The package's
# *projected path* interpolates each component of Fg into a high-order H1 space
# (order `g_order`) and takes Curl of the interpolant, (Curl A)_ij = eps_irs dA_js/dX_r
# (eq. 7); it is the path that also works for computed growth fields.
#
# The paper reports b on the planes n_i = Fg e_i / |Fg e_i| (Fig. 1d). For isotropic growth
# these are the coordinate planes, and eq. (16) makes G the skew matrix of grad theta over
# 3 theta^(4/3). With grad theta = (t/4) e1:
#
# * on n1 = e1, b = 0: a loop in the X2-X3 plane sees the same growth everywhere;
# * on n2 and n3, |b| = (1/4) / (3 theta^(4/3)), from 1/12 at X1 = 0 down to ~0.062 at X1 = 1,
#   along -e3 (plane n2) and +e2 (plane n3).

# %%
curl_Fg, _ = inc.curl_projected(growth.Fg, mesh, scene.g_order)
G = inc.incompatibility_tensor(growth.Fg, curl_Fg)
normals = inc.lattice_normals(growth.Fg)  # n_i = Fg e_i / |Fg e_i|
b = {f"n{i + 1}": inc.burgers_vector(G, n) for i, n in enumerate(normals)}
for label, vec in b.items():
    print(f"max |b| on plane {label}: {postprocess.maximum(ngs.Norm(vec), mesh):.5f} 1/mm")
print(f"eq. (16) at X1 = 0:        {1 / 12:.5f} 1/mm")

# %% [markdown]
# |b| on the plane n2, with the vectors b drawn on a clipping plane normal to X3 through the
# centre of the cube (the colour is |b|; move the clipping plane and switch the vectors in the
# viewer's menu). The vectors all point along -e3 and shrink where the cube has grown more.

# %%
clip = {"x": 0, "y": 0, "z": -1, "dist": 0}
b2_view = Draw(b["n2"], mesh, "b on n2", clipping=clip, vectors={"grid_size": 12})

# %% [markdown]
# And on the plane n3, where b points along +e2:

# %%
b3_view = Draw(b["n3"], mesh, "b on n3", clipping=clip, vectors={"grid_size": 12})

# %% [markdown]
# ## Mechanics: the body grows and stays in one piece
#
# Equilibrium is the minimum of the elastic energy int Jg Psi(Fe) dV over displacements u
# (section 2.4). The cube is traction-free; its six rigid-body motions are removed by a
# statically determinate support at three vertices, which carries no load. Growth is applied
# from t = 0 to t = 1 in one load step (the solver cuts it if Newton fails).

# %%
time.Set(0.0)
problem = GrowthMechanics(mesh, growth, case.material, order=scene.order)
with ngs.TaskManager():
    history = solve_growth(problem, time, NewtonOptions(steps=scene.steps))
energy = problem.strain_energy()
reference = 2.19533e-7  # N mm, converged high-order value (README, Performance)
print(f"t = {time.Get():g}, {problem.ndof} dofs, {history.newton_iterations} Newton iterations")
print(f"strain energy {energy:.6e} N mm, {abs(energy / reference - 1):.1e} from {reference:g}")

# %% [markdown]
# The residual stress comes from the same energy by symbolic differentiation
# (`postprocess.stresses`): P = dW/dF, S = F^-1 P. Below is S11 (Fig. 1f) on the deformed
# configuration, `deformation=u` at true scale (the face X1 = 1 ends up ~7 % wider than the
# face X1 = 0; pass `scale=...` to exaggerate). The residual stress is a few kPa, a few
# thousandths of mu, and self-equilibrated: tension and compression balance in every section.

# %%
stress = postprocess.stresses(problem.energy_density, problem.u)
e1 = ngs.CF((1, 0, 0))
S11 = postprocess.component(stress["S"], e1)
Psi = stress["W"] / growth.Jg  # strain energy density per intermediate volume
S11_min, S11_max = -postprocess.maximum(-S11, mesh), postprocess.maximum(S11, mesh)
print(f"S11 from {S11_min:.2e} to {S11_max:.2e} MPa")
deformed_view = Draw(S11, mesh, "S11", deformation=problem.u)

# %% [markdown]
# ## The profile along the X1 centre line (Fig. 1g)
#
# The strain energy density Psi and the scalar Curl Fg : Curl Fg along the line
# X2 = X3 = 0.5 mm. From eq. (15), Curl Fg : Curl Fg = 2 |grad theta|^2 / (9 theta^(4/3)),
# drawn as markers.

# %%
start, end, coord = case.line
s, values = postprocess.sample_line(
    mesh, {"Psi": Psi, "curlFg_sq": inc.curl_norm_squared(curl_Fg)}, start, end)
X1 = start[0] + s
theta_line = 1 + scene.a * X1
curl_sq_exact = 2 * scene.a**2 / (9 * theta_line ** (4 / 3))

fig, ax = plt.subplots(figsize=(5.5, 3.8))
ax.plot(X1, values["Psi"], color="tab:blue", lw=2)
ax.set_xlabel(f"{coord} [mm]")
ax.set_ylabel(r"$\Psi$ [MPa]", color="tab:blue")
twin = ax.twinx()
twin.plot(X1, values["curlFg_sq"], color="tab:red", lw=2, ls="--", label="projected")
twin.plot(X1[::10], curl_sq_exact[::10], "o", color="tab:red", mfc="none", label="eq. (15)")
twin.set_ylabel(r"Curl $F^g$ : Curl $F^g$ [1/mm$^2$]", color="tab:red")
twin.legend(loc="upper center")
ax.set_title("cube: profile along the X1 centre line (Fig. 1g)")
fig.tight_layout()
plt.show()

# %% [markdown]
# ## Verification: G against the closed form, eq. (16)
#
# `closed_form_G` writes eq. (16) out independently of the generic Curl operator, with the
# gradient of theta taken symbolically. The relative L2 error of the projected G is of the
# order of the interpolation error of theta^(1/3) at order `g_order` (1e-9 to 1e-10), on the
# coarse mesh as on the fine one: G does not depend on how the displacement is discretised.

# %%
G_exact = inc.closed_form_G(growth)
error = inc.relative_l2_error(G, G_exact, mesh)
print(f"relative L2 error of G (t = {time.Get():g}): {error:.2e}")
assert error < 1e-5, error
