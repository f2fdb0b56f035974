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
# One call runs the `cube` scene (the same as `ngincompat run cube`): growth field ->
# mechanics -> incompatibility (G, b) -> residual stress -> the profile of Fig. 1g -> G against
# its closed form, eq. (16). The cells after it explain and draw what it returns.
#
# It runs at the scene's defaults (tetrahedra of displacement order 6 at maxh 0.5 mm, on a
# symmetric integration rule; `CubeScene.from_settings({}, preset="paper")` takes the paper's
# hexahedral layout instead). With the environment variable `NGINCOMPAT_COARSE=1` (the tests)
# it takes the scene's `preview` preset: the incompatibility is as accurate, the strain energy
# is not.

# %%
import os

from IPython.display import display
from ngsolve.webgui import Draw

from ngincompat import sampling
from ngincompat.scenes import CubeScene
from ngincompat.workflow import plots

# %matplotlib inline
COARSE = os.environ.get("NGINCOMPAT_COARSE") == "1"
scene = CubeScene.from_settings({}, preset="preview") if COARSE else CubeScene()
print(scene.describe())

results = scene.run()  # mesh, solve, G and b, stresses, profiles: nothing is written

# %% [markdown]
# `results` is a typed record: the metrics (numbers, in the scene's units), the profiles
# sampled along the X1 centre line, the specifications of the scene's figures, the solver
# history of each stage, and the NGSolve fields themselves on `results.domain`, the mesh.

# %%
mesh, fields, m = results.domain, results.fields, results.metrics
L, stress, energy = (results.units[k] for k in ("length", "stress", "energy"))
print(f"{mesh.ne} elements;", results.summary())
print("fields:", ", ".join(fields))
print("\n".join(results.metric_lines()))  # units: the scene's, "-" a ratio

# %% [markdown]
# ## The growth field
#
# The fields are those of the end of growth, t = 1, where theta runs from 1 at X1 = 0 to 1.25
# at X1 = 1.

# %%
theta_view = Draw(fields["theta"], mesh, "theta")

# %% [markdown]
# ## Incompatibility: Curl Fg, G and Burgers vectors
#
# G depends on Fg alone, so it is known before any mechanics is solved. The scene takes the
# *projected path*: each component of Fg is interpolated into a high-order H1 space
# (order `g_order`) and Curl is taken of the interpolant, (Curl A)_ij = eps_irs dA_js/dX_r
# (eq. 7); it is the path that also works for computed growth fields.
#
# The paper reports b on the planes n_i = Fg e_i / |Fg e_i| (Fig. 1d), the fields `b_n1`,
# `b_n2`, `b_n3`. For isotropic growth these are the coordinate planes, and eq. (16) makes G
# the skew matrix of grad theta over 3 theta^(4/3). With grad theta = (t/4) e1:
#
# * on n1 = e1, b = 0: a loop in the X2-X3 plane sees the same growth everywhere;
# * on n2 and n3, |b| = (1/4) / (3 theta^(4/3)), from 1/12 at X1 = 0 down to ~0.062 at X1 = 1,
#   along -e3 (plane n2) and +e2 (plane n3).

# %%
for plane in ("n1", "n2", "n3"):
    print(f"max |b| on plane {plane}: {sampling.maximum(fields[f'|b_{plane}|'], mesh):.5f} "
          f"1/{L}")
print(f"eq. (16) at X1 = 0:        {1 / 12:.5f} 1/{L}")

# %% [markdown]
# |b| on the plane n2, with the vectors b drawn on a clipping plane normal to X3 through the
# centre of the cube (the colour is |b|; move the clipping plane and switch the vectors in the
# viewer's menu). The vectors all point along -e3 and shrink where the cube has grown more.

# %%
clip = {"x": 0, "y": 0, "z": -1, "dist": 0}
b2_view = Draw(fields["b_n2"], mesh, "b on n2", clipping=clip, vectors={"grid_size": 12})

# %% [markdown]
# And on the plane n3, where b points along +e2:

# %%
b3_view = Draw(fields["b_n3"], mesh, "b on n3", clipping=clip, vectors={"grid_size": 12})

# %% [markdown]
# The same along the X1 centre line, the scene's figure of the Burgers vectors: zero on n1,
# equal magnitudes on n2 and n3, falling as 1/theta^(4/3).

# %%
figures = {spec.file: spec for spec in results.figures}
display(plots.figure(results, figures["burgers.png"]))

# %% [markdown]
# ## Mechanics: the body grows and stays in one piece
#
# Equilibrium is the minimum of the elastic energy int Jg Psi(Fe) dV over displacements u
# (section 2.4). The cube is traction-free; its six rigid-body motions are removed by a
# statically determinate support at three vertices, which carries no load. The scene applies
# the growth from t = 0 to t = 1 in one load step (the solver cuts it if Newton fails); its
# solver history has one stage, "growth". The strain energy converges to 2.19533e-7 N mm
# under refinement (README, Performance); the coarse mesh is some 50 % off.

# %%
for stage, history in results.solver.items():
    print(f"stage {stage}: t = {history.t_reached:g}, {len(history.steps)} load step(s), "
          f"{history.newton_iterations} Newton iterations, {results.timings[stage]:.2f} s")
reference = 2.19533e-7  # N mm, converged high-order value
print(f"strain energy {m['strain_energy']:.6e} {energy}, "
      f"{abs(m['strain_energy'] / reference - 1):.1e} from {reference:g}")

# %% [markdown]
# The residual stress comes from the same energy by symbolic differentiation: P = dW/dF,
# S = F^-1 P. Below is S11 (Fig. 1f) on the deformed configuration, `deformation=u` at true
# scale (the face X1 = 1 ends up ~7 % wider than the face X1 = 0; pass `scale=...` to
# exaggerate). The residual stress is a few kPa, a few thousandths of mu, and
# self-equilibrated: tension and compression balance in every section.

# %%
S11_max = sampling.maximum(fields["S11"], mesh)
S11_min = -sampling.maximum(-fields["S11"], mesh)
print(f"S11 from {S11_min:.2e} to {S11_max:.2e} {stress}")
deformed_view = Draw(fields["S11"], mesh, "S11", deformation=fields["u"])

# %% [markdown]
# Along the centre line, S11, S22 and S33 (S22 and S33 coincide by symmetry):

# %%
display(plots.figure(results, figures["stress.png"]))

# %% [markdown]
# ## The profile along the X1 centre line (Fig. 1g)
#
# The strain energy density Psi and the scalar Curl Fg : Curl Fg along the line
# X2 = X3 = 0.5 mm: the scene's figure, with eq. (15),
# Curl Fg : Curl Fg = 2 |grad theta|^2 / (9 theta^(4/3)), added as markers on its right axis.

# %%
line = results.profile("line")
X1 = line["X1"]
curl_sq_eq15 = 2 * scene.a**2 / (9 * (1 + scene.a * X1) ** (4 / 3))
fig = plots.figure(results, figures["profile.png"])
left, right = fig.axes
right.plot(X1[5::10], curl_sq_eq15[5::10], "x", color="k", label="eq. (15)")
left.legend(handles=left.get_lines() + right.get_lines(), fontsize="small")
display(fig)

# %% [markdown]
# ## Verification: G against the closed form, eq. (16)
#
# The scene compares the projected G with `GrowthModel.closed_form_G`, which
# writes eq. (16) out independently of the generic Curl operator, with the gradient of theta
# taken symbolically. The relative L2 error is of the order of the interpolation error of
# theta^(1/3) at order `g_order` (1e-9 to 1e-10), on the coarse mesh as on the fine one: G
# does not depend on how the displacement is discretised.
#
# The scene also computes G a second way, from the elastic deformation alone (eq. 12:
# G = Je Fe^-1 curl Fe^-1, derivatives in the current configuration). It agrees with G of
# eq. (10) only as far as the displacement is resolved: ~1e-2 on the coarse mesh.

# %%
print(f"relative L2 error of G against eq. (16): {m['G_error_L2_rel']:.2e}")
print(f"G from Fe (eq. 12) against G from Fg (eq. 10): {m['G_elastic_vs_growth_L2_rel']:.2e}")
assert m["G_error_L2_rel"] < 1e-5, m["G_error_L2_rel"]
