"""How many elements a builder would make, estimated from the dimensions and ``maxh`` alone,
without meshing: so that a scene refuses a mesh that would not fit in memory (``maxh`` of
0.001 on the 1 mm cube is 10^9 cells, 7 GB within a minute of meshing) before building it.

Netgen's tetrahedra have edges of about the local mesh size h: a region of volume V where
every extent is at least h holds about :data:`TETS_PER_CELL` V / h^3 of them (measured 3.5 to
6.2 on the cube, hemisphere, disc, cylinder and brain); an extent below h counts as h (the
thin skin patch is one element thick). Near a point or a face
meshed finer, the size grows with Netgen's grading g = 0.3 (h(r) = h0 + g r), which adds the
integral of the cell density over that graded zone. The bilayer is a plane section
meshed with triangles (about :data:`TRIANGLES_PER_CELL` per h^2). The estimates are in
log-safe products of ratios, so a dimension of 1e308 gives an infinite estimate, never a NaN.

Each function takes the builder's keywords (the same defaults) and returns the estimated number
of elements; :data:`ESTIMATES` maps the builders' names (:data:`geometries.BUILDERS`) to them.
The estimates are within a factor 4 of the meshes' counts (tests/workflow/test_inputs_hostile.py).
"""

import math

from .skin_patch import SIDE, THICKNESS

#: Tetrahedra per cell of volume h^3 (measured 3.5 to 6.2).
TETS_PER_CELL = 5.0
#: Triangles per cell of area h^2 (measured 1.5 to 2.8 on the bilayer's sections).
TRIANGLES_PER_CELL = 2.0
#: Netgen's grading g: the mesh size grows as h(r) = h0 + g r away from a finer point or face.
GRADING = 0.3


def _cells(extents, h, fill=1.0):
    """Cells of size h in a box of the given extents (each at least one cell thick), times
    the fraction ``fill`` of the box the body occupies."""
    n = fill
    for extent in extents:
        n *= max(1.0, extent / h)
    return n


def triangles(extents, h):
    """Triangles of size h in a rectangle of the given extents."""
    return TRIANGLES_PER_CELL * _cells(extents, h)


def tets(extents, h, fill=1.0):
    """Tetrahedra of size h in a body of bounding box ``extents`` filling ``fill`` of it."""
    return TETS_PER_CELL * _cells(extents, h, fill)


def graded_point(h, h0, solid_angle=4 * math.pi):
    """Tetrahedra added around a point meshed at h0 < h: the integral of the cell density
    1 / (h0 + g r)^3 over the cone of ``solid_angle`` until the size reaches h."""
    if h0 >= h:
        return 0.0
    return TETS_PER_CELL * solid_angle / GRADING ** 3 * math.log(h / h0)


def cube_elements(side=1.0, maxh=0.25, elements="hex", quarter=False, **_):
    h = min(maxh, side)
    if elements == "hex":
        n = max(1, math.ceil(side / h - 1e-9))
        return float(n * math.ceil(n / 2) ** 2) if quarter else float(n) ** 3
    return tets((side, side / 2, side / 2) if quarter else (side,) * 3, h)


def curved(maxh, radius):
    """The mesh size on a surface curved with ``radius``: Netgen meshes it at most at
    :data:`CURVATURE_SIZE` x radius, whatever ``maxh`` (a cylinder 1.1 cm across and 1 cm
    long at maxh 0.25 has 5,805 elements, not the 16 of maxh alone)."""
    return min(maxh, CURVATURE_SIZE * radius)


#: The mesh size on a curved surface per unit of its radius (measured on thin cylinders).
CURVATURE_SIZE = 0.5


def hemisphere_elements(R0=1.0, maxh=0.3, centre_maxh=None, quarter=False, **_):
    share = 0.25 if quarter else 1.0
    h = curved(maxh, R0)
    body = tets((2 * R0, 2 * R0, R0), h, fill=math.pi / 6)
    centre = 0.0 if centre_maxh is None else graded_point(min(h, R0), centre_maxh,
                                                          2 * math.pi)
    return share * (body + centre)


def disc_elements(R0=1.0, height=0.5, maxh=0.25, **_):
    return tets((2 * R0, 2 * R0, height), curved(maxh, R0), fill=math.pi / 4)


def cylinder_elements(area=math.pi / 4, length=1.0, maxh=0.25, **_):
    diameter = 2 * math.sqrt(area / math.pi)
    return tets((diameter, diameter, length), curved(maxh, diameter / 2), fill=math.pi / 4)


def skin_patch_elements(side=SIDE, thickness=THICKNESS, maxh=1.0, **_):
    return tets((side, side, thickness), maxh)


def bilayer_elements(length=3.0, height=1.0, cortex=0.05, maxh=0.05, cortex_maxh=None,
                     top_maxh=None, **_):
    """The triangles of the bilayer's section."""
    fine = maxh if cortex_maxh is None else cortex_maxh
    finest = fine if top_maxh is None else top_maxh
    # the cortex graded from the top edge's size: as if all of it were meshed at the
    # average of the two (an underestimate when the grading reaches ``fine`` within it)
    top = triangles((length, cortex), (fine + finest) / 2)
    below = triangles((length, max(height - cortex, 0.0)), maxh)
    # graded from the fine interface: per unit length, the integral of the cells per cell
    # height, (h0 + g z)^-2 dz
    graded = TRIANGLES_PER_CELL * (length / fine) / GRADING if fine < maxh else 0.0
    return top + below + graded


def brain_elements(semi_axes=(8.5, 7.0, 6.0), maxh=1.0, **_):
    return tets(tuple(2 * a for a in semi_axes), maxh, fill=math.pi / 6)


#: The estimate of each builder, by the builder's name.
ESTIMATES = {"cube": cube_elements, "hemisphere": hemisphere_elements, "disc": disc_elements,
             "cylinder": cylinder_elements, "skin_patch": skin_patch_elements,
             "bilayer": bilayer_elements, "brain": brain_elements}
