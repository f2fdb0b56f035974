"""Geometric incompatibility: Curl Fg (eq. 7), G (eq. 10, 12), Burgers vectors (eq. 11).

Two paths lead to Curl Fg:

* **exact**: for an analytic growth field, the reference gradient of Fg comes from symbolic
  differentiation of the CoefficientFunction (``CF.Diff(x)``), so G is exact to round-off;
* **projected**: each component of Fg is interpolated into a high-order H1 space and Curl
  comes from the gradient of the interpolant; this is the path for computed growth fields.

The closed forms of section 2.3 (eq. 16, 19-22, 24-27) are written out independently of the
generic operators, so they can serve as oracles.

Conventions
-----------
A reference gradient of a 3x3 field A is stored with indices ``dA[j, s, r] = dA_js / dX_r``,
which is what ``ngsolve.Grad`` gives for a matrix-valued GridFunction, and

    (Curl A)_ij = eps_irs dA_js / dX_r      (eq. 7).
"""

from typing import TypeAlias

import ngsolve as ngs

CF: TypeAlias = ngs.CoefficientFunction

_COORDS = (ngs.x, ngs.y, ngs.z)


def levi_civita() -> CF:
    """The permutation symbol eps_ijk as a 3x3x3 CoefficientFunction."""
    return ngs.fem.LeviCivitaSymbol(3)


def gradient_exact(A: CF) -> CF:
    """Reference gradient of an analytic CoefficientFunction, ``dA[j, s, r] = dA_js/dX_r``.

    ``A`` may be a scalar, a 3-vector or a 3x3 matrix; the derivative index is always last.
    """
    parts = tuple(A.Diff(c) for c in _COORDS)
    dims = tuple(A.dims) if A.dims != [1] else ()
    if not dims:
        return ngs.CF(parts)
    stacked = ngs.CF(parts, dims=(3,) + dims)
    if len(dims) == 1:
        return ngs.fem.Einsum("rj->jr", stacked)
    return ngs.fem.Einsum("rjs->jsr", stacked)


def curl(dA: CF) -> CF:
    """Curl of a tensor from its gradient, eq. (7): ``(Curl A)_ij = eps_irs dA_js/dX_r``."""
    return ngs.fem.Einsum("irs,jsr->ij", levi_civita(), dA)


def curl_exact(A: CF) -> CF:
    """Curl A by symbolic differentiation of an analytic CoefficientFunction (eq. 7)."""
    return curl(gradient_exact(A))


def project_tensor(A: CF, mesh: ngs.Mesh, order: int) -> tuple[CF, CF]:
    """Interpolate a 3x3 field into H1(order), component by component.

    Returns
    -------
    A_h : CoefficientFunction
        The interpolant, 3x3.
    dA_h : CoefficientFunction
        Its reference gradient, ``dA_h[j, s, r] = d(A_h)_js / dX_r``.

    Notes
    -----
    Nine scalar interpolations (``GridFunction.Set``) instead of one in ``MatrixValued(H1)``:
    the local problems are 9x smaller, which makes order 6 on hexahedra ~10^3 times cheaper.
    On the section of a body in plane strain (a two-dimensional mesh, fields independent of
    X3) the derivatives by X3 are zero.
    """
    space = ngs.H1(mesh, order=order)
    parts = []
    for j in range(3):
        for s in range(3):
            gf = ngs.GridFunction(space)
            gf.Set(A[j, s])
            parts.append(gf)
    A_h = ngs.CF(tuple(parts), dims=(3, 3))
    dA_h = ngs.CF(tuple(_gradient(gf, mesh.dim) for gf in parts), dims=(3, 3, 3))
    return A_h, dA_h


def _gradient(gf: ngs.GridFunction, dim: int) -> CF:
    """The reference gradient of a scalar GridFunction as a 3-vector (zero by X3 on a
    section, ``dim`` 2)."""
    grad = ngs.Grad(gf)
    return grad if dim == 3 else ngs.CF((grad[0], grad[1], 0))


def curl_projected(A: CF, mesh: ngs.Mesh, order: int) -> tuple[CF, CF]:
    """Curl A of the H1 interpolant of A (eq. 7); returns (Curl A_h, A_h)."""
    A_h, dA_h = project_tensor(A, mesh, order)
    return curl(dA_h), A_h


def incompatibility_tensor(Fg: CF, curl_Fg: CF) -> CF:
    """G = (1/Jg) Fg Curl Fg, eq. (10)."""
    return (1.0 / ngs.Det(Fg)) * (Fg * curl_Fg)


def inverse_elastic_gradient(Fg: CF, dFg: CF, F: CF, dF: CF) -> tuple[CF, CF]:
    """Fe^-1 = Fg F^-1 and its reference gradient from those of Fg and F (no projection).

    ``dFg[j, a, k] = d(Fg)_ja / dX_k``, ``dF[b, c, k] = d F_bc / dX_k`` (for F = I + Grad u the
    second derivatives of u); with d(F^-1)/dX_k = -F^-1 (dF/dX_k) F^-1,

        d(Fe^-1)_js / dX_k = dFg[j, a, k] (F^-1)_as - Fg_ja (F^-1)_ab dF[b, c, k] (F^-1)_cs.

    Returns (Fe^-1, its gradient in index order [j, s, k]), as
    :func:`incompatibility_from_elastic` takes them.
    """
    F_inv = ngs.Inv(F)
    dFe_inv = (ngs.fem.Einsum("jak,as->jsk", dFg, F_inv)
               - ngs.fem.Einsum("ja,ab,bck,cs->jsk", Fg, F_inv, dF, F_inv))
    return Fg * F_inv, dFe_inv


def incompatibility_from_elastic(Fe_inv: CF, dFe_inv: CF, F: CF) -> CF:
    """G from the elastic deformation alone, eq. (12): G = Je Fe^-1 curl Fe^-1.

    Parameters
    ----------
    Fe_inv : CoefficientFunction
        Fe^-1 as a function of X (usually a projected GridFunction).
    dFe_inv : CoefficientFunction
        Its reference gradient, ``d(Fe^-1)_js/dX_k`` in index order [j, s, k].
    F : CoefficientFunction
        The deformation gradient; the current-configuration derivative is
        ``d/dx_r = d/dX_k (F^-1)_kr``.
    """
    d_spatial = ngs.fem.Einsum("jsk,kr->jsr", dFe_inv, ngs.Inv(F))
    return (1.0 / ngs.Det(Fe_inv)) * (Fe_inv * curl(d_spatial))


def incompatibility_projected(Fg: CF, mesh: ngs.Mesh, order: int) -> tuple[CF, CF, CF]:
    """G = (1/Jg) Fg Curl Fg (eq. 10) of a computed growth field by the projected path.

    Returns (G, Curl Fg_h, Fg_h), Fg_h the H1(order) interpolant that Curl is taken of."""
    curl_Fg, Fg_h = curl_projected(Fg, mesh, order)
    return incompatibility_tensor(Fg, curl_Fg), curl_Fg, Fg_h


def burgers_vector(G: CF, n: CF) -> CF:
    """Local Burgers vector density on the plane with normal n, eq. (11): b = G^T n."""
    return G.trans * n


def lattice_normals(Fg: CF) -> tuple[CF, CF, CF]:
    """The paper's planes in the intermediate configuration, n_i = Fg e_i / |Fg e_i|."""
    normals = []
    for i in range(3):
        v = Fg[:, i]
        normals.append(v / ngs.Norm(v))
    return tuple(normals)


def curl_norm_squared(curl_Fg: CF) -> CF:
    """The scalar invariant Curl Fg : Curl Fg (section 3.1)."""
    return ngs.InnerProduct(curl_Fg, curl_Fg)


def grad_scalar(theta: CF) -> CF:
    """Gradient of an analytic scalar CoefficientFunction as a 3-vector."""
    return ngs.CF(tuple(theta.Diff(c) for c in _COORDS))


def _hodge(v: CF) -> CF:
    """Hodge star of v (eq. 15): the matrix of (v x e_i) (x) e_i, column i being v x e_i."""
    return ngs.CF((0, -v[2], v[1],
                   v[2], 0, -v[0],
                   -v[1], v[0], 0), dims=(3, 3))


def curl_isotropic_closed_form(theta: CF, grad_theta: CF) -> CF:
    """Curl Fg for isotropic growth, eq. (15): (1 / (3 theta^(2/3))) (grad theta x e_i) (x) e_i."""
    return (1.0 / (3.0 * theta ** (2.0 / 3.0))) * _hodge(grad_theta)


def G_isotropic_closed_form(theta: CF, grad_theta: CF) -> CF:
    """G for isotropic growth, eq. (16): the skew matrix of grad theta over 3 theta^(4/3)."""
    return (1.0 / (3.0 * theta ** (4.0 / 3.0))) * _hodge(grad_theta)


def curl_area_closed_form(theta: CF, grad_theta: CF, N0: CF) -> CF:
    """Curl Fg for area growth with constant N0, eq. (19)."""
    c = 1.0 / (2.0 * ngs.sqrt(theta))
    return c * _hodge(grad_theta) - c * ngs.OuterProduct(ngs.Cross(grad_theta, N0), N0)


def G_area_closed_form(theta: CF, grad_theta: CF, N0: CF) -> CF:
    """G for area growth, eq. (20): (theta^-1/2 I + (theta^-1 - theta^-1/2) N0 N0) Curl Fg."""
    s = ngs.sqrt(theta)
    pre = (1.0 / s) * ngs.Id(3) + (1.0 / theta - 1.0 / s) * ngs.OuterProduct(N0, N0)
    return pre * curl_area_closed_form(theta, grad_theta, N0)


def burgers_area_closed_form(theta: CF, grad_theta: CF, N0: CF) -> CF:
    """b on the plane N0 for area growth, eq. (21)-(22): |grad theta| / (2 theta^(3/2)) s.

    With s the in-plane unit vector orthogonal to the in-plane growth gradient; written as
    (1 / (2 theta^(3/2))) N0 x grad theta, which is eq. (22) for an in-plane gradient.
    """
    return (1.0 / (2.0 * theta ** 1.5)) * ngs.Cross(N0, grad_theta)


def curl_fiber_closed_form(theta: CF, grad_theta: CF, f0: CF) -> CF:
    """Curl Fg for fiber growth with constant f0, eq. (24): (grad theta x f0) (x) f0."""
    return ngs.OuterProduct(ngs.Cross(grad_theta, f0), f0)


def G_fiber_closed_form(theta: CF, grad_theta: CF, f0: CF) -> CF:
    """G for fiber growth, eq. (25): (theta^-1 I + (1 - theta^-1) f0 f0) Curl Fg."""
    pre = (1.0 / theta) * ngs.Id(3) + (1.0 - 1.0 / theta) * ngs.OuterProduct(f0, f0)
    return pre * curl_fiber_closed_form(theta, grad_theta, f0)


def burgers_fiber_magnitude(theta: CF, grad_theta: CF, f0: CF) -> CF:
    """|b| on the plane m orthogonal to f0 and grad theta, eq. (27).

    |b| = |grad theta| sin(beta) / theta, beta the angle between grad theta and f0; b points
    along +f0 for m = grad theta x f0 / |grad theta x f0| and along -f0 for -m.
    """
    return ngs.Norm(ngs.Cross(grad_theta, f0)) / theta


def relative_l2_error(A: CF, A_ref: CF, mesh: ngs.Mesh, order: int = 10) -> float:
    """||A - A_ref||_L2 / ||A_ref||_L2 over the mesh (absolute error if A_ref vanishes)."""
    diff = ngs.Integrate(ngs.InnerProduct(A - A_ref, A - A_ref), mesh, order=order)
    ref = ngs.Integrate(ngs.InnerProduct(A_ref, A_ref), mesh, order=order)
    diff, ref = max(float(diff), 0.0), max(float(ref), 0.0)
    return (diff / ref) ** 0.5 if ref > 0 else diff ** 0.5
