"""ngincompat.fem.problem: oracles, consistency, supports and pins, the mixed pair's inf-sup."""

import ngsolve as ngs
import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from conftest import cube_problem

from geometries import bilayer, cube
from ngincompat.errors import ParameterError
from ngincompat.fem import postprocess
from ngincompat.fem.problem import (
    GrowthMechanics,
    bubbles,
    displacement_space,
    mixed_unknowns_per_element,
    rigid_pins,
)
from ngincompat.fem.stepping import solve_growth
from ngincompat.incompatibility import operators as inc
from ngincompat.mechanics.growth import IsotropicGrowth, TensorGrowth
from ngincompat.mechanics.kinematics import deformation_gradient
from ngincompat.mechanics.materials import NeoHookean


@pytest.mark.parametrize("elements", ["hex", "tet"])
def test_uniform_growth_is_stress_free_and_affine(elements):
    """A compatible (uniform) Fg gives G = 0, zero stress and u = (Fg - I) X up to a rigid
    motion: F^T F = Fg^T Fg everywhere."""
    time = ngs.Parameter(0.0)
    Fg = ngs.CF((1 + 0.3 * time, 0.1 * time, 0, 0, 1 - 0.1 * time, 0, 0, 0, 1 + 0.2 * time),
                dims=(3, 3))
    growth = TensorGrowth(Fg)
    mesh = cube(maxh=0.5, elements=elements)
    problem = GrowthMechanics(mesh, growth, MATERIAL, order=2)
    history = solve_growth(problem, time)
    assert history.converged and history.t_reached == 1.0
    F = deformation_gradient(problem.u)
    C_error = ngs.Integrate(ngs.InnerProduct(F.trans * F - Fg.trans * Fg,
                                             F.trans * F - Fg.trans * Fg), mesh) ** 0.5
    assert C_error < 1e-10
    sigma = postprocess.stresses(problem.energy_density, problem.u)["sigma"]
    assert ngs.Integrate(ngs.InnerProduct(sigma, sigma), mesh) ** 0.5 < 1e-10
    assert abs(problem.strain_energy()) < 1e-14
    G = inc.incompatibility_tensor(Fg, inc.curl_exact(Fg))
    assert ngs.Integrate(ngs.InnerProduct(G, G), mesh) ** 0.5 < 1e-14


MATERIAL = NeoHookean.paper_idealized()


def test_energy_residual_tangent_agree_by_finite_differences():
    """(E(u + e w) - E(u - e w)) / 2e = <r(u), w> and (r(u + e w) - r(u - e w)) / 2e = K w
    (K uncondensed: with static condensation the assembled matrix is the Schur complement)."""
    problem, time = cube_problem(order=3, condense=False)
    time.Set(1.0)
    a, u = problem.form, problem.u.vec
    rng = np.random.default_rng(0)
    u.FV().NumPy()[:] = 0.02 * rng.standard_normal(len(u))
    w = u.CreateVector()
    w.FV().NumPy()[:] = rng.standard_normal(len(u))
    eps = 1e-6
    up, um, r, rp, rm, Kw = (u.CreateVector() for _ in range(6))
    up.data = u + eps * w
    um.data = u - eps * w
    a.Apply(u, r)
    fd_energy = (a.Energy(up) - a.Energy(um)) / (2 * eps)
    assert fd_energy == pytest.approx(ngs.InnerProduct(r, w), rel=1e-7)
    a.Apply(up, rp)
    a.Apply(um, rm)
    a.AssembleLinearization(u)
    Kw.data = a.mat * w
    diff = Kw.CreateVector()
    diff.data = (1 / (2 * eps)) * (rp - rm) - Kw
    assert diff.Norm() < 1e-6 * Kw.Norm()


@pytest.mark.parametrize("formulation", ["displacement", "mixed"])
def test_component_form_equals_the_vector_form(formulation):
    """The energy form on three scalar H1 spaces (components=True) gives the energy, residual
    and tangent of the same energy on VectorH1 (components=False), to round-off."""
    time = ngs.Parameter(1.0)
    growth = IsotropicGrowth(1 + 0.25 * ngs.x * time)
    mesh = cube(maxh=0.5, elements="tet")
    component, vector = (GrowthMechanics(mesh, growth, MATERIAL, order=3,
                                         formulation=formulation, components=c).form
                         for c in (True, False))
    assert component.space.ndof == vector.space.ndof
    spaces = (vector.space,) if formulation == "displacement" else vector.space.components
    assert isinstance(spaces[0], ngs.VectorH1)
    u = ngs.GridFunction(vector.space).vec
    u.FV().NumPy()[:] = 0.02 * np.random.default_rng(1).standard_normal(len(u))
    r, r_vector = u.CreateVector(), u.CreateVector()
    component.Apply(u, r)
    vector.Apply(u, r_vector)
    assert component.Energy(u) == pytest.approx(vector.Energy(u), rel=1e-12)
    r_vector.data -= r
    assert r_vector.Norm() < 1e-12 * r.Norm()
    component.AssembleLinearization(u)
    vector.AssembleLinearization(u)
    K, K_vector = (np.array(f.mat.COO()[2]) for f in (component, vector))
    assert np.abs(K - K_vector).max() < 1e-12 * np.abs(K).max()


def test_cube_energy_converges_to_reference():
    """The cube of section 3.1: strain energy 2.19533e-7 N mm (independent high-order runs);
    order 4 on 4^3 hexahedra is within 1e-4 of it."""
    problem, time = cube_problem(maxh=0.25, order=4)
    solve_growth(problem, time)
    assert problem.strain_energy() == pytest.approx(2.19533e-7, rel=1e-4)


def test_G_from_elastic_part_agrees_with_G_from_growth_under_refinement():
    """G by eq. (12) from the solved Fe approaches G by eq. (10) as the mesh is refined."""
    errors = []
    for maxh in (0.5, 0.25):
        problem, time = cube_problem(maxh=maxh, order=3)
        solve_growth(problem, time)
        Fg = problem.growth.Fg
        F = deformation_gradient(problem.u)
        Fe_inv = Fg * ngs.Inv(F)
        G_e = inc.incompatibility_from_elastic(*inc.project_tensor(Fe_inv, problem.mesh, 4), F)
        G = problem.growth.closed_form_G()
        errors.append(inc.relative_l2_error(G_e, G, problem.mesh))
    assert errors[1] < 0.5 * errors[0], errors
    assert errors[1] < 0.05


def test_problem_rejects_bad_order_and_missing_fibers():
    time = ngs.Parameter(0.0)
    mesh = cube(maxh=1.0)
    growth = IsotropicGrowth(1 + ngs.x * time)
    with pytest.raises(ParameterError, match="order = 0"):
        GrowthMechanics(mesh, growth, MATERIAL, order=0)
    from ngincompat.mechanics.materials import GOH
    with pytest.raises(ParameterError, match="fibers"):
        GrowthMechanics(mesh, growth, GOH(1, 1, 1, 1, 0), order=1)


def test_clamped_body_keeps_zero_displacement_on_the_clamped_face():
    time = ngs.Parameter(0.0)
    mesh = cube(maxh=0.5)
    problem = GrowthMechanics(mesh, IsotropicGrowth(1 + 0.3 * ngs.x * time), MATERIAL,
                              order=2, dirichlet="left")
    solve_growth(problem, time)
    u = problem.u
    on_left = ngs.Integrate(ngs.InnerProduct(u, u), mesh, ngs.BND,
                            definedon=mesh.Boundaries("left"))
    on_right = ngs.Integrate(ngs.InnerProduct(u, u), mesh, ngs.BND,
                             definedon=mesh.Boundaries("right"))
    assert on_left < 1e-28
    assert on_right > 1e-3
    assert problem.strain_energy() > 1e-5


def test_componentwise_compatible_fit_equals_the_vector_laplace_solve():
    """The predictor's scalar factorisations solve the same problem as the vector Laplacian,
    also when the components have different free dofs (a symmetry plane, the pins)."""
    time = ngs.Parameter(1.0)
    growth = IsotropicGrowth(1 + 0.25 * ngs.x * time + 0.1 * ngs.y * ngs.z)
    problem = GrowthMechanics(cube(maxh=0.5), growth, MATERIAL, order=3,
                              symmetry={"left": "x"})
    load = problem.growth_load()
    w = problem.compatible_displacement(load)
    u, v = problem.fes.TnT()
    lap = ngs.BilinearForm(ngs.InnerProduct(ngs.Grad(u), ngs.Grad(v)) * ngs.dx).Assemble()
    free = problem.fes.FreeDofs()
    for dof in problem.fes.GetDofNrs(ngs.NodeId(ngs.VERTEX, 0)):   # (0, 0, 0), on "left"
        free.Clear(dof)
    reference = ngs.GridFunction(problem.fes)
    reference.vec.data = lap.mat.Inverse(free, inverse="umfpack") * load
    fit = ngs.GridFunction(problem.fes)
    fit.vec.data = w
    # the same minimiser up to the constants that the anchoring of each component leaves open
    misfit = ngs.Integrate(ngs.InnerProduct(ngs.Grad(fit - reference), ngs.Grad(fit - reference)),
                           problem.mesh)
    assert ngs.Integrate(ngs.InnerProduct(ngs.Grad(fit), ngs.Grad(fit)), problem.mesh) > 1e-3
    assert misfit < 1e-20


@pytest.mark.parametrize("symmetry, dirichlet, count", [
    ({}, "", 6), ({"left": "x"}, "", 3), ({"back": "y", "top": "z"}, "", 1),
    ({}, "left", 0)])
def test_pins_remove_exactly_the_rigid_motions_left_free(symmetry, dirichlet, count):
    """Pinned and fixed dofs together admit no rigid motion, and no more pins than free
    motions are used (the support stays statically determinate)."""
    time = ngs.Parameter(1.0)
    problem = GrowthMechanics(cube(maxh=0.5), IsotropicGrowth(1 + 0.25 * ngs.x * time),
                              MATERIAL, order=2, dirichlet=dirichlet, symmetry=symmetry)
    assert len(problem.pinned) == count
    free = np.array(problem.fes.FreeDofs(), dtype=bool)
    free[list(problem.pinned)] = False
    motions = []
    for cf in (ngs.CF((1, 0, 0)), ngs.CF((0, 1, 0)), ngs.CF((0, 0, 1)),
               ngs.CF((0, -ngs.z, ngs.y)), ngs.CF((ngs.z, 0, -ngs.x)), ngs.CF((-ngs.y, ngs.x, 0))):
        gf = ngs.GridFunction(problem.fes)
        gf.Set(cf)
        motions.append(gf.vec.FV().NumPy()[~free])
    assert np.linalg.matrix_rank(np.array(motions).T, tol=1e-8) == 6


@pytest.mark.parametrize("symmetry, pins", [({}, 3), ({"left": "x"}, 1),
                                            ({"left": "x", "bottom": "y"}, 0)])
def test_a_section_is_pinned_against_the_rigid_motions_its_supports_leave(symmetry, pins):
    """Of the three rigid motions of a section (two translations, the rotation about X3)
    a roller end leaves the vertical translation, a roller bottom besides it none."""
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    space = displacement_space(mesh, 2, symmetry=symmetry)
    assert len(rigid_pins(mesh, space)) == pins


def test_a_section_has_no_third_axis_to_hold():
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    with pytest.raises(ParameterError, match="symmetry axis = 'z'.*x or y"):
        displacement_space(mesh, 2, symmetry={"left": "z"})

# ---------------------------------------------------------------- the mixed formulation's pair
# Its discrete inf-sup constant on the traction-free unit cube, computed from the matrices
# (the smallest non-zero eigenvalue of B A^-1 B^T q = beta^2 M q, A the H1 inner product of
# the displacements, B the divergence against the pressures, M the pressures' mass matrix).


def _matrix(form):
    rows, cols, values = form.mat.COO()
    return sp.csr_matrix((values.NumPy(), (rows.NumPy(), cols.NumPy())),
                         shape=(form.mat.height, form.mat.width))


def inf_sup(displacements, pressures):
    u, v = displacements.TnT()
    p, q = pressures.TnT()
    a = ngs.BilinearForm((ngs.InnerProduct(ngs.Grad(u), ngs.Grad(v)) + u * v) * ngs.dx)
    b = ngs.BilinearForm(trialspace=displacements, testspace=pressures)
    b += ngs.div(u) * q * ngs.dx
    m = ngs.BilinearForm(p * q * ngs.dx)
    A, B, M = (_matrix(f.Assemble()) for f in (a, b, m))
    S = B @ spla.splu(A.tocsc()).solve(B.T.toarray())
    values = sla.eigh((S + S.T) / 2, M.toarray(), eigvals_only=True)
    return float(np.sqrt(values[values > 1e-10 * values.max()].min()))


@pytest.mark.parametrize("order", [2, 3])
def test_the_bubbles_make_the_pair_on_tetrahedra_inf_sup_stable(order):
    """Without them the constant falls with the mesh size (order 2: 0.15 at maxh 0.5, 0.036 at
    0.35, 6e-4 at 0.25); with them it stays above 0.5 (0.64, 0.57, 0.55)."""
    coarse, fine = (cube(maxh=h, elements="tet") for h in (0.5, 0.35))
    plain = [inf_sup(displacement_space(mesh, order), ngs.L2(mesh, order=order - 1))
             for mesh in (coarse, fine)]
    enriched = [inf_sup(displacement_space(mesh, order, enrichment=bubbles(mesh, order,
                                                                           "mixed")),
                        ngs.L2(mesh, order=order - 1)) for mesh in (coarse, fine)]
    assert plain[1] < 0.5 * plain[0] and plain[1] < 0.05
    assert min(enriched) > 0.4 and enriched[1] > 0.8 * enriched[0]


def test_bubbles_only_for_the_mixed_formulation_below_order_4_on_tetrahedra(unit_cube_hex,
                                                                           unit_cube_tet):
    assert bubbles(unit_cube_tet, 2, "mixed") == {"orderface": 3, "orderinner": 4}
    assert bubbles(unit_cube_tet, 4, "mixed") == {}
    assert bubbles(unit_cube_tet, 2, "displacement") == {}
    assert bubbles(unit_cube_hex, 2, "mixed") == {}


def test_a_material_with_moduli_per_region_passes_the_formulation_check():
    """Regional has no single mu or nu (each scene checks its regions' own): the check asks
    nothing of them for the displacement form and refuses the mixed one, which needs a bulk
    split; a material with one nu is still held to the displacement form's limit."""
    from ngincompat.fem.problem import check_formulation
    from ngincompat.mechanics.materials import Regional
    mesh = bilayer(length=1.0, height=0.5, cortex=0.1, maxh=0.25)
    material = Regional(mesh, {"cortex": NeoHookean.from_nu(3.0, 0.45),
                               "subcortex": NeoHookean.from_nu(1.0, 0.45)})
    check_formulation(material, "displacement", 2)
    with pytest.raises(ParameterError, match="mixed needs a bulk split"):
        check_formulation(material, "mixed", 2)
    with pytest.raises(ParameterError, match="nu"):
        check_formulation(NeoHookean.from_nu(1.0, 0.499999), "displacement", 2)


@pytest.mark.parametrize("elements, order", [("tet", 2), ("tet", 3), ("tet", 4), ("hex", 2)])
def test_the_mixed_pairs_unknowns_per_element_are_what_its_spaces_have(elements, order):
    """What the mixed formulation adds to the displacement (its pressure, and on tetrahedra of
    order 2 and 3 the bubbles' net dofs), counted on the spaces the problem builds, per
    element of a cube: within 6 % of the estimate on tetrahedra (about two faces each; the
    boundary's add a few per cent), exact on hexahedra (the pressure alone)."""
    mesh = cube(maxh=0.15 if elements == "tet" else 0.25, elements=elements)
    plain = ngs.VectorH1(mesh, order=order).ndof
    mixed = (ngs.VectorH1(mesh, order=order, **bubbles(mesh, order, "mixed")).ndof
             + ngs.L2(mesh, order=order - 1).ndof)
    rel = 0.06 if elements == "tet" else 1e-12
    assert (mixed - plain) / mesh.ne == pytest.approx(
        mixed_unknowns_per_element(elements, order), rel=rel)
