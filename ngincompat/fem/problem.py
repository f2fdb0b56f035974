"""The mechanics of a body under prescribed growth (section 2.4), and what the problems share.

Equilibrium, eq. (30) without body force, is the stationarity of the total elastic energy

    Pi(u) = int_B0 Jg Psi(Fe) dV,      Fe = (I + Grad u) Fg^-1,

over displacements u in VectorH1 of any order. Growth enters through Fg(X, t); the time is an
:class:`ngsolve.Parameter` owned by the caller, so a load step is ``time.Set(t)``.

Boundary conditions: ``dirichlet`` names boundaries where u = 0. A body with none is
traction-free and only its rigid-body motions are removed, by pinning as many displacement
components at vertices as there are motions left free (a statically determinate support, six
components at three vertices without symmetry planes: it carries no reaction for a
self-equilibrated body, so it gives the same solution as Lagrange multipliers on the rigid
modes while keeping the tangent symmetric positive definite near equilibrium).

The displacement space, the pins and the local heap here serve the coupled problem too
(:class:`~ngincompat.fem.coupled.CoupledProblem`, a sum of the energy terms of
:mod:`ngincompat.fem.terms`); its residual is compiled by :mod:`ngincompat.fem.compiler`.
"""

import numbers
from collections.abc import Iterable, Mapping, Sequence
from typing import Literal

import ngsolve as ngs
import numpy as np
from ngsolve.krylovspace import CGSolver

from ngincompat import config, parallel
from ngincompat.errors import require
from ngincompat.fem.quadrature import resolve, volume_measure
from ngincompat.fem.rigid import rigid_modes, vertex_dofs
from ngincompat.fem.solver import NewtonProblem, resolve_linear_solver
from ngincompat.mechanics import kinematics
from ngincompat.mechanics.fields import DirectionField
from ngincompat.mechanics.growth import GrowthModel
from ngincompat.mechanics.materials import (
    Material,
    MixedMaterial,
    grown_energy_density,
    intermediate_fibers,
)


def ensure_heap(order: int) -> None:
    """Raise NGSolve's local heap so the element matrices of ``order`` fit.

    The symbolic linearisation of the energy needs about 265 bytes per integration point and
    element dof: 210 MB at order 7 and 435 MB at order 8 on a hexahedron (measured; 512 x 1536
    and 729 x 2187), beyond the package's default heap
    (:data:`ngincompat.config.DEFAULT_HEAP`, "Local Heap overflow"). This asks for 400 bytes
    per (order + 1)^3 points x 3 (order + 1)^3 dofs, an upper bound for tetrahedra;
    the heap is allocated once per assembly and only the part used is touched.
    """
    config.ensure_heap(400 * 3 * (order + 1) ** 6)


#: Size (ndof) from which a :class:`~ngincompat.fem.coupled.CoupledProblem` compiles its
#: residual (and its energy at frozen growth) to machine code by default: the tangent
#: assembly then takes less than half the time, after some seconds of compilation per form
#: in every run, which pays from a few tens of tangents at this size (the coupled scenes
#: assemble 50-400, the folding and crescent previews have 16,000 dofs) and not for the small
#: problems of the tests (measured on the skin: ``docs/measurements/solver-costs.md``, "The
#: coupled residual").
REALCOMPILE_NDOF = 10000


#: The smallest Poisson's ratio of the mixed formulation. Its pressure term -p^2 / (2 lambda),
#: lambda / mu = 2 nu / (1 - 2 nu), divides by zero at nu = 0 and outweighs the elastic
#: energy a millionfold below this (nu = 1e-300 overflowed to a non-finite energy and was
#: reported as "not converged"): the mixed form is for the nearly incompressible.
MIXED_NU_MIN = 1e-6

#: The largest Poisson's ratio of the displacement formulation (lambda / mu = 5e4): nearer
#: 0.5 it locks and Newton fails (the cube's preview at nu = 0.499999 stopped "not
#: converged" at t = 0.15), where the mixed formulation converges.
DISPLACEMENT_NU_MAX = 0.49999


def check_formulation(material: Material, formulation: str, order: int) -> None:
    """Raise ParameterError unless ``formulation`` ("displacement" or "mixed") can be used with
    ``material`` at displacement ``order``: the mixed form needs a bulk split of the energy
    and order >= 2."""
    require(formulation in ("displacement", "mixed"), "formulation", formulation,
            "displacement or mixed")
    # moduli per region (Regional) have no single nu: each scene checks its own
    mu, lam = getattr(material, "mu", None), getattr(material, "lam", None)
    nu = (float(lam) / (2 * (float(lam) + float(mu)))
          if isinstance(lam, numbers.Real) and isinstance(mu, numbers.Real) else None)
    if formulation == "displacement" and nu is not None:
        require(nu <= DISPLACEMENT_NU_MAX, "nu", round(nu, 12),
                f"<= {DISPLACEMENT_NU_MAX:g} for the displacement formulation, which locks "
                "nearer incompressibility: use formulation=mixed")
    if formulation == "mixed":
        require(isinstance(material, MixedMaterial), "formulation", formulation,
                f"displacement for the {material.name} material (mixed needs a bulk split "
                "of the energy, as neo-hookean has)")
        require(order >= 2, "order", order, ">= 2 for the mixed formulation")
        if nu is not None:
            require(nu >= MIXED_NU_MIN, "nu", round(nu, 12) if nu >= 1e-12 else nu,
                    f"in [{MIXED_NU_MIN:g}, 0.5) for the mixed formulation (its pressure "
                    "term p^2 / (2 lambda) needs lambda / mu >= 2e-6; a compressible body "
                    "is the displacement formulation's)")


class GrowthMechanics:
    """The discrete energy minimisation problem for a growth model and a material.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    growth : GrowthModel
        See :mod:`ngincompat.mechanics.growth`.
    material : Material
        See :mod:`ngincompat.mechanics.materials`.
    order : int
        Polynomial order of the displacement, >= 1.
    fibers : sequence of DirectionField
        Reference fiber directions a0 for anisotropic materials.
    dirichlet : str
        Regular expression of boundaries with u = 0; empty for a traction-free body.
    symmetry : dict, optional
        Symmetry planes: ``{"flat": "z"}`` sets the displacement component normal to the
        boundary ``flat`` (a plane X3 = const) to zero. The rigid-body pins of a body without
        ``dirichlet`` then remove only the motions the planes leave free.
    condense : bool
        Static condensation of element-interior dofs (exact; cheaper factorisation).
    formulation : {"displacement", "mixed"}
        "mixed" adds a pressure p, discontinuous of order - 1, and replaces the bulk term
        lam/2 g(Je)^2 of the energy by p g(Je) - p^2 / (2 lam) (a perturbed Lagrangian: at
        stationarity in p, p = lam g and the energies agree). The constraint g = 0 is then
        enforced only against the pressure space, which removes the volumetric locking of
        nearly incompressible materials (lam >> mu); p is element-local and condensed. On
        tetrahedra of order 2 and 3 the displacement has bubbles (:func:`bubbles`), without
        which this pair is not inf-sup stable and locks itself. The
        problem is a saddle point, so the line search tests the residual instead of the energy.
        Needs a :class:`~ngincompat.mechanics.materials.MixedMaterial`, one with such a bulk term
        (neo-Hookean, g = ln Je), and order >= 2.
    components : bool or None
        Assemble the energy on three scalar H1 spaces (:func:`component_space`): the same
        energy, residual and tangent as on VectorH1, the tangent in half the time. False
        assembles it on VectorH1, as NGSolve's BDDC preconditioner ("cg", "gmres") needs:
        built on the component spaces, its coarse problem is singular (GMRES then stalls on
        the cube). None: as ``linear_solver`` needs.
    linear_solver : str
        Newton's linear solver for this problem (:data:`~ngincompat.fem.solver.LINEAR_SOLVERS`;
        "auto" resolved by :func:`~ngincompat.fem.solver.resolve_linear_solver` for its size
        and its ``iterative``, the attribute ``linear_solver`` the solver it means): it
        decides ``components`` where that is None, component spaces for "direct" and "amg".
    quadrature : {"gauss", "symmetric", "auto"}
        The rule of energy, residual and tangent (:mod:`ngincompat.fem.quadrature`): NGSolve's
        Gauss rule of degree 2 order - 2, or on tetrahedra the symmetric rule of that degree
        with about a third of the points at order 6; "auto" the symmetric one where it has at
        most half the points. The rule taken is the attribute ``quadrature``.
    coarse : {"edges", "vertices"}
        The coarse space of the BDDC preconditioner of "cg" and "gmres"
        (:data:`COARSE_SPACES`), also of the distributed compatible fit's.
    """

    def __init__(self, mesh: ngs.Mesh, growth: GrowthModel, material: Material, order: int = 2,
                 fibers: Sequence[DirectionField] = (), dirichlet: str = "",
                 symmetry: Mapping[str, str] | None = None, condense: bool = True,
                 formulation: Literal["displacement", "mixed"] = "displacement",
                 components: bool | None = None, quadrature: str = "gauss",
                 linear_solver: str = "auto", coarse: str = "edges") -> None:
        require(isinstance(order, int) and order >= 1, "order", order, "an integer >= 1")
        check_formulation(material, formulation, order)
        self.quadrature = resolve(quadrature, mesh, order)
        dx = volume_measure(mesh, order, self.quadrature)
        mixed = formulation == "mixed"
        ensure_heap(order)
        if material.needs_fibers:
            require(len(fibers) > 0, "fibers", fibers, "at least one fiber direction for GOH")
        self.mesh = mesh
        self.growth = growth
        self.material = material
        self.order = order
        self.fibers = tuple(fibers)
        self.condense = condense
        self.formulation = formulation
        symmetry = dict(symmetry or {})
        self.bubbles = bubbles(mesh, order, formulation)
        self.coarse = coarse
        self.space = displacement_space(mesh, order, dirichlet, symmetry, self.bubbles, coarse)
        if mixed:
            self.fes = ngs.FESpace([self.space, ngs.L2(mesh, order=order - 1)])
            self.state = ngs.GridFunction(self.fes, name="state")
            self.u, self.pressure = self.state.components
            self.has_energy = False
            self.inverse = "sparsecholesky" if condense else "umfpack"
            # a saddle point whose pressure is element-local: condensed, CG solves it (asked
            # for by name), but "auto" keeps the factorisation, which the atrophy scene's
            # ellipsoid solves faster at its size (docs/performance.md, "Where auto switches
            # to CG")
            self.iterative = None
        else:
            self.fes = self.space
            self.u = self.state = ngs.GridFunction(self.fes, name="displacement")
            self.pressure = None
        # the space's own array, which NGSolve's BDDC preconditioner reads: pins cleared in it
        self.freedofs = self.fes.FreeDofs(coupling=condense)
        if not dirichlet:
            self.pinned = rigid_pins(mesh, self.fes)
            for dof in self.pinned:
                self.freedofs.Clear(dof)
        else:
            self.pinned = ()
        self._fit_inverse: _ComponentLaplaceInverse | None = None
        self.linear_solver = resolve_linear_solver(linear_solver, mesh, self.fes.ndof,
                                                   self.iterative)
        if components is None:
            components = self.linear_solver in ("direct", "amg")
        if components:
            form_space = component_space(self.space, [self.fes.components[1]] if mixed else [],
                                         self.bubbles)
            trial = form_space.TrialFunction()
            F = kinematics.component_deformation_gradient(trial[:3])
            pressure = trial[3] if mixed else None
        else:
            form_space = self.fes
            trial = self.fes.TrialFunction()
            F = kinematics.deformation_gradient(trial[0] if mixed else trial)
            pressure = trial[1] if mixed else None
        density = self._density(F, pressure)
        self.form = ngs.BilinearForm(form_space, symmetric=True, condense=condense)
        self.form += ngs.Variation(density.Compile() * dx)

    has_energy = True
    inverse = "sparsecholesky"
    #: The iterative solver its tangent suits, the Hessian of an energy (symmetric, positive
    #: definite near a stable equilibrium): "auto" takes it for a large problem. CG with the
    #: smoothed-aggregation multigrid: above the switch faster and leaner than CG with BDDC,
    #: its iterations flat as the mesh is refined (``docs/performance.md``, "Where auto
    #: switches to CG").
    iterative: str | None = "amg"

    @property
    def ndof(self) -> int:
        """Number of unknowns (over all ranks of a distributed mesh)."""
        return self.fes.ndofglobal

    def fibers_intermediate(self) -> tuple[ngs.CoefficientFunction, ...]:
        """Fiber directions pushed to the intermediate configuration, Fg a0 / |Fg a0| (eq. 39)."""
        return intermediate_fibers(self.growth.Fg, self.fibers)

    def _density(self, F: ngs.CoefficientFunction,
                 p: ngs.CoefficientFunction | None = None) -> ngs.CoefficientFunction:
        """Jg Psi(Fe), Fe = F Fg^-1; with a pressure p, the mixed form of the bulk term."""
        if p is None:
            return grown_energy_density(F, self.growth, self.material, self.fibers)
        # with a pressure the material is a MixedMaterial (check_formulation)
        rest, g = self.material.bulk_split(  # type: ignore[attr-defined]
            kinematics.elastic_part(F, self.growth.Fg))
        return self.growth.Jg * (rest + p * g
                                 - p * p / (2 * self.material.lam))  # type: ignore[attr-defined]

    def frozen_tangent(self) -> ngs.BaseMatrix:
        """The tangent of the equilibrium at the current state (the growth is prescribed),
        assembled into and returned as ``form.mat``: the Hessian of the energy, condensed as
        the problem is (mixed: the pressure eliminated)."""
        self.form.AssembleLinearization(self.state.vec)
        return self.form.mat

    def energy_density(self, F: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """Strain energy per reference volume, Jg Psi(Fe) with Fe = F Fg^-1 (mixed: with the
        computed pressure in the bulk term, so its derivative is the mixed stress)."""
        return self._density(F, self.pressure)

    def strain_energy(self, degree: int | None = None) -> float:
        """Total elastic energy int Jg Psi dV of the current state (mixed: the value of the
        discrete saddle-point functional); summed over the ranks of a distributed mesh.

        By the form's own rule, or with ``degree`` integrated again by NGSolve's Gauss rule
        of that degree (the check of a cheaper rule, see :mod:`ngincompat.fem.quadrature`)."""
        if degree is not None:
            F = kinematics.deformation_gradient(self.u)
            return ngs.Integrate(self.energy_density(F), self.mesh, order=degree)
        return parallel.total(self.mesh, self.form.Energy(self.state.vec))

    def growth_load(self) -> ngs.BaseVector:
        """The vector f with f . v = int (Fg - I) : Grad v dV, at the current growth time."""
        v = self.space.TestFunction()
        form = ngs.LinearForm(ngs.InnerProduct(self.growth.Fg - ngs.Id(3), ngs.Grad(v)) * ngs.dx)
        load = self.u.vec.CreateVector()
        load.data = form.Assemble().vec
        return load

    def compatible_displacement(self, load: ngs.BaseVector) -> ngs.BaseVector:
        """The best compatible approximation of a growth increment: the displacement w that
        minimises int |Grad w - dFg|^2 dV, given ``load`` = f(dFg) (see :meth:`growth_load`).

        A growth step that starts from u + w instead of u begins close to the stress-free state
        it would reach if dFg were compatible, so Newton starts in its quadratic range. The
        minimisation decouples into one scalar Laplace problem per displacement component
        (VectorH1 stores its three H1 components one after the other), so a single scalar
        stiffness matrix is assembled, about a thirtieth of the cost of the vector one at
        order 5, and factorised once per distinct set of free dofs; the factorisations are
        reused. The rigid-body pins do not constrain the fit (the Laplacian has no rotational
        kernel, and pinning rotations linearly would strain it); a component free everywhere
        is only anchored at one dof against its constant.
        """
        if self._fit_inverse is None:
            self._fit_inverse = _ComponentLaplaceInverse(self.space, self.bubbles, self.coarse)
        return self._fit_inverse.solve(load)


class _ComponentLaplaceInverse:
    """The inverse of the vector Laplacian on VectorH1, applied component by component with
    one scalar H1 stiffness matrix of the same order: in a serial run by its sparse Cholesky
    factorisations (one per distinct set of free dofs, reused), on a distributed mesh, which
    has no direct solver, by CG preconditioned with BDDC (whose element matrices on the
    scalar space are a ninth of the vector space's). Free dofs per component as in ``fes``; a
    component without fixed dofs is anchored against its constant at one vertex (the first,
    or on a distributed mesh the one with the lexicographically smallest coordinates; the
    anchor only shifts the fit by a translation). BDDC's coarse space is that of ``coarse``
    (:data:`COARSE_SPACES`)."""

    def __init__(self, fes: ngs.FESpace, enrichment: Mapping[str, int] | None = None,
                 coarse: str = "edges") -> None:
        mesh = fes.mesh
        self.distributed = parallel.distributed(mesh)
        scalar = wirebasket(ngs.H1(mesh, order=fes.globalorder, **(enrichment or {})), coarse)
        self.n = scalar.ndof
        require(3 * self.n == fes.ndof, "displacement space", fes,
                "VectorH1 of three H1 components")
        s, t = scalar.TnT()
        lap = ngs.BilinearForm(scalar, symmetric=True)
        lap += ngs.grad(s) * ngs.grad(t) * ngs.dx
        bddc = ngs.Preconditioner(lap, "bddc") if self.distributed else None
        lap.Assemble()
        mask = np.array(fes.FreeDofs(), dtype=bool)
        anchor = self._anchor(mesh, scalar)
        self.inverses, self._fixed, made = [], [], {}
        for c in range(3):
            free = mask[c * self.n:(c + 1) * self.n].copy()
            if parallel.total(mesh, np.count_nonzero(~free)) == 0:
                free[anchor] = False
            key = free.tobytes()
            if key not in made:
                bits = ngs.BitArray(self.n)
                bits.Clear()
                for i in np.flatnonzero(free):
                    bits.Set(int(i))
                if self.distributed:
                    project = ngs.Projector(bits, True)
                    made[key] = CGSolver(lap.mat,
                                         project @ bddc.mat @ project,  # type: ignore[union-attr]
                                         tol=1e-10, maxiter=2000)
                else:
                    made[key] = lap.mat.Inverse(bits, inverse="sparsecholesky")
            self.inverses.append(made[key])
            self._fixed.append(~free)
        self._rhs = lap.mat.CreateColVector()
        self._sol = lap.mat.CreateColVector()

    def _anchor(self, mesh: ngs.Mesh, scalar: ngs.FESpace) -> list[int]:
        """The scalar dofs of the anchor vertex on this rank (none if it is elsewhere)."""
        if not self.distributed:
            return [scalar.GetDofNrs(ngs.NodeId(ngs.VERTEX, 0))[0]]
        pts = np.array([p.point for p in mesh.vertices]).reshape(-1, 3)
        corner = np.unique(parallel.gather_rows(mesh, pts), axis=0)[0]
        return [scalar.GetDofNrs(ngs.NodeId(ngs.VERTEX, i))[0]
                for i, p in enumerate(pts) if np.array_equal(p, corner)]

    def solve(self, load: ngs.BaseVector) -> ngs.BaseVector:
        """w = L^-1 load on the free dofs, zero on the others, one component at a time."""
        w = load.CreateVector()
        f, x = load.FV().NumPy(), w.FV().NumPy()
        for c, inverse in enumerate(self.inverses):
            block = slice(c * self.n, (c + 1) * self.n)
            self._rhs.FV().NumPy()[:] = f[block]
            self._rhs.FV().NumPy()[self._fixed[c]] = 0.0
            if self.distributed:
                self._rhs.SetParallelStatus(load.GetParallelStatus())
            self._sol.data = inverse * self._rhs
            if self.distributed:
                self._sol.Cumulate()
            x[block] = self._sol.FV().NumPy()
        if self.distributed:
            w.SetParallelStatus(self._sol.GetParallelStatus())
        return w


def component_space(space: ngs.FESpace, rest: Sequence[ngs.FESpace] = (),
                    enrichment: Mapping[str, int] | None = None) -> ngs.FESpace:
    """The space of the energy form: the displacement space ``space`` (VectorH1) as three
    scalar H1 spaces of its order (and its ``enrichment``, :func:`bubbles`), followed by the
    spaces ``rest``.

    VectorH1 stores its three H1 components one after the other, so the compound has the
    same dofs in the same order and every vector and matrix of the one is one of the other
    (the boundary conditions stay with ``space``: the form needs none). The tangent of the
    energy is the same matrix, but NGSolve assembles it per pair of components, skipping
    the zero blocks of Grad u's derivative with respect to the dofs, which VectorH1's
    tangent multiplies through: half the time of the element matrices on the cube's
    tetrahedra of order 6 (``docs/measurements/solver-costs.md``, "The cube's tangent").
    """
    scalar = ngs.H1(space.mesh, order=space.globalorder, **(enrichment or {}))
    compound = ngs.FESpace([scalar] * 3 + list(rest))
    require(compound.ndof == space.ndof + sum(r.ndof for r in rest), "displacement space",
            space, "VectorH1 of three H1 components")
    return compound


#: Displacement orders at which the mixed formulation on tetrahedra gets bubbles
#: (:func:`bubbles`): below 4 its stress locked as nu -> 0.5 without them.
BUBBLE_ORDERS = (2, 3)


def bubbles(mesh: ngs.Mesh, order: int, formulation: str) -> dict[str, int]:
    """The enrichment of the displacement space (NGSolve's H1 flags) that makes the mixed
    formulation's pair inf-sup stable on a mesh of tetrahedra: face bubbles of ``order`` + 1
    and interior bubbles of ``order`` + 2 (for order 2 the three-dimensional Crouzeix-Raviart
    element, P2 + bubbles against P1 discontinuous); {} otherwise.

    Without them P_k against P_(k-1) discontinuous is not stable on tetrahedra: the discrete
    inf-sup constant of the traction-free cube falls towards 0 as the mesh is refined, and
    the cube's stress grew some fifty-fold from nu = 0.45 to 0.49999 at order 2; with them
    the constant stays above 0.5 and the stress within 5 % of the hexahedra's
    (``docs/measurements/mixed.md``). From order 4 on the stress did not lock, and the
    bubbles are not added (their cost grows with the order). The interior bubbles are
    condensed; the face bubbles add global unknowns (twice as many at order 2)."""
    if formulation != "mixed" or order not in BUBBLE_ORDERS:
        return {}
    others = sum(el.type != ngs.ET.TET for el in mesh.Elements(ngs.VOL))
    if parallel.total(mesh, others) > 0:
        return {}
    return {"orderface": order + 1, "orderinner": order + 2}


def mixed_unknowns_per_element(shape: str, order: int) -> float:
    """About how many unknowns the mixed formulation of ``order`` k adds per element of
    ``shape`` ("tet", "hex" or "triangle") to the displacement's: its pressure, discontinuous
    of order k - 1 (k (k + 1) (k + 2) / 6 on a tetrahedron, k^3 on a hexahedron, k (k + 1) / 2
    on a triangle), and on tetrahedra at :data:`BUBBLE_ORDERS` the bubbles of :func:`bubbles`:
    3 components of the face bubbles of order k + 1 on about two faces per tetrahedron (an
    inner face is shared by two) and of the interior ones of order k + 2, less those of order
    k the displacement has: 13 per tetrahedron at k = 2, 34 at k = 3."""
    k = order
    if shape == "tet":
        extra = k * (k + 1) * (k + 2) / 6
        if k in BUBBLE_ORDERS:
            def face(p: int) -> float:          # a triangle's bubbles of order p
                return (p - 1) * (p - 2) / 2

            def inner(p: int) -> float:         # a tetrahedron's bubbles of order p
                return (p - 1) * (p - 2) * (p - 3) / 6
            extra += 3 * (2 * (face(k + 1) - face(k)) + inner(k + 2) - inner(k))
        return extra
    return k ** 3 if shape == "hex" else k * (k + 1) / 2


#: The coarse spaces of NGSolve's BDDC preconditioner (``linear_solver`` cg or gmres), its
#: wirebasket: "edges", the vertex and edge dofs (NGSolve's default in three dimensions; at
#: order 2 every dof of the condensed system but the mixed formulation's face bubbles, so CG
#: needs few iterations and the coarse problem, factorised on rank 0 of a distributed run,
#: is nearly the whole system), or "vertices", the vertex dofs alone (a coarse problem of
#: three unknowns per vertex: rank 0 lighter than the workers on the atrophy ellipsoid, at
#: several times the CG iterations; on the fsaverage brain CG with it stopped at its
#: iteration limit and Newton's first step failed;
#: ``docs/measurements/mpi.md``, "Rank 0 and the coarse space").
COARSE_SPACES = ("edges", "vertices")


def displacement_space(mesh: ngs.Mesh, order: int, dirichlet: str = "",
                       symmetry: Mapping[str, str] | None = None,
                       enrichment: Mapping[str, int] | None = None,
                       coarse: str = "edges") -> ngs.FESpace:
    """VectorH1 of ``order`` (with the H1 flags ``enrichment``, :func:`bubbles`) with u = 0
    on ``dirichlet`` and the normal component zero on the symmetry planes (boundary name ->
    axis "x", "y" or "z"; "x" or "y" on the section of a body in plane strain, a mesh of
    dimension 2); its wirebasket, BDDC's coarse space, is that of ``coarse``
    (:data:`COARSE_SPACES`)."""
    symmetry = dict(symmetry or {})
    axes = ("x", "y", "z")[:mesh.dim]
    for name, axis in symmetry.items():
        require(axis in axes, "symmetry axis", axis, " or ".join(axes))
        require(name in mesh.GetBoundaries(), "symmetry boundary", name,
                ", ".join(sorted(set(mesh.GetBoundaries()))))
    planes = {f"dirichlet{axis}": "|".join(n for n, a in symmetry.items() if a == axis)
              for axis in axes if axis in symmetry.values()}
    return wirebasket(ngs.VectorH1(mesh, order=order, dirichlet=dirichlet, **planes,
                                   **(enrichment or {})), coarse)


def wirebasket(space: ngs.FESpace, coarse: str) -> ngs.FESpace:
    """``space`` with the wirebasket of the coarse space ``coarse`` (:data:`COARSE_SPACES`):
    its edge dofs made wirebasket or interface dofs where NGSolve's default (the edges in
    three dimensions, the vertices alone in two) is the other. Set on the dofs, not by the
    H1 flag ``wb_withedges``, which VectorH1 takes but reports on every construction as an
    undocumented option."""
    require(coarse in COARSE_SPACES, "coarse", coarse, " or ".join(COARSE_SPACES))
    edges = coarse == "edges"
    if edges == (space.mesh.dim == 3):
        return space
    kinds = ngs.COUPLING_TYPE.WIREBASKET_DOF, ngs.COUPLING_TYPE.INTERFACE_DOF
    old, new = kinds[::-1] if edges else kinds
    for edge in space.mesh.edges:
        for dof in space.GetDofNrs(edge):
            if dof >= 0 and space.CouplingType(dof) == old:
                space.SetCouplingType(dof, new)
    return space


def rigid_pins(mesh: ngs.Mesh, fes: ngs.FESpace, held: Iterable[int] = ()) -> tuple[int, ...]:
    """Displacement dofs at vertices whose pinning removes exactly the rigid-body motions
    that the boundary conditions of ``fes`` and the dofs ``held`` (fixed besides them)
    leave free.

    ``fes`` is the displacement space (VectorH1), or a compound space whose first component
    it is. A rigid motion t + w x X is interpolated exactly by vertex dofs alone, so the six
    modes are known at every vertex dof. Those that vanish on the dofs already fixed (e.g. by
    symmetry planes: one plane leaves three motions, two perpendicular planes one, a clamped
    face none) span the free motions, of dimension k. Dofs are taken greedily, each only if
    it constrains a motion the ones before leave free, until k are pinned; the order of
    preference is the "3-2-1" support: all of P0 (smallest coordinate sum), the components
    of P1 (farthest from P0) across the line P0-P1, the component of P2 (farthest from that
    line) normal to the plane P0 P1 P2 (in plane strain: P0, and P1 across the line), then
    the other dofs. Pins across the line leave the
    body free to stretch along it, so the pinned values (from the predictor) cost no
    rotation that Newton would have to undo. The support is statically determinate: it
    carries no reaction for a self-equilibrated body, gives the same deformation as Lagrange
    multipliers on the modes, and keeps the tangent symmetric positive definite near
    equilibrium.
    """
    d = mesh.dim
    pts, dofs = vertex_dofs(fes)
    free = np.array(fes.FreeDofs(), dtype=bool)
    free[list(held)] = False
    free = free[dofs]
    if not parallel.distributed(mesh):
        return tuple(int(dofs[v, c]) for v, c in _pin_nodes(pts, free))
    # every rank chooses from all vertices (each once), then pins its own copies of them
    table = np.unique(parallel.gather_rows(mesh, np.column_stack([pts, free])), axis=0)
    local = {tuple(p): i for i, p in enumerate(pts)}
    return tuple(int(dofs[local[tuple(table[v, :d])], c])
                 for v, c in _pin_nodes(table[:, :d], table[:, d:].astype(bool))
                 if tuple(table[v, :d]) in local)


def pin_reactions(problem: NewtonProblem) -> np.ndarray:
    """The forces the rigid-body pins of ``problem`` exert in its current state: the
    residual (internal force) at the pinned dofs, which only the pins balance. For a
    self-equilibrated body in equilibrium they vanish (the residual is orthogonal to the
    rigid motions, which the pins alone constrain)."""
    residual = problem.state.vec.CreateVector()
    problem.form.Apply(problem.state.vec, residual)
    return residual.FV().NumPy()[list(problem.pinned)].copy()


def _pin_nodes(pts: np.ndarray, free: np.ndarray) -> list[tuple[int, int]]:
    """The (vertex, component) pairs that :func:`rigid_pins` pins, for vertex coordinates
    ``pts`` (n, d) and the free flags ``free`` of their d displacement components."""
    modes = rigid_modes(pts)
    fixed = modes[~free]
    basis = np.eye(modes.shape[2])
    if len(fixed):
        _, s, vt = np.linalg.svd(fixed)
        basis = vt[int(np.sum(s > 1e-10 * s[0])):].T
    pinned: list[tuple[int, int]]
    pinned, chosen = [], np.zeros((0, basis.shape[1]))
    for v, c in _support_preference(pts):
        if len(pinned) == basis.shape[1]:
            break
        if not free[v, c]:
            continue
        trial = np.vstack([chosen, modes[v, c] @ basis])
        if np.linalg.matrix_rank(trial, tol=1e-8) > len(chosen):
            chosen = trial
            pinned.append((v, c))
    return pinned


def _support_preference(pts: np.ndarray) -> list[tuple[int, int]]:
    """(vertex, component) pairs in the order of preference of :func:`rigid_pins`."""
    d = pts.shape[1]
    i0 = int(np.argmin(pts.sum(axis=1)))
    r = pts - pts[i0]
    i1 = int(np.argmax(np.linalg.norm(r, axis=1)))
    axis = r[i1] / np.linalg.norm(r[i1])
    k1 = int(np.argmax(np.abs(axis)))
    first = [(i0, k) for k in range(d)] + [(i1, k) for k in range(d) if k != k1]
    if d == 3:
        i2 = int(np.argmax(np.linalg.norm(r - np.outer(r @ axis, axis), axis=1)))
        first.append((i2, int(np.argmax(np.abs(np.cross(axis, r[i2]))))))
    rest = [(v, c) for v in range(len(pts)) for c in range(d) if (v, c) not in first]
    return first + rest
