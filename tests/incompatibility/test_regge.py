"""ngincompat.incompatibility.regge: the Regge interpolant, its distributional Einstein tensor."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import l2_norm

from ngincompat import config
from ngincompat.incompatibility import curvature as cv
from ngincompat.incompatibility import regge
from ngincompat.mechanics import fields
from ngincompat.mechanics.growth import FiberGrowth

#: A constant, anisotropic metric A^T A: flat.
A = np.array([[1.2, 0.3, 0.0], [0.1, 0.9, 0.2], [0.0, -0.2, 1.1]])
FLAT = ngs.CF(tuple((A.T @ A).ravel()), dims=(3, 3))


@pytest.fixture(scope="module")
def smooth_disc():
    """The disc geometry with smooth area growth theta = 1 + (X1^2 + X2^2)/4 about e3, and
    its exact curvature."""
    from geometries import disc
    from ngincompat.mechanics.growth import AreaGrowth
    config.ensure_heap(10**8)
    Fg = AreaGrowth(1 + (ngs.x * ngs.x + ngs.y * ngs.y) / 4, fields.constant("e3")).Fg
    return disc(maxh=0.5, curve_order=2).ngmesh, cv.growth_curvature(Fg)


def _rel(a, b, mesh):
    return l2_norm(a - b, mesh, order=6) / l2_norm(b, mesh, order=6)


def test_regge_path_converges_to_exact_under_h_and_p(smooth_disc):
    from ngincompat.incompatibility import regge
    ngmesh, exact = smooth_disc
    coarse = ngs.Mesh(ngmesh)
    coarse.Curve(2)
    errors = {k: _rel(regge.discrete_curvature(exact.metric, coarse, k).einstein,
                      exact.einstein, coarse) for k in (1, 2)}
    # p: one degree more, several times smaller (measured 0.71 -> 0.087)
    assert errors[2] < 0.2 * errors[1]
    # h: uniform refinement at k = 2 (measured rate about 2; loose check > 1)
    ngmesh.Refine()
    fine = ngs.Mesh(ngmesh)
    fine.Curve(2)
    fine_error = _rel(regge.discrete_curvature(exact.metric, fine, 2).einstein,
                      exact.einstein, fine)
    assert fine_error < 0.5 * errors[2]
    # the scalar curvature of the lift against the exact S
    assert _rel(regge.discrete_curvature(exact.metric, fine, 2).scalar, exact.scalar,
                fine) < 0.1


def test_regge_pairing_and_interior_terms(smooth_disc):
    # the distributional Einstein tensor against a smooth test field vanishing on the
    # boundary: close to the exact pairing, and the facet and edge terms matter (the
    # element term alone is off by much more)
    from geometries import disc
    from ngincompat.incompatibility import regge
    _, exact = smooth_disc
    mesh = disc(maxh=0.5, curve_order=2)
    g = exact.metric
    r2 = ngs.x * ngs.x + ngs.y * ngs.y
    phi = (1 - r2) * ngs.z * (0.5 - ngs.z) * ngs.CF((1, 0.3, 0.2, 0.3, 2, 0.1, 0.2, 0.1, 1),
                                                    dims=(3, 3))
    density = ngs.sqrt(ngs.Det(g)) * ngs.Inv(g) * exact.einstein * ngs.Inv(g)
    reference = ngs.Integrate(ngs.InnerProduct(density, phi), mesh, order=8)
    G = regge.DistributionalEinstein.of(regge.regge_interpolant(g, mesh, 2))
    full = G.apply(phi)
    volume_only = ngs.Integrate(ngs.InnerProduct(G.volume, phi), mesh)
    assert abs(full - reference) < 1e-3 * abs(reference)
    assert abs(volume_only - reference) > 10 * abs(full - reference)


def test_regge_path_on_the_flat_cylinder():
    # the paper's cylinder: the discrete curvature converges to zero under p
    from geometries import cylinder
    from ngincompat.incompatibility import regge
    mesh = cylinder(maxh=0.5, curve_order=2)
    g = cv.growth_metric(FiberGrowth(1 + ngs.y / 4, fields.constant("e1")).Fg)
    discrete = [regge.discrete_curvature(g, mesh, k) for k in (1, 2)]
    norms = [l2_norm(cv.einstein_norm(d.einstein, d.gh), mesh, order=6) for d in discrete]
    assert norms[1] < 0.05 * norms[0]
    assert norms[1] < 5e-3


def test_the_interpolant_of_a_metric_of_the_spaces_degree_is_exact(unit_cube_tet):
    """A metric linear in X is in the Regge space of degree 1: its canonical interpolant is
    the metric itself."""
    x, y, z = ngs.x, ngs.y, ngs.z
    g = FLAT + 0.1 * ngs.CF((x, y, 0, y, z, x, 0, x, 1 + y), dims=(3, 3))
    gh = regge.regge_interpolant(g, unit_cube_tet, 1)
    assert isinstance(gh.space, ngs.HCurlCurl)
    assert l2_norm(gh - g, unit_cube_tet) < 1e-12 * l2_norm(g, unit_cube_tet)


def test_a_flat_metric_has_no_distributional_curvature(unit_cube_tet):
    """A constant metric is Euclidean under a linear map: no element term, straight facets,
    and the g-dihedral angles around every interior edge add up to 2 pi. The pairing with any
    test field and the lifted Einstein and scalar curvature vanish to round-off."""
    G = regge.DistributionalEinstein.of(regge.regge_interpolant(FLAT, unit_cube_tet, 1))
    phi = ngs.CF((1 + ngs.x, ngs.y, 0.2, ngs.y, 2 - ngs.z, ngs.x * ngs.y, 0.2, ngs.x * ngs.y,
                  1 + ngs.z * ngs.z), dims=(3, 3))
    assert abs(G.apply(phi)) < 1e-12
    discrete = regge.discrete_curvature(FLAT, unit_cube_tet, order=1)
    assert l2_norm(discrete.einstein, unit_cube_tet) < 1e-10
    assert l2_norm(discrete.scalar, unit_cube_tet) < 1e-10
    assert l2_norm(discrete.einstein_elementwise, unit_cube_tet) < 1e-12


def test_only_interior_facets_and_edges_are_counted(unit_cube_tet):
    """The facet indicator is 1 on interior facets, 0 on the boundary: over the elements'
    boundaries it integrates to the elements' facet area less the body's surface (each
    interior facet seen from both sides). The edge indicator is 1 on interior edges, 0 on
    boundary edges: over the elements' edges it is the summed length of their interior
    edges."""
    mesh = unit_cube_tet
    facet, edge = regge._interior_indicators(mesh)
    all_facets = ngs.Integrate(ngs.CF(1) * ngs.dx(element_boundary=True), mesh)
    surface = ngs.Integrate(1, mesh, ngs.BND)
    assert surface == pytest.approx(6.0)
    assert ngs.Integrate(facet * ngs.dx(element_boundary=True), mesh) == pytest.approx(
        all_facets - surface, rel=1e-12)
    assert ngs.Integrate(facet, mesh, ngs.BND) == pytest.approx(0.0, abs=1e-14)
    boundary = {e.nr for el in mesh.Elements(ngs.BND) for e in el.edges}
    points = np.array([v.point for v in mesh.vertices])
    interior = 0.0
    for el in mesh.Elements(ngs.VOL):
        for e in el.edges:
            if e.nr not in boundary:
                a, b = (v.nr for v in mesh[e].vertices)
                interior += np.linalg.norm(points[a] - points[b])
    assert boundary and interior > 0
    assert ngs.Integrate(edge * ngs.dx(element_vb=ngs.BBND), mesh) == pytest.approx(
        interior, rel=1e-10)

