"""The mechanics of a growing body (section 2.4): the only module that builds FESpaces and forms.

Equilibrium, eq. (30) without body force, is the stationarity of the total elastic energy

    Pi(u) = int_B0 Jg Psi(Fe) dV,      Fe = (I + Grad u) Fg^-1,

over displacements u in VectorH1 of any order. Growth enters through Fg(X, t); the time is an
:class:`ngsolve.Parameter` owned by the caller, so a load step is ``time.Set(t)``.

Boundary conditions: ``dirichlet`` names boundaries where u = 0. A body with none is
traction-free and only its six rigid-body motions are removed, by pinning six displacement
components at three vertices (a statically determinate "3-2-1" support: it carries no reaction
for a self-equilibrated body, so it gives the same solution as Lagrange multipliers on the rigid
modes while keeping the tangent symmetric positive definite near equilibrium).
"""

import ngsolve as ngs
import numpy as np

from . import kinematics
from .errors import require


class GrowthMechanics:
    """The discrete energy minimisation problem for a growth model and a material.

    Parameters
    ----------
    mesh : ngsolve.Mesh
    growth : growth model (see :mod:`ngincompat.growth`)
    material : material (see :mod:`ngincompat.materials`)
    order : int
        Polynomial order of the displacement, >= 1.
    fibers : sequence of DirectionField
        Reference fiber directions a0 for anisotropic materials.
    dirichlet : str
        Regular expression of boundaries with u = 0; empty for a traction-free body.
    symmetry : dict, optional
        Symmetry planes: ``{"flat": "z"}`` sets the displacement component normal to the
        boundary ``flat`` (a plane X3 = const) to zero. The rigid-body pins of a body without
        ``dirichlet`` are then placed on these boundaries, where they only remove the motions
        the planes leave free.
    condense : bool
        Static condensation of element-interior dofs (exact; cheaper factorisation).
    """

    def __init__(self, mesh, growth, material, order=2, fibers=(), dirichlet="", symmetry=None,
                 condense=True):
        require(isinstance(order, int) and order >= 1, "order", order, "an integer >= 1")
        if material.needs_fibers:
            require(len(fibers) > 0, "fibers", fibers, "at least one fiber direction for GOH")
        self.mesh = mesh
        self.growth = growth
        self.material = material
        self.order = order
        self.fibers = tuple(fibers)
        self.condense = condense
        symmetry = dict(symmetry or {})
        for name, axis in symmetry.items():
            require(axis in ("x", "y", "z"), "symmetry axis", axis, "x, y or z")
            require(name in mesh.GetBoundaries(), "symmetry boundary", name,
                    ", ".join(sorted(set(mesh.GetBoundaries()))))
        planes = {f"dirichlet{axis}": "|".join(n for n, a in symmetry.items() if a == axis)
                  for axis in ("x", "y", "z") if axis in symmetry.values()}
        self.fes = ngs.VectorH1(mesh, order=order, dirichlet=dirichlet, **planes)
        self.u = ngs.GridFunction(self.fes, name="displacement")
        self.freedofs = self.fes.FreeDofs(coupling=condense)
        if not dirichlet:
            self.pinned = self._pin_rigid_modes(tuple(symmetry))
            for dof in self.pinned:
                self.freedofs.Clear(dof)
        else:
            self.pinned = ()
        self._fit_inverse = None
        trial = self.fes.TrialFunction()
        density = self.energy_density(kinematics.deformation_gradient(trial))
        self.form = ngs.BilinearForm(self.fes, symmetric=True, condense=condense)
        self.form += ngs.Variation(density.Compile() * ngs.dx)

    @property
    def ndof(self):
        return self.fes.ndof

    def fibers_intermediate(self):
        """Fiber directions pushed to the intermediate configuration, Fg a0 / |Fg a0| (eq. 39)."""
        Fg = self.growth.Fg
        pushed = []
        for f in self.fibers:
            v = Fg * f.cf
            pushed.append(v / ngs.Norm(v))
        return tuple(pushed)

    def energy_density(self, F):
        """Strain energy per reference volume, Jg Psi(Fe) with Fe = F Fg^-1."""
        Fe = kinematics.elastic_part(F, self.growth.Fg)
        return self.growth.Jg * self.material.energy(Fe, self.fibers_intermediate())

    def strain_energy(self):
        """Total elastic energy int Jg Psi dV of the current state."""
        return self.form.Energy(self.u.vec)

    def growth_load(self):
        """The vector f with f . v = int (Fg - I) : Grad v dV, at the current growth time."""
        v = self.fes.TestFunction()
        form = ngs.LinearForm(ngs.InnerProduct(self.growth.Fg - ngs.Id(3), ngs.Grad(v)) * ngs.dx)
        load = self.u.vec.CreateVector()
        load.data = form.Assemble().vec
        return load

    def compatible_displacement(self, load):
        """The best compatible approximation of a growth increment: the displacement w that
        minimises int |Grad w - dFg|^2 dV, given ``load`` = f(dFg) (see :meth:`growth_load`).

        A growth step that starts from u + w instead of u begins close to the stress-free state
        it would reach if dFg were compatible, so Newton starts in its quadratic range. The
        factorisation of the vector Laplacian is made once and reused. Of the rigid-body pins
        only the translation (the first vertex) constrains the fit: the Laplacian has no
        rotational kernel, and pinning rotations linearly would strain the fit.
        """
        if self._fit_inverse is None:
            u, v = self.fes.TnT()
            lap = ngs.BilinearForm(ngs.InnerProduct(ngs.Grad(u), ngs.Grad(v)) * ngs.dx)
            free = self.fes.FreeDofs()
            for dof in self.pinned[:3]:
                free.Clear(dof)
            self._fit_inverse = lap.Assemble().mat.Inverse(free, inverse="sparsecholesky")
        w = load.CreateVector()
        w.data = self._fit_inverse * load
        return w

    def _pin_rigid_modes(self, on=()):
        """Dofs of six displacement components at three vertices that remove rigid motions.

        With symmetry planes, the vertices are taken on them (``on``: boundary names), so the
        pins add no constraint beyond the planes other than removing the remaining motions.

        P0 is fixed; at P1 (the vertex farthest from P0, d = P1 - P0) the two components other
        than d's largest are fixed, which leaves only rotations about d; at P2 (farthest from the
        line P0-P1) the largest component of d x (P2 - P0) is fixed, which removes that rotation.
        """
        pts = np.array([v.point for v in self.mesh.vertices])
        if on:
            keep = sorted({v.nr for el in self.mesh.Elements(ngs.BND) if el.mat in on
                           for v in el.vertices})
            index = np.array(keep)
        else:
            index = np.arange(len(pts))
        i0, i1, i2 = index[self._three_vertices(pts[index])]
        d = pts - pts[i0]
        axis = d[i1] / np.linalg.norm(d[i1])
        k1 = int(np.argmax(np.abs(axis)))
        k2 = int(np.argmax(np.abs(np.cross(axis, d[i2]))))
        comps = [(i0, 0), (i0, 1), (i0, 2)] + [(i1, k) for k in range(3) if k != k1] + [(i2, k2)]
        return tuple(self.fes.GetDofNrs(ngs.NodeId(ngs.VERTEX, int(v)))[c] for v, c in comps)

    @staticmethod
    def _three_vertices(pts):
        """Indices of P0 (smallest coordinate sum), P1 (farthest from P0) and P2 (farthest
        from the line P0-P1) among ``pts``."""
        i0 = int(np.argmin(pts.sum(axis=1)))
        d = pts - pts[i0]
        i1 = int(np.argmax(np.linalg.norm(d, axis=1)))
        axis = d[i1] / np.linalg.norm(d[i1])
        dist_line = np.linalg.norm(d - np.outer(d @ axis, axis), axis=1)
        i2 = int(np.argmax(dist_line))
        return [i0, i1, i2]
