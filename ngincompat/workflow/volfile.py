"""Netgen's own ``.vol`` / ``.vol.gz`` mesh files, read by Netgen after checking their text.

meshio does not read the ``.vol`` files current Netgen writes, and Netgen's reader does not
report a damaged file (it crashes, hangs, or returns an empty mesh), so the structure of the
text is checked first; the OCC geometry a file may carry after ``endmesh`` is test-read in a
separate process before it is used to curve the mesh. Errors are those of
:mod:`ngincompat.workflow.meshfiles`: one line naming ``mesh``, the file and the reason.
"""

from __future__ import annotations

import gzip
import hashlib
import logging
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from ngincompat.workflow.meshfiles import file_error, one_line, point

if TYPE_CHECKING:     # read where a file is
    import netgen.meshing

log = logging.getLogger(__name__)

#: File names read here.
EXTENSIONS = (".vol", ".vol.gz")

#: Seconds the separate process that test-reads a geometry may take.
_GEOMETRY_PROBE_TIMEOUT = 60


def read(path: Path, curve: bool = False) -> ngs.Mesh:
    """Read a ``.vol`` / ``.vol.gz`` file.

    Parameters
    ----------
    path : pathlib.Path
        An existing file.
    curve : bool
        The mesh will be curved: read the geometry the file carries (a
        :class:`~ngincompat.errors.ParameterError` for a file without one).

    Returns
    -------
    ngsolve.Mesh
    """
    return _checked_vol_mesh(path, _read_vol(path, curve))


#: Sections of the mesh part of a .vol file whose rows are checked: name -> row kind.
_VOL_CHECKED = {
    "points": "points",
    "volumeelements": "volume",
    "surfaceelements": "surface",
    "surfaceelementsgi": "surface",
    "surfaceelementsuv": "surface",
}


def _read_vol_text(path: Path) -> str:
    try:
        if path.name.lower().endswith(".gz"):
            with gzip.open(path, "rt", encoding="utf-8") as f:
                return f.read()
        return path.read_text(encoding="utf-8")
    except (EOFError, gzip.BadGzipFile) as exc:
        raise file_error(path, f"damaged gzip data: {one_line(exc)}") from None
    except UnicodeDecodeError:
        raise file_error(path, "is not a text file: not a Netgen mesh") from None
    except OSError as exc:
        raise file_error(path, f"cannot be read: {one_line(exc)}") from None


def _check_vol(path: Path, text: str) -> tuple[str, str]:
    """Check the mesh part of a .vol file; return (mesh part, geometry part).

    Netgen's reader does not report a damaged file: it crashes, hangs, or returns an empty
    mesh. So the structure is checked here: the ``mesh3d`` header, a 3-D dimension, the row
    counts of the points and elements, the point numbers of the elements and the final
    ``endmesh`` line.
    """
    lines = text.split("\n")
    n = len(lines)
    i = 0

    def next_data(i: int) -> int:
        while i < n and (not lines[i].strip() or lines[i].lstrip().startswith("#")):
            i += 1
        return i

    i = next_data(i)
    if i >= n or lines[i].strip() != "mesh3d":
        raise file_error(path, "is not a Netgen mesh (the file does not start with 'mesh3d')")
    i += 1
    npoints, max_point, nvol, section = None, 0, 0, "mesh3d"
    end = None
    while True:
        i = next_data(i)
        if i >= n:
            raise file_error(path, f"is truncated: the file ends in section '{section}' without "
                                   "the final 'endmesh' line")
        word = lines[i].strip()
        i += 1
        if word.replace("_", "").isalpha() and word.islower() and len(word) > 2:
            section = word
        if word == "endmesh":
            end = i
            break
        if word == "curvedelements":
            # An archive of the curved elements follows; Netgen reads it up to 'endmesh'.
            while i < n and lines[i].strip() != "endmesh":
                i += 1
            continue
        if word == "dimension":
            i = next_data(i)
            if i >= n or lines[i].strip() != "3":
                dim = lines[i].strip() if i < n else "missing"
                raise file_error(path, f"is not a 3-D mesh (dimension {dim}): a volume mesh is "
                                       "needed")
            i += 1
            continue
        kind = _VOL_CHECKED.get(word)
        if kind is None:
            continue                # other sections: Netgen skips what it does not know
        i = next_data(i)
        try:
            count = int(lines[i]) if i < n else -1
        except ValueError:
            count = -1
        if count < 0:
            raise file_error(path, f"section '{word}' (line {i}) does not start with a row count")
        rows = lines[i + 1:i + 1 + count]
        if len(rows) < count or not all(r.strip() for r in rows):
            found = sum(1 for r in rows if r.strip())
            raise file_error(path, f"is truncated or damaged: section '{word}' announces {count} "
                                   f"rows but has {found}")
        if kind == "points":
            npoints = count
            _check_point_rows(path, rows)
        elif kind == "volume":
            nvol += count
            max_point = max(max_point, _check_element_rows(path, word, rows, first=1))
        else:
            max_point = max(max_point, _check_element_rows(path, word, rows, first=4))
        i += 1 + count
    if nvol == 0:
        raise file_error(path, "has no volume elements: a 3-D volume mesh is needed")
    if npoints is None:
        raise file_error(path, "has no 'points' section")
    if max_point > npoints:
        raise file_error(path, f"is damaged: an element uses point {max_point} but the file has "
                               f"{npoints} points")
    return "\n".join(lines[:end]) + "\n", "\n".join(lines[end:])


def _check_point_rows(path: Path, rows: list[str]) -> None:
    try:
        xyz = np.array(" ".join(rows).split(), dtype=float)
    except ValueError as exc:
        raise file_error(path, f"is damaged: section 'points' has a value that is not a number "
                               f"({one_line(exc)})") from None
    if xyz.size != 3 * len(rows):
        raise file_error(path, "is damaged: section 'points' has rows that are not 3 coordinates")
    if not np.isfinite(xyz).all():
        raise file_error(path, "is damaged: section 'points' has coordinates that are not finite")


def _check_element_rows(path: Path, section: str, rows: list[str], first: int) -> int:
    """Check rows ``... np p1 .. pnp ...`` (np at column ``first``); return the largest p."""
    # Fast path: integer rows of one width (e.g. all tetrahedra); otherwise row by row.
    try:
        table = np.array(" ".join(rows).split(), dtype=np.int64)
    except ValueError:
        table = None
    if table is not None and table.size > first:
        width = first + 1 + int(table[first])
        if width > first + 1 and table.size == width * len(rows):
            table = table.reshape(len(rows), width)
            if (table[:, first] == width - first - 1).all() and table[:, first + 1:].min() >= 1:
                return int(table[:, first + 1:].max())
    largest = 0
    for k, row in enumerate(rows):
        fields = row.split()
        try:
            npts = int(fields[first])
            pts = [int(p) for p in fields[first + 1:first + 1 + npts]]
        except (IndexError, ValueError):
            pts, npts = [], -1
        if npts < 1 or len(pts) != npts or min(pts) < 1:
            raise file_error(path, f"is damaged: row {k + 1} of section '{section}' is not an "
                                   f"element: {row.strip()[:80]!r}")
        largest = max(largest, max(pts))
    return largest


def _read_vol(path: Path, curve: bool) -> netgen.meshing.Mesh:
    from netgen.meshing import Mesh as NetgenMesh

    text = _read_vol_text(path)
    mesh_part, geometry_part = _check_vol(path, text)
    has_geometry = bool(geometry_part.strip())
    if curve and not has_geometry:
        raise file_error(path, "carries no geometry to curve the mesh to (only .vol files that "
                               "Netgen meshed from an OCC geometry do): curve_order must be "
                               "None or 1")
    if curve:
        _probe_geometry(path, geometry_part)
        content = mesh_part + geometry_part
    else:
        # Without curving the geometry is not needed: leave it out, Netgen's geometry reader
        # does not survive a damaged one either.
        content = mesh_part
    with tempfile.TemporaryDirectory(prefix="ngincompat-mesh-") as tmpdir:
        plain = Path(tmpdir) / "mesh.vol"
        plain.write_text(content, encoding="utf-8")
        ngmesh = NetgenMesh(dim=3)
        try:
            ngmesh.Load(str(plain))
        except Exception as exc:    # Netgen raises its own exception types
            raise file_error(path, f"Netgen could not read it: {one_line(exc)}") from None
    return ngmesh


_PROBE = """
import sys
from netgen.meshing import Mesh
m = Mesh(dim=3)
m.Load(sys.argv[1])
if type(m.GetGeometry()).__name__ == "NetgenGeometry":
    sys.exit("no geometry was read")
"""


#: SHA-256 of the geometry parts this process has test-read successfully.
_GEOMETRIES_READ: set[str] = set()


def _probe_geometry(path: Path, geometry_part: str) -> None:
    """Read the geometry part of a .vol file in a separate process (it may crash or hang)."""
    digest = hashlib.sha256(geometry_part.encode()).hexdigest()
    if digest in _GEOMETRIES_READ:
        return
    with tempfile.TemporaryDirectory(prefix="ngincompat-geo-") as tmpdir:
        probe = Path(tmpdir) / "geometry.vol"
        probe.write_text("mesh3d\ndimension\n3\n\nendmesh\n" + geometry_part, encoding="utf-8")
        try:
            done = subprocess.run([sys.executable, "-c", _PROBE, str(probe)],
                                  capture_output=True, text=True,
                                  timeout=_GEOMETRY_PROBE_TIMEOUT)
        except subprocess.TimeoutExpired:
            raise file_error(path, f"its geometry (after 'endmesh') could not be read: Netgen "
                                   f"did not finish in {_GEOMETRY_PROBE_TIMEOUT} s; read the mesh "
                                   "without curving it again") from None
    if done.returncode != 0:
        if done.returncode < 0:
            reason = f"Netgen crashed (signal {-done.returncode})"
        else:
            tail = [s for s in done.stderr.strip().splitlines() if s.strip()]
            reason = one_line(tail[-1]) if tail else f"exit status {done.returncode}"
        raise file_error(path, f"its geometry (after 'endmesh') could not be read: {reason}; "
                               "read the mesh without curving it again")
    _GEOMETRIES_READ.add(digest)


def _checked_vol_mesh(path: Path, ngmesh: netgen.meshing.Mesh) -> ngs.Mesh:
    """The ngsolve.Mesh of a .vol file whose nodes are all corners of volume elements."""
    mesh = ngs.Mesh(ngmesh)
    npoints = len(ngmesh.Points())
    if npoints != mesh.nv:
        raise file_error(path, f"has {npoints - mesh.nv} nodes that are not element corners "
                                   "(second-order elements?): only first-order .vol meshes are "
                                   "read")
    used = np.zeros(npoints + 1, dtype=bool)
    used[ngmesh.Elements3D().NumPy()["nodes"].ravel()] = True
    unused = np.flatnonzero(~used[1:])
    if len(unused):
        k = int(unused[0])
        raise file_error(path, f"{len(unused)} of its {npoints} nodes belong to no volume "
                                   f"element, the first is node {k + 1} at "
                                   f"{point(ngmesh.Coordinates()[k])}; remove them")
    if mesh.GetNE(ngs.BND) == 0:
        log.warning("%s has no boundary elements: the whole surface is traction-free and no "
                    "boundary can be clamped by name", path)
    return mesh
