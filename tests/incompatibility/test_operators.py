"""ngincompat.incompatibility.operators: Curl, G, Burgers vectors and the closed forms of 2.3."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import l2_norm, random_points, values_at

from geometries import cube
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import AreaGrowth, FiberGrowth, IsotropicGrowth, TensorGrowth

X1, X2, X3 = ngs.x, ngs.y, ngs.z


def test_curl_convention_pinned_on_manufactured_field(unit_cube_hex):
    """(Curl A)_ij = eps_irs dA_js/dX_r (eq. 7). A = X2 e1 (x) e1 has Curl A = -e3 (x) e1: the
    transposed convention would give -e1 (x) e3 and the opposite sign +e3 (x) e1.
    B = X3 e1 (x) e2 has Curl B = -e1 (x) e1."""
    A = ngs.CF((X2, 0, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    expected = np.zeros((3, 3))
    expected[2, 0] = -1.0
    B = ngs.CF((0, X3, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    expected_B = np.zeros((3, 3))
    expected_B[0, 0] = -1.0
    pts = random_points(5)
    for field, want in ((A, expected), (B, expected_B)):
        exact = values_at(inc.curl_exact(field), unit_cube_hex, pts).reshape(-1, 3, 3)
        projected, _ = inc.curl_projected(field, unit_cube_hex, 2)
        proj = values_at(projected, unit_cube_hex, pts).reshape(-1, 3, 3)
        for got in (exact, proj):
            np.testing.assert_allclose(got, np.broadcast_to(want, got.shape), atol=1e-12)


def test_curl_of_tensor_acts_as_curl_of_transpose_times_vector(unit_cube_hex):
    """Eq. (6): (Curl A) v = curl(A^T v) for constant v, with curl w = eps_irs dw_s/dX_r."""
    A = ngs.CF((X1 * X2, X3 ** 2, ngs.sin(X1), X2 * X3, X1, X1 * X3,
                ngs.exp(X2), X1 * X2 * X3, X2), dims=(3, 3))
    v = ngs.CF((0.3, -1.2, 0.7))
    w = A.trans * v
    dw = inc.gradient_exact(w)
    curl_w = ngs.fem.Einsum("irs,sr->i", inc.levi_civita(), dw)
    diff = inc.curl_exact(A) * v - curl_w
    assert l2_norm(diff, unit_cube_hex) < 1e-12
    assert l2_norm(curl_w, unit_cube_hex) > 0.1


def test_gradient_is_compatible(unit_cube_hex):
    """Curl Grad v = 0 for any vector field v (section 2.2)."""
    v = ngs.CF((X1 * X2 ** 2, ngs.sin(X3) * X1, ngs.exp(X1 * X2)))
    grad_v = ngs.fem.Einsum("jr->jr", inc.gradient_exact(v))
    assert l2_norm(inc.curl_exact(grad_v), unit_cube_hex) < 1e-12


THETA = 1 + 0.3 * X1 + 0.2 * X2 * X3 + 0.1 * ngs.sin(2 * X3)


@pytest.mark.parametrize("growth", [
    IsotropicGrowth(THETA),
    AreaGrowth(THETA, fields.constant((0.3, -0.5, 1.0))),
    AreaGrowth(THETA, fields.constant("e3")),
    FiberGrowth(THETA, fields.constant((1.0, 2.0, 0.5))),
    FiberGrowth(THETA, fields.constant("e1")),
], ids=["isotropic", "area-oblique", "area-e3", "fiber-oblique", "fiber-e1"])
def test_closed_forms_match_generic_exact_path(growth, unit_cube_hex):
    """Eq. (16), (19)-(20), (24)-(25) against G = (1/Jg) Fg Curl Fg with symbolic derivatives."""
    G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
    reference = growth.closed_form_G()
    assert l2_norm(reference, unit_cube_hex) > 1e-2
    assert inc.relative_l2_error(G, reference, unit_cube_hex) < 1e-13


@pytest.mark.parametrize("kind", ["isotropic", "area", "fiber"])
def test_closed_form_curls_match_generic_exact_path(kind, unit_cube_hex):
    """Curl Fg of eq. (15), (19) and (24) against eq. (7) with symbolic derivatives."""
    direction = fields.constant((0.3, -0.5, 1.0))
    grad = inc.grad_scalar(THETA)
    growth, reference = {
        "isotropic": (IsotropicGrowth(THETA), inc.curl_isotropic_closed_form(THETA, grad)),
        "area": (AreaGrowth(THETA, direction),
                 inc.curl_area_closed_form(THETA, grad, direction.cf)),
        "fiber": (FiberGrowth(THETA, direction),
                  inc.curl_fiber_closed_form(THETA, grad, direction.cf)),
    }[kind]
    assert l2_norm(reference, unit_cube_hex) > 1e-2
    assert inc.relative_l2_error(inc.curl_exact(growth.Fg), reference, unit_cube_hex) < 1e-13


def test_isotropic_burgers_vectors_lie_in_their_plane(unit_cube_hex):
    """Eq. (16)-(17): G is skew, so n . G^T n = 0 for every normal, and b is orthogonal to
    grad theta on every plane (b = (1/(3 theta^(4/3))) grad theta x n up to sign)."""
    growth = IsotropicGrowth(THETA)
    G = growth.closed_form_G()
    grad = inc.grad_scalar(THETA)
    pts = random_points(30, seed=1)
    rng = np.random.default_rng(2)
    for _ in range(3):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        b = inc.burgers_vector(G, ngs.CF(tuple(n)))
        along_n = values_at(ngs.InnerProduct(b, ngs.CF(tuple(n))), unit_cube_hex, pts)
        along_grad = values_at(ngs.InnerProduct(b, grad), unit_cube_hex, pts)
        assert np.max(np.abs(along_n)) < 1e-14
        assert np.max(np.abs(along_grad)) < 1e-14
        assert np.max(values_at(ngs.Norm(b), unit_cube_hex, pts)) > 1e-3


def test_unidirectional_growth_has_no_burgers_vector_on_gradient_plane(unit_cube_hex):
    """Section 3.1: for theta = theta(X1), b vanishes on n1 = Fg e1 / |Fg e1|."""
    growth = IsotropicGrowth(1 + X1 / 4)
    n = inc.lattice_normals(growth.Fg)
    G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
    assert l2_norm(inc.burgers_vector(G, n[0]), unit_cube_hex) < 1e-14
    assert l2_norm(inc.burgers_vector(G, n[1]), unit_cube_hex) > 1e-2


def test_area_burgers_vector_eq22(unit_cube_hex):
    """Eq. (21)-(22): on the plane N0, b is in the plane, orthogonal to the growth gradient,
    with magnitude |grad theta| / (2 theta^(3/2)) for an in-plane gradient."""
    theta = 1 + 0.25 * ngs.sqrt(X1 ** 2 + X2 ** 2)
    growth = AreaGrowth(theta, fields.constant("e3"))
    N0 = growth.normal.cf
    G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
    b = inc.burgers_vector(G, N0)
    grad = inc.grad_scalar(theta)
    b22 = inc.burgers_area_closed_form(theta, grad, N0)
    assert inc.relative_l2_error(b, b22, unit_cube_hex) < 1e-13
    pts = random_points(30, seed=3)
    assert np.max(np.abs(values_at(ngs.InnerProduct(b, N0), unit_cube_hex, pts))) < 1e-14
    assert np.max(np.abs(values_at(ngs.InnerProduct(b, grad), unit_cube_hex, pts))) < 1e-14
    magnitude = ngs.Norm(grad) / (2 * theta ** 1.5)
    np.testing.assert_allclose(values_at(ngs.Norm(b), unit_cube_hex, pts),
                               values_at(magnitude, unit_cube_hex, pts), rtol=1e-12)


def test_fiber_burgers_vectors_eq26_eq27(unit_cube_hex):
    """Eq. (26): no Burgers vector on the fiber plane; eq. (27): on m = grad theta x f0 / |.|,
    orthogonal to f0 and grad theta, b = |grad theta| sin(beta) / theta f0 (beta = 90 deg)."""
    theta = 1 + X2 / 4
    f0 = fields.constant("e1").cf
    growth = FiberGrowth(theta, fields.constant("e1"))
    G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
    assert l2_norm(inc.burgers_vector(G, f0), unit_cube_hex) < 1e-14
    m = fields.constant((0, 0, -1)).cf  # grad theta x f0 = (e2 x e1) / 4 = -e3 / 4
    b = inc.burgers_vector(G, m)
    expected = inc.burgers_fiber_magnitude(theta, inc.grad_scalar(theta), f0) * f0
    assert inc.relative_l2_error(b, expected, unit_cube_hex) < 1e-13
    pts = random_points(10, seed=4)
    np.testing.assert_allclose(values_at(ngs.Norm(b), unit_cube_hex, pts)[:, 0],
                               0.25 / (1 + pts[:, 1] / 4), rtol=1e-12)


def test_uniform_growth_is_compatible(unit_cube_hex):
    """A uniform growth tensor of any kind has G = 0."""
    for growth in (IsotropicGrowth(ngs.CF(1.7)),
                   AreaGrowth(ngs.CF(1.7), fields.constant("e2")),
                   TensorGrowth(ngs.CF((1.2, 0.1, 0, 0, 0.9, 0, 0.3, 0, 1.1), dims=(3, 3)))):
        G = inc.incompatibility_tensor(growth.Fg, inc.curl_exact(growth.Fg))
        assert l2_norm(G, unit_cube_hex) < 1e-14
        curl_h, _ = inc.curl_projected(growth.Fg, unit_cube_hex, 3)
        assert l2_norm(curl_h, unit_cube_hex) < 1e-11


def test_G_from_elastic_part_equals_G_from_growth_exactly(unit_cube_hex):
    """Eq. (12) = eq. (10) for any smooth deformation: with u analytic, Fe^-1 = Fg F^-1 and
    G = Je Fe^-1 curl Fe^-1 computed with exact derivatives equals (1/Jg) Fg Curl Fg."""
    growth = IsotropicGrowth(THETA)
    u = ngs.CF((0.1 * X1 * X2, 0.05 * ngs.sin(X3) + 0.1 * X1, 0.08 * X2 * X3 ** 2))
    F = ngs.Id(3) + inc.gradient_exact(u)
    Fe_inv = growth.Fg * ngs.Inv(F)
    G_e = inc.incompatibility_from_elastic(Fe_inv, inc.gradient_exact(Fe_inv), F)
    G = growth.closed_form_G()
    assert inc.relative_l2_error(G_e, G, unit_cube_hex) < 1e-12


def test_gradient_of_the_inverse_elastic_part_from_second_derivatives(unit_cube_hex):
    """d(Fg F^-1)/dX from dFg and the second derivatives of u equals the symbolic gradient;
    the scenes evaluate eq. (12) with it instead of projecting Fe^-1."""
    growth = IsotropicGrowth(THETA)
    u = ngs.CF((0.1 * X1 * X2, 0.05 * ngs.sin(X3) + 0.1 * X1, 0.08 * X2 * X3 ** 2))
    F = ngs.Id(3) + inc.gradient_exact(u)
    Fe_inv, dFe_inv = inc.inverse_elastic_gradient(growth.Fg, inc.gradient_exact(growth.Fg),
                                                   F, inc.gradient_exact(F))
    reference = inc.gradient_exact(growth.Fg * ngs.Inv(F))
    assert l2_norm(Fe_inv - growth.Fg * ngs.Inv(F), unit_cube_hex) < 1e-14
    assert l2_norm(dFe_inv - reference, unit_cube_hex) < 1e-12 * l2_norm(reference,
                                                                         unit_cube_hex)


def _cube_G_error(n, p):
    mesh = cube(maxh=1.0 / n)
    growth = IsotropicGrowth(1 + X1 / 4)
    curl_h, _ = inc.curl_projected(growth.Fg, mesh, p)
    return inc.relative_l2_error(inc.incompatibility_tensor(growth.Fg, curl_h),
                                 growth.closed_form_G(), mesh)


def test_projected_path_h_convergence_rate():
    """The cube's G by the projected path converges like h^p under h-refinement (order p)."""
    for p in (1, 2):
        ns = np.array([2, 4, 8])
        errors = np.array([_cube_G_error(n, p) for n in ns])
        rate = np.polyfit(np.log(1.0 / ns), np.log(errors), 1)[0]
        assert rate > p - 0.2, (p, errors, rate)


def test_projected_path_p_convergence_and_default_accuracy():
    """Under p-refinement on a fixed mesh the error falls by a growing factor per order
    (exponential convergence); at the cube's defaults (maxh 0.25, g_order 6) it is < 1e-6."""
    errors = [_cube_G_error(2, p) for p in (2, 3, 4, 5, 6)]
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(ratios > 10), errors
    assert _cube_G_error(4, 6) < 1e-6
