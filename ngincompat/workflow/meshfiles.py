"""Volume meshes of the formats meshio reads, converted to Netgen, with the checks a growth
run needs; and the one-line errors every mesh reader gives.

:func:`ngincompat.workflow.inputs.load_mesh` reads Netgen's own ``.vol`` files with
:mod:`ngincompat.workflow.volfile` and every other format here:

* Every other format (:data:`MESHIO_FORMATS`) is read by meshio, which parses and checks the
  file format, and converted here: the corner nodes and cells become Netgen points and
  elements, the region tags materials, the boundary cells boundary elements; what matters
  for the physics is checked on the way (a volume mesh, supported cell types, cells of
  positive volume, boundary cells on faces of the volume cells).

Every error is a :class:`~ngincompat.errors.ParameterError` that names the parameter
(``mesh``), the file and the reason on one line.
"""

from __future__ import annotations

import contextlib
import io
import logging
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, TypeAlias

import ngsolve as ngs
import numpy as np

from ngincompat.errors import ParameterError

if TYPE_CHECKING:     # read where a file is
    import meshio
    import netgen.meshing

log = logging.getLogger(__name__)

#: Formats read by meshio: file extension -> meshio's format name.
MESHIO_FORMATS = {".msh": "gmsh", ".vtu": "vtu", ".vtk": "vtk", ".inp": "abaqus",
                  ".mesh": "medit"}


def read(path: Path, suffix: str) -> ngs.Mesh:
    """Read a volume mesh file of a meshio format into NGSolve.

    Parameters
    ----------
    path : pathlib.Path
        An existing file.
    suffix : str
        Its extension, a key of :data:`MESHIO_FORMATS`.

    Returns
    -------
    ngsolve.Mesh
    """
    return ngs.Mesh(_read_meshio(path, MESHIO_FORMATS[suffix]))


def file_error(path: str | os.PathLike, reason: str, name: str = "mesh") -> ParameterError:
    """The error for an input file: names the parameter, the file and the reason, one line."""
    text = str(path)
    if len(text) > PATH_QUOTE:      # its start and its file name, not thousands of characters
        text = f"{text[:PATH_QUOTE // 2]}...{text[-PATH_QUOTE // 2:]}"
    return ParameterError(f"{name} = '{text}': {reason}")


#: The most characters of a file's path that an error message quotes.
PATH_QUOTE = 300


def suffix_of(path: str | os.PathLike, allowed: Iterable[str]) -> str | None:
    """The entry of ``allowed`` the file name ends with (case-insensitive), or None."""
    name = Path(path).name.lower()
    for ext in sorted(allowed, key=len, reverse=True):
        if name.endswith(ext):
            return ext
    return None


def one_line(exc: BaseException | str) -> str:
    """An exception's message on one line of at most 200 characters."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def point(p: Iterable[float]) -> str:
    """Coordinates for a message: ``(x, y, z)``."""
    return "(" + ", ".join(f"{float(c):.6g}" for c in p) + ")"


#: Corners of each first-order cell type of meshio that is read.
_CORNERS = {"tetra": 4, "pyramid": 5, "wedge": 6, "hexahedron": 8, "triangle": 3, "quad": 4}

#: Second-order cell types and their first-order type (meshio lists the corners first).
_FIRST_ORDER = {"tetra10": "tetra", "pyramid13": "pyramid", "pyramid14": "pyramid",
                "wedge15": "wedge", "wedge18": "wedge", "hexahedron20": "hexahedron",
                "hexahedron24": "hexahedron", "hexahedron27": "hexahedron",
                "triangle6": "triangle", "triangle7": "triangle", "quad8": "quad",
                "quad9": "quad"}

#: For each corner k of a volume cell (meshio's numbering, which is VTK's): (k, a, b, c) with
#: det(Xa - Xk, Xb - Xk, Xc - Xk) > 0 in a cell of positive orientation. A tetrahedron's
#: Jacobian is constant: one corner tells.
_CORNER_FRAMES = {
    "tetra": [(0, 1, 2, 3)],
    "pyramid": [(0, 1, 3, 4), (1, 2, 0, 4), (2, 3, 1, 4), (3, 0, 2, 4)],
    "wedge": [(0, 1, 2, 3), (1, 2, 0, 4), (2, 0, 1, 5), (3, 5, 4, 0), (4, 3, 5, 1),
              (5, 4, 3, 2)],
    "hexahedron": [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7), (4, 7, 5, 0),
                   (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)],
}

#: The corners of the mirror image of a cell: a negatively oriented cell becomes positive.
_MIRROR = {"tetra": [0, 2, 1, 3], "pyramid": [0, 3, 2, 1, 4], "wedge": [0, 2, 1, 3, 5, 4],
           "hexahedron": [0, 3, 2, 1, 4, 7, 6, 5]}

#: Netgen's corners of a positive cell, from VTK's (then ngsolve's Jacobian is > 0).
_NETGEN_ORDER = {"tetra": [1, 0, 2, 3], "pyramid": [0, 1, 2, 3, 4],
                 "wedge": [0, 1, 2, 3, 4, 5], "hexahedron": list(range(8))}

#: The faces of each volume cell type, corners in cyclic order.
_FACES: dict[str, list[tuple[int, ...]]] = {
    "tetra": [(0, 1, 2), (0, 1, 3), (1, 2, 3), (0, 2, 3)],
    "pyramid": [(0, 1, 2, 3), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
    "wedge": [(0, 1, 2), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
    "hexahedron": [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                   (3, 0, 4, 7)],
}

_POLYGONS = {3: "triangles", 4: "quadrilaterals"}

# the cells of one dimension: (first-order type, corners, tags) per block
_Cells: TypeAlias = list[tuple[str, np.ndarray, np.ndarray]]

#: Integer cell data that number the regions, looked for in this order: Gmsh's physical
#: groups, MEDIT's references, VTK's entity ids. An only integer cell array is taken too,
#: else the named cell sets (Abaqus element sets).
_TAG_KEYS = ("gmsh:physical", "medit:ref", "CellEntityIds")

#: A corner Jacobian at most this fraction of the cube of the corner's longest edge is a
#: degenerate (flat) cell.
_FLAT = 1e-10

#: Name of an untagged region or boundary, and of the outer faces without a boundary cell.
DEFAULT_NAME = "default"

#: What a mesh file must hold, for the messages.
_ALLOWED = ("a 3-D volume mesh of tetrahedra, hexahedra, prisms (wedges) or pyramids, with "
            "triangles or quadrilaterals on the boundary, is needed")


def _read_meshio(path: Path, file_format: str) -> netgen.meshing.Mesh:
    """Read a mesh with meshio; check it and build its Netgen mesh (see :func:`read`)."""
    import meshio

    said = io.StringIO()
    try:
        # meshio prints its readers' errors and ends the process (SystemExit) when none read
        # the file: both are kept here and told in the one-line error
        with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
            data = meshio.read(path, file_format=file_format)
    except (Exception, SystemExit) as exc:  # meshio raises many types for a damaged file
        reason = one_line(said.getvalue()) if isinstance(exc, SystemExit) else one_line(exc)
        raise file_error(path, f"cannot be read as a {file_format} file (truncated or "
                               f"damaged?): {reason}") from None
    points = np.asarray(data.points, dtype=float)
    if points.shape[1] != 3:
        raise file_error(path, f"is a {points.shape[1]}-D mesh: {_ALLOWED}")
    if not np.isfinite(points).all():
        raise file_error(path, "has node coordinates that are not finite")
    notes: list[str] = []
    tags, names = _cell_tags(path, data)
    volume, boundary = _cells(path, data, tags, notes)
    if not volume:
        raise file_error(path, _without_volume(points, boundary))
    corners = _corner_nodes(volume, boundary, len(points), notes)
    points = points[corners]
    volume = [_oriented(path, points, *block) for block in volume]
    ngmesh = _netgen_mesh(path, points, volume, boundary, names, notes)
    for note in notes:
        log.warning("%s: %s", path, note)
    return ngmesh


def _cell_tags(path: Path, data: meshio.Mesh
               ) -> tuple[list[np.ndarray], dict[tuple[int, int], str]]:
    """The region tag of every cell (one integer array per cell block, 0: none) and the
    names of the tags, {(dimension, tag): name}."""
    integer = {key: value for key, value in data.cell_data.items()
               if all(np.issubdtype(np.asarray(a).dtype, np.integer) for a in value)}
    keys = [key for key in _TAG_KEYS if key in integer] or (list(integer) if len(integer) == 1
                                                             else [])
    if keys:
        names = {}
        if keys[0] == "gmsh:physical":      # $PhysicalNames: name -> (tag, dimension)
            names = {(int(v[1]), int(v[0])): name for name, v in data.field_data.items()
                     if np.size(v) == 2}
        return [np.asarray(a, dtype=np.int64).ravel() for a in integer[keys[0]]], names
    tags = [np.zeros(len(block.data), dtype=np.int64) for block in data.cells]
    sets = [(name, blocks) for name, blocks in data.cell_sets.items()
            if not name.startswith("gmsh:")]
    names = {}
    for number, (name, blocks) in enumerate(sets, start=1):
        for tag, cells in zip(tags, blocks, strict=True):
            cells = np.asarray(cells, dtype=np.int64)
            if tag[cells].any():
                other = sets[int(tag[cells].max()) - 1][0]
                raise file_error(path, f"its cell sets {other!r} and {name!r} share cells: "
                                       "the regions of a mesh must not overlap")
            tag[cells] = number
        names[3, number] = names[2, number] = name
    return tags, names


def _cells(path: Path, data: meshio.Mesh, tags: list[np.ndarray],
           notes: list[str]) -> tuple[_Cells, _Cells]:
    """The volume and the boundary cells, lists of (first-order type, corners, tags)."""
    volume: _Cells
    boundary: _Cells
    volume, boundary, second_order = [], [], set()
    for block, tag in zip(data.cells, tags, strict=True):
        kind = _FIRST_ORDER.get(block.type, block.type)
        if kind not in _CORNERS:
            if block.type.startswith(("vertex", "line")):
                continue                # points and edges (physical curves): not used
            raise file_error(path, f"has cells of type {block.type!r}, which are not read: "
                                   f"{_ALLOWED} (first or second order)")
        if kind != block.type:
            second_order.add(block.type)
        cells = (kind, np.asarray(block.data, dtype=np.int64)[:, :_CORNERS[kind]], tag)
        (boundary if kind in ("triangle", "quad") else volume).append(cells)
    if second_order:
        notes.append(f"second-order cells ({', '.join(sorted(second_order))}) are read with "
                     "their corners only: straight-sided elements, the other nodes left out")
    return volume, boundary


def _without_volume(points: np.ndarray, boundary: _Cells) -> str:
    """Why a mesh without volume cells is refused."""
    if not boundary:
        return f"has no cells: {_ALLOWED}"
    if np.ptp(points, axis=0).min() == 0:
        return f"is a 2-D mesh (its nodes lie in one coordinate plane): {_ALLOWED}"
    return f"is a surface mesh (triangles and quadrilaterals only): {_ALLOWED}"


def _corner_nodes(volume: _Cells, boundary: _Cells, npoints: int, notes: list[str]) -> np.ndarray:
    """The nodes that are corners of volume cells, in file order; renumbers the cells."""
    used = np.zeros(npoints, dtype=bool)
    for _, corners, _ in volume:
        used[corners] = True
    corners = np.flatnonzero(used)
    number = np.full(npoints, -1, dtype=np.int64)
    number[corners] = np.arange(len(corners))
    if len(corners) < npoints:
        notes.append(f"{npoints - len(corners)} of its {npoints} nodes are no corner of a "
                     "volume cell and are left out")
    for cells in (volume, boundary):
        cells[:] = [(kind, number[c], tag) for kind, c, tag in cells]
    return corners


def _oriented(path: Path, points: np.ndarray, kind: str, corners: np.ndarray,
              tag: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """Refuse degenerate and tangled cells; turn the negatively oriented ones (a file
    convention, e.g. Netgen's own tetrahedra); give the corners in Netgen's order."""
    det: list[np.ndarray] | np.ndarray
    scale: list[np.ndarray] | np.ndarray
    det, scale = [], []
    for k, a, b, c in _CORNER_FRAMES[kind]:
        edges = points[corners[:, [a, b, c]]] - points[corners[:, [k]]]
        det.append(np.linalg.det(edges))
        scale.append(np.linalg.norm(edges, axis=2).max(axis=1) ** 3)
    det, scale = np.array(det).T, np.array(scale).T
    flat = (np.abs(det) <= _FLAT * scale).any(axis=1)
    tangled = (det > 0).any(axis=1) & (det < 0).any(axis=1)
    for bad, what in ((flat, "degenerate (flat)"), (tangled, "inverted at some corners")):
        if bad.any():
            first = corners[np.flatnonzero(bad)[0]]
            raise file_error(path, f"{int(bad.sum())} of its {len(corners)} {kind} cells are "
                                   f"{what}, the first at {point(points[first].mean(axis=0))}:"
                                   " every cell needs a positive volume at all its corners")
    negative = det[:, 0] < 0
    corners = corners.copy()
    corners[negative] = corners[negative][:, _MIRROR[kind]]
    return kind, corners[:, _NETGEN_ORDER[kind]], tag


def _netgen_mesh(path: Path, points: np.ndarray, volume: _Cells, boundary: _Cells,
                 names: Mapping[tuple[int, int], str],
                 notes: list[str]) -> netgen.meshing.Mesh:
    """The Netgen mesh: a material per volume tag, boundary elements per boundary tag and
    pair of regions (outer boundaries and interfaces), named by ``names``."""
    from netgen.meshing import FaceDescriptor
    from netgen.meshing import Mesh as NetgenMesh

    names, unnamed = dict(names), []

    def name(dim: int, tag: int, prefix: str) -> str:
        if (dim, tag) not in names:
            names[dim, tag] = f"{prefix}{tag}" if tag else DEFAULT_NAME
            unnamed.append(names[dim, tag])
        return names[dim, tag]

    ngmesh = NetgenMesh(dim=3)
    ngmesh.AddPoints(np.ascontiguousarray(points))
    cell_tags = np.concatenate([tag for _, _, tag in volume])
    regions = np.unique(cell_tags)
    for k, tag in enumerate(regions, start=1):
        ngmesh.SetMaterial(k, name(3, int(tag), "region"))
        for _, corners, tags in volume:
            ngmesh.AddElements(dim=3, index=k, data=corners[tags == tag].astype(np.int32))
    domain = np.searchsorted(regions, cell_tags) + 1
    centre = np.concatenate([points[corners].mean(axis=1) for _, corners, _ in volume])
    number = 0
    for size in (3, 4):
        faces, tags, cells = _boundary_faces(path, points, volume, boundary, size, notes)
        if not len(faces):
            continue
        # an interface belongs to the region of the lower number, as in Netgen's meshes
        swap = (cells[:, 1] >= 0) & (domain[cells[:, 1]] < domain[cells[:, 0]])
        cells[swap] = cells[swap][:, ::-1]
        faces = _outward(points, faces, centre[cells[:, 0]])
        domin = domain[cells[:, 0]]
        domout = np.where(cells[:, 1] >= 0, domain[cells[:, 1]], 0)
        groups, group = np.unique(np.stack([tags, domin, domout], axis=1), axis=0,
                                  return_inverse=True)
        for g, (tag, din, dout) in enumerate(groups.tolist()):
            number += 1
            ngmesh.Add(FaceDescriptor(surfnr=number, domin=din, domout=dout, bc=number))
            ngmesh.SetBCName(number - 1, DEFAULT_NAME if tag < 0 else name(2, tag, "boundary"))
            ngmesh.AddElements(dim=2, index=number,
                               data=faces[group.ravel() == g].astype(np.int32))
    if unnamed:
        notes.append(f"regions or boundaries without a name are called {', '.join(unnamed)}")
    return ngmesh


def _boundary_faces(path: Path, points: np.ndarray, volume: _Cells, boundary: _Cells, size: int,
                    notes: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The boundary faces with ``size`` corners: those of the file's boundary cells (one per
    face) and the outer faces of the volume cells without one (tag -1). Returns their corners,
    tags and the volume cells on each side (index into all volume cells; -1: none)."""
    rows: list[np.ndarray] | np.ndarray
    owner: list[np.ndarray] | np.ndarray
    face: tuple[int, ...] | np.ndarray     # a cell's face, then each face's number
    rows, owner, start = [], [], 0
    for kind, corners, _ in volume:
        for face in _FACES[kind]:
            if len(face) == size:
                rows.append(corners[:, face])
                owner.append(start + np.arange(len(corners)))
        start += len(corners)
    given = [(corners, tag) for kind, corners, tag in boundary if _CORNERS[kind] == size]
    if not given and not rows:
        return np.zeros((0, size), np.int64), np.zeros(0, np.int64), np.zeros((0, 2), np.int64)
    empty = np.zeros((0, size), dtype=np.int64)
    rows = np.concatenate([empty, *rows])
    owner = np.concatenate([np.zeros(0, np.int64), *owner])
    bfaces = np.concatenate([empty, *(corners for corners, _ in given)])
    btags = np.concatenate([np.zeros(0, np.int64), *(tag for _, tag in given)])
    _, index = np.unique(np.sort(np.concatenate([rows, bfaces]), axis=1), axis=0,
                         return_inverse=True)
    face, bface = index.ravel()[:len(rows)], index.ravel()[len(rows):]
    count = np.bincount(face, minlength=int(index.max()) + 1)
    if count.max() > 2:
        raise file_error(path, f"has {_POLYGONS[size]} shared by more than two volume cells: "
                               "overlapping or repeated cells")
    orphan = np.flatnonzero(count[bface] == 0)
    if len(orphan):
        raise file_error(path, f"has boundary {_POLYGONS[size]} that are no face of a volume "
                               f"cell, the first at {point(points[bfaces[orphan[0]]].mean(0))}")
    bface, first = np.unique(bface, return_index=True)
    if len(first) < len(btags):
        notes.append(f"{len(btags) - len(first)} boundary {_POLYGONS[size]} repeat a face: "
                     "the first is kept")
    missing = np.setdiff1d(np.flatnonzero(count == 1), bface)
    if len(missing):
        notes.append(f"{len(missing)} outer {_POLYGONS[size]} have no boundary cell in the file:"
                     f" they are added as boundary {DEFAULT_NAME!r}")
    order = np.argsort(face, kind="stable")
    side = np.zeros(len(face), dtype=np.int64)      # 1: the second cell on the face
    side[order[1:]] = face[order[1:]] == face[order[:-1]]
    cells = np.full((len(count), 2), -1, dtype=np.int64)
    cells[face, side] = owner
    row = np.empty(len(count), dtype=np.int64)
    row[face] = np.arange(len(face))
    faces = np.concatenate([bfaces[first], rows[row[missing]]])
    tags = np.concatenate([btags[first], np.full(len(missing), -1)])
    return faces, tags, cells[np.concatenate([bface, missing])]


def _outward(points: np.ndarray, faces: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """The faces with their corners ordered so that the normal points away from ``centre``
    (the centre of the cell they bound; Netgen's boundary normal points out of domin)."""
    p = points[faces]
    if faces.shape[1] == 3:
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    else:
        normal = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    inward = np.einsum("ij,ij->i", normal, p.mean(axis=1) - centre) < 0
    faces = faces.copy()
    faces[inward] = faces[inward][:, ::-1]
    return faces
