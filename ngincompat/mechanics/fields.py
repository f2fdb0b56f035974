"""Direction fields on the reference configuration: normals N0 and fibers f0.

A :class:`DirectionField` wraps a unit-vector CoefficientFunction together with whether it is
constant in space. The closed forms of section 2.3 (eq. 19-22, 24-27) assume constant N0 and f0,
so only constant fields give a scene a closed-form oracle.
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ngincompat import names
from ngincompat.errors import ParameterError

_AXES = {"e1": (1.0, 0.0, 0.0), "e2": (0.0, 1.0, 0.0), "e3": (0.0, 0.0, 1.0)}


@dataclass(frozen=True, eq=False)
class DirectionField:
    """A unit vector field.

    Attributes
    ----------
    cf : ngsolve.CoefficientFunction
        The field, a 3-vector of unit length wherever it is defined.
    name : str
        A label for results and error messages.
    vector : tuple of float or None
        The constant value when the field is constant in space, else None.
    """

    cf: ngs.CoefficientFunction
    name: str
    vector: tuple | None = None

    @property
    def is_constant(self) -> bool:
        return self.vector is not None


def constant(vector: str | Sequence[float], name: str | None = None) -> DirectionField:
    """A constant unit direction; ``vector`` is normalised, ``"e1"``, ``"e2"``, ``"e3"`` work."""
    if isinstance(vector, str):
        if vector not in _AXES:
            raise ParameterError(
                f"direction {vector!r} is unknown: allowed e1, e2, e3 or three numbers")
        name = name or vector
        vector = _AXES[vector]
    v = np.asarray(vector, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise ParameterError(f"direction {vector!r} must be three finite numbers, not all zero")
    v = v / np.linalg.norm(v)
    return DirectionField(ngs.CF(tuple(v)), name or "({:g}, {:g}, {:g})".format(*v), tuple(v))


def radial(center: Sequence[float] = (0.0, 0.0, 0.0),
           axis: str | Sequence[float] | None = None) -> DirectionField:
    """Unit radial direction from ``center``; about the line ``center + s*axis`` if given.

    Undefined on the centre point (line); a tiny regularisation keeps it finite there.
    """
    c = ngs.CF(tuple(float(a) for a in center))
    d = ngs.CF((ngs.x, ngs.y, ngs.z)) - c
    if axis is not None:
        a = constant(axis).cf
        d = d - ngs.InnerProduct(d, a) * a
    return DirectionField(d / ngs.sqrt(ngs.InnerProduct(d, d) + 1e-30), "radial")


def circumferential(axis: str | Sequence[float] = "e3",
                    center: Sequence[float] = (0.0, 0.0, 0.0)) -> DirectionField:
    """Unit circumferential direction about the line ``center + s*axis``: axis x radial."""
    a = constant(axis).cf
    r = radial(center, axis).cf
    return DirectionField(ngs.Cross(a, r), "circumferential")


def from_name(spec: str, parameter: str = "direction") -> DirectionField:
    """A direction field from a short name: e1, e2, e3, radial, radial_xy, circumferential,
    or the bilayer's axons_curved, axons_concentric, axons_straight (default placement);
    ``parameter`` is the name an unknown one is reported under."""
    if spec in _AXES:
        return constant(spec)
    if spec == "radial":
        return radial()
    if spec == "radial_xy":
        return radial(axis="e3")
    if spec == "circumferential":
        return circumferential()
    if spec.startswith("axons_") and spec[len("axons_"):] in AXONS:
        return axons(spec[len("axons_"):])
    raise ParameterError(
        f"{parameter} = {spec!r} is unknown: allowed e1, e2, e3, radial, radial_xy, "
        "circumferential, " + ", ".join(f"axons_{kind}" for kind in AXONS))


#: The axon fields (:data:`ngincompat.names.AXONS`).
AXONS = names.AXONS
#: Depth of the focus of the curved and concentric axons below the interface (cm): the curved
#: axons meet the interface at most atan(length / (2 FOCUS_DEPTH)) from its normal, 26.6
#: degrees on the paper's 3 cm strip.
FOCUS_DEPTH = 3.0


def axons(kind: str, interface: float = 0.95, length: float = 3.0,
          focus_depth: float = FOCUS_DEPTH, vertical: str = "e3") -> DirectionField:
    """The bilayer's axon orientations in the subcortex (cortical folding, Fig. 7).

    Parameters
    ----------
    kind : str
        One of :data:`ngincompat.names.AXONS`.
        ``straight``: normal to the cortex-subcortex interface (the ``vertical``);
        ``curved``: fanning outward, radial from a focus ``focus_depth`` below the interface
        at the middle of the strip; ``concentric``: arcs around that focus (the out-of-plane
        axis x radial), parallel to the interface above the focus.
    interface : float
        Height of the flat interface (cm), along ``vertical``.
    length : float
        Length of the strip along X1 (cm); the focus lies below its middle.
    focus_depth : float
        Depth of the focus below the interface (cm), > 0.
    vertical : {"e3", "e2"}
        The vertical axis: e3 for a body whose out-of-plane axis is e2; e2 for the section
        of a body in plane strain (its points (X1, X2), e3 out of plane: the paper's axes).
    """
    if kind not in AXONS:
        raise ParameterError(f"axons = {kind!r} is unknown: allowed {', '.join(AXONS)}")
    if vertical not in ("e2", "e3"):
        raise ParameterError(f"vertical = {vertical!r} is unknown: allowed e2, e3")
    if kind == "straight":
        return constant(vertical, name="axons straight")
    if focus_depth <= 0:
        raise ParameterError(f"focus_depth = {focus_depth!r} is out of range: allowed > 0")
    across = "e2" if vertical == "e3" else "e3"
    focus = (length / 2, *((0.0, interface - focus_depth) if vertical == "e3" else
                           (interface - focus_depth, 0.0)))
    fan = radial(focus, axis=across)
    if kind == "curved":
        return DirectionField(fan.cf, "axons curved")
    return DirectionField(ngs.Cross(constant(across).cf, fan.cf), "axons concentric")


def by_region(mesh: ngs.Mesh, directions: Mapping[str, DirectionField],
              name: str) -> DirectionField:
    """A direction field made of one field per region of the mesh (the cortex's e1 above the
    subcortex's axons), e.g. ``by_region(mesh, {"cortex": constant("e1"), ...}, "f0")``.

    Every region of the mesh needs a field; the result is constant only if all the fields
    are the same constant.
    """
    regions = set(mesh.GetMaterials())
    if set(directions) != regions:
        raise ParameterError(f"directions for {sorted(directions)} are out of range: allowed "
                             f"one for each region: {', '.join(sorted(regions))}")
    vectors = {d.vector for d in directions.values()}
    vector = vectors.pop() if len(vectors) == 1 else None
    cf = mesh.MaterialCF({r: d.cf for r, d in directions.items()})
    return DirectionField(cf, name, vector)
