"""Frictionless self-contact of a boundary: the walls of a fold may touch but not pass through
each other.

Every point X of the boundary Gamma (current place x = X + u) is paired with the closest point
Y of Gamma among the parts that face it (outward normals more than 90 degrees apart: the
opposite wall of a fold, never the point's own neighbourhood), within the distance ``reach``.
The gap of the pair is

    g(X) = (x(Y) - x(X)) . n(X),

n the outward normal at x(X): positive while the walls are apart, negative where X has passed
through the other wall. The contact is enforced by a penalty kappa on the ramp rounded over
the penetration ``width`` eps of :func:`~ngincompat.fem.contact.ramp` (r(s) = max(s, 0) with
its kink smoothed so that the tangent does not jump, R its integral), with the energy

    Pi_c = (kappa / 2) int_Gamma w R(-g) dA       (reference area),

w = 1 for a pair that lies along the normal (x(Y) - x(X) within 25.8 degrees of n(X), cos =
0.9, in the state of the last update) and 0 otherwise. Around the bottom of a narrow sulcus
the search also pairs points across the bend at oblique angles, behind each other's tangent
plane although the walls do not overlap: on the coarse bilayer with a refined top creasing
at 49.5 days their penalty pushed the crease's walls apart with forces the measures (which
count only pairs along the normal) did not see, a residual that every update of the pairs
renewed whatever the step (1.0e-3 at the start of steps of 0.02 and of 0.0025 days), so that
cutting the step did not help Newton.

Every touching pair is met twice, once from each wall, so the half: two flat walls pressed
into each other by the penetration delta carry the pressure p = kappa r(delta) (= kappa delta
with eps = 0), and the penetration of a wall under the pressure p is about p / kappa + eps / 2.

The pairs and the normals are those of the state of the last :meth:`SelfContact.update` (the
start of the step: :meth:`SelfContact.accept_step` updates them); within a step Pi_c is then
a smooth function of u, whose residual and tangent NGSolve assembles exactly by symbolic
differentiation. A point that comes into contact during a step is paired if it was within
``reach`` of the other wall at the step's start, so ``reach`` must exceed the walls' approach
per step.

Why NGSolve's ``ContactBoundary``: it pairs the points of one boundary region with the same
region (self-contact: the facing test above excludes a point's own element and its
neighbours on a smooth surface), searches with a bounding-box tree in C++, evaluates the other
point's displacement through ``u.Other()`` on curved elements of any order, and adds the pairs
to the problem's form as extra elements whose energy it differentiates symbolically: the
exact tangent of Pi_c with frozen pairs, and it takes part in the static condensation and the
compound space of a :class:`~ngincompat.fem.coupled.CoupledProblem` (checked against the
closed form of two blocks pressed together, tests/fem/test_self_contact.py). Its limits, taken
here: the pairs and normals are frozen between updates (no linearisation of the closest-point
projection), and its gap function's evaluation keeps the displacement of the last update, so
the measures (:meth:`SelfContact.measures`) use a third ``ContactBoundary`` updated with the
current state, whose gap function, unlike the energy's pairs, also pairs neighbours on one
smooth wall: the measures count a pair only along the normal, and evaluate it at NGSolve's
own mapped points (points located by coordinates missed pairs of the two blocks' test).
A body in plane strain is meshed by its section (a two-dimensional mesh): its boundary is
a curve, the contact's integrals are per unit length out of plane.

*Mirror walls.* A body cut by a symmetry plane (rollers: the normal displacement held on the
plane) stands for itself and its mirror image. A sulcus centred on the plane has its second
wall in the image, which the pair search never sees: without it the wall creases across the
plane into its own image and the march stalls (``docs/measurements/folding.md``, "Why it
stalled at 62 days"). Each plane (point P, unit normal m into the body) gives
the pair of X with its own image, along m, and the gap

    g_m(X) = 2 (x(X) - P) . m,

the distance between the point and its image; in the energy they enter as the pairs above,

    Pi_m = (kappa / 2) int_Gamma R(-g_m) dA,

so that a wall pressed into its image carries the pressure kappa r(delta) of two walls pressed
together by the penetration delta = -g_m. Pi_m needs no search and is exact in u (its
residual and tangent by symbolic differentiation); where the walls are apart (g_m > 0) it is
zero.
"""

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat.errors import require
from ngincompat.fem.contact import ramp
from ngincompat.fem.terms import Term, Unknown
from ngincompat.fem.work import part

#: Integration order of the pairs on each element of the boundary.
INTORDER = 4


def _relative_position(mesh: ngs.Mesh, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """x(Y) - x(X) of a pair, u the trial displacement (``Other()``: at Y)."""
    X = ngs.CF((ngs.x, ngs.y, ngs.z)[:mesh.dim])
    return X.Other() + u.Other() - X - u


class SelfContact(Term):
    """Frictionless penalty self-contact of the ``boundary`` (a region expression), with the
    penalty ``penalty`` kappa (stress / length), the ramp rounded over the penetration
    ``width`` eps (length) and pairs searched within ``reach`` (length); ``mirrors`` the
    symmetry planes whose image of the boundary is a wall too, each a point P and the unit
    normal m into the body (see the module's notes), until :meth:`remove_mirrors`."""

    def __init__(self, boundary: str, penalty: float, width: float, reach: float,
                 mirrors: Iterable[tuple[Sequence[float], Sequence[float]]] = ()) -> None:
        require(math.isfinite(penalty) and penalty > 0, "contact_penalty", penalty,
                "> 0 (finite)")
        require(math.isfinite(width) and width >= 0, "contact_width", width, ">= 0 (finite)")
        require(math.isfinite(reach) and reach > 0, "contact_reach", reach, "> 0 (finite)")
        self.boundary, self.penalty, self.width, self.reach = boundary, penalty, width, reach
        self.mirrors = tuple((tuple(map(float, point)), tuple(map(float, normal)))
                             for point, normal in mirrors)
        for _, normal in self.mirrors:
            require(abs(math.hypot(*normal) - 1) < 1e-12, "mirror normal", normal,
                    "a unit vector")
        self.mirrored = ngs.Parameter(1.0)       # 0: the mirrors' images are gone

    def attach(self, problem: Any, unknowns: Sequence[Unknown]) -> ngs.comp.SumOfIntegrals | None:
        self.mesh, self.u, self.problem = problem.mesh, problem.u, problem
        # the pairs in the problem's form, the same pairs in a form of their own (the
        # term's energy) and those of the measures: a ContactBoundary each (one adding its
        # pairs to two forms leaves the first with a freed copy of the displacement); the
        # own form's takes the pairs of the problem's instead of searching again
        self.own = ngs.BilinearForm(problem.fes)
        self.paired = ngs.GridFunction(problem.space)    # the state of the last update
        self.forms = [(self.pairing(problem.displacement.trial), form)
                      for form in (problem.form, self.own)]
        region = self.mesh.Boundaries(self.boundary)
        self.probe = ngs.ContactBoundary(region, region)
        self.update()
        if not self.mirrors:
            return None
        u, v = problem.displacement.trial, problem.displacement.test
        return self.mirrored * self.mirror_energy(u).Diff(u, v).Compile() * self._measure()

    def remove_mirrors(self) -> None:
        """The symmetry planes are removed with the supports they were: their images are
        walls no longer (in the residual, the energy and the measures)."""
        self.mirrored.Set(0.0)

    def _images(self) -> tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]:
        """The mirrors whose images are walls now."""
        return self.mirrors if self.mirrored.Get() else ()

    def mirror_gaps(self, u: ngs.CoefficientFunction) -> list[ngs.CoefficientFunction]:
        """The gaps g_m = 2 (x - P) . m of the boundary's points to their images in the
        ``mirrors``, ``u`` the displacement (CFs)."""
        x = ngs.CF((ngs.x, ngs.y, ngs.z)[:self.mesh.dim]) + u
        return [2 * (x - ngs.CF(point[:self.mesh.dim])) * ngs.CF(normal[:self.mesh.dim])
                for point, normal in self._images()]

    def mirror_energy(self, u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """The density of Pi_m, (kappa / 2) sum over the mirrors of R(-g_m) (a CF)."""
        return sum((self.penalty / 2 * ramp(-gap, self.width)[1]
                    for gap in self.mirror_gaps(u)), ngs.CF(0.0))

    def _measure(self) -> ngs.comp.DifferentialSymbol:
        """The boundary's integral, with the two more degrees the ramp's kink needs (as the
        expander's contact)."""
        return ngs.ds(self.boundary, bonus_intorder=2)

    def pairing(self, trial: ngs.CoefficientFunction) -> ngs.ContactBoundary:
        """A ContactBoundary of the boundary with itself carrying the energy Pi_c of the
        trial displacement ``trial``."""
        region = self.mesh.Boundaries(self.boundary)
        contact = ngs.ContactBoundary(region, region)
        gap = _relative_position(self.mesh, trial) * contact.normal
        contact.AddEnergy(self.facing(contact.normal) * self.penalty / 2
                          * ramp(-gap, self.width)[1])
        return contact

    def facing(self, normal: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """1 where a pair of the last update lies within 25.8 degrees of the normal
        ``normal`` (cos = 0.9, in the state of that update: constant within a step), else 0:
        the pairs that the measures count (:meth:`gap`). Around the bottom of a narrow
        sulcus the search also pairs points across the bend at oblique angles."""
        relative = _relative_position(self.mesh, self.paired)
        along = relative * normal
        return ngs.IfPos(along * along - 0.81 * (relative * relative), 1.0, 0.0)

    def update(self) -> None:
        """Pair the boundary's points in the current state (the pairs and normals the energy
        uses until the next update): one search, whose pairs both forms take."""
        (searched, form), (other, own) = self.forms
        self.paired.vec.data = self.u.vec
        with part("contact search"):
            searched.Update(self.u, form, INTORDER, self.reach, keep_pairs=True)
            other.Update(self.u, own, INTORDER, self.reach, other=searched)

    def accept_step(self) -> None:
        self.update()

    def restore(self, data: Mapping[str, Any]) -> None:
        self.update()

    def energy(self) -> float:
        """Pi_c with the pairs of the last update, and Pi_m, at the current state."""
        energy = self.own.Energy(self.problem.state.vec)
        if self._images():
            energy += ngs.Integrate(self.mirror_energy(self.u), self.mesh, ngs.BND,
                                    definedon=self.mesh.Boundaries(self.boundary),
                                    order=2 * self.u.space.globalorder + 2)
        return energy

    def gap(self) -> ngs.CoefficientFunction:
        """The gap g of the current state, freshly paired (a CF on the boundary; 1e300 where
        no facing point is within ``reach``)."""
        with part("contact search"):
            self.probe.Update(self.u, maxdist=self.reach)
        to_pair = self.probe.gap          # x(Y) - x(X) of the probe's update
        gap = to_pair * self.probe.normal
        distance = ngs.Norm(to_pair)
        # the gap function's own search (unlike the pairs of the energy) also pairs points
        # of one smooth wall, beyond their common vertices: measured in NGSolve 6.2.2608, a
        # flat top paired 97 % of its points in-plane, and the crowns of folds of
        # curvature 32 / cm were seen to penetrate themselves 0.024 cm. Such a pair lies
        # along the surface (|g| / |x(Y) - x(X)| about the curvature times half their
        # distance), a facing one along the normal: only pairs within 25.8 degrees of it
        # (cos = 0.9) count.
        facing = ngs.IfPos(self.reach - distance, 1.0, 0.0) * ngs.IfPos(
            gap * gap - 0.81 * distance * distance, 1.0, 0.0)
        return ngs.IfPos(facing, gap, 1e300)

    def measures(self) -> dict[str, float]:
        """``self_contact_area``: the reference area of the boundary where it penetrates the
        other wall or an image (g < 0 or g_m < 0, where the pressure acts) and
        ``self_contact_penetration_max``, the largest -g or -g_m at the integration points
        of the boundary (0 without contact)."""
        gap = self.gap()
        for image in self.mirror_gaps(self.u):
            gap = ngs.IfPos(gap - image, image, gap)
        return measure(self.mesh, self.boundary, gap)


def measure(mesh: ngs.Mesh, boundary: str, gap: ngs.CoefficientFunction,
            order: int = 2) -> dict[str, float]:
    """The contact area (reference area where ``gap`` < 0) and the largest penetration -gap,
    both over the points of NGSolve's rule of ``order`` on the ``boundary`` (each point a
    search for its pair: the cost of the measures)."""
    values, weights = boundary_values(mesh, boundary, gap, order)
    return {"self_contact_area": float(np.sum(weights[values < 0])),
            "self_contact_penetration_max": max(0.0, -float(np.min(values, initial=0.0)))}


#: The straight boundary elements :func:`boundary_values` integrates over, and the corners
#: whose edges span them.
FLAT = {ngs.ET.TRIG: (0, 1, 2), ngs.ET.QUAD: (0, 1, 3), ngs.ET.SEGM: (0, 1)}


def boundary_values(mesh: ngs.Mesh, boundary: str, cf: ngs.CoefficientFunction,
                    order: int) -> tuple[np.ndarray, np.ndarray]:
    """The values of the scalar ``cf`` at the points of NGSolve's rule of ``order`` on every
    element of the ``boundary`` and the points' reference areas, for straight elements:
    triangles and parallelograms, or the segments of a section's boundary (:data:`FLAT`).
    The weights of NGSolve's rules sum to the reference element's size, 1/2 on the triangle
    and 1 on the square and the segment, so a point's area is its weight times the norm of
    the cross product of the spanning edges (twice the triangle's area, the
    parallelogram's), on a segment times its length."""
    elements = list(mesh.Elements(ngs.BND))
    if any(element.type not in FLAT for element in elements):
        raise ValueError("boundary_values needs a boundary of triangles, parallelograms or "
                         "segments")
    rules = {kind: ngs.IntegrationRule(kind, order) for kind in FLAT}
    mask = np.array(mesh.Boundaries(boundary).Mask())
    values = np.asarray(cf(mesh.MapToAllElements(rules, ngs.BND))).ravel()
    start, inside, weights = 0, [], []
    for element in elements:
        p = np.array([mesh[element.vertices[i]].point for i in FLAT[element.type]])
        n = len(rules[element.type].weights)
        if mask[element.index]:
            spanned = (np.linalg.norm(p[1] - p[0]) if len(p) == 2 else
                       np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0])))
            weights.append(spanned * np.array(rules[element.type].weights))
            inside.append(np.arange(start, start + n))
        start += n
    if not inside:
        return np.zeros(0), np.zeros(0)
    return values[np.concatenate(inside)], np.concatenate(weights)
