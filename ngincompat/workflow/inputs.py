"""Inputs that users bring: their own mesh file and a growth field given as data on it.

This is what the ``custom`` scene reads when a run is not built from a geometry of
:mod:`geometries` and an expression for theta, but from files:

* :func:`load_mesh` reads a Netgen ``.vol`` / ``.vol.gz`` file or an ASCII Gmsh ``.msh`` file
  (format 2) and checks it before Netgen sees it, so that a damaged file is a
  :class:`~ngincompat.errors.ParameterError` naming the file and the problem, not a crash;
  :func:`save_mesh` writes a ``.vol`` / ``.vol.gz`` atomically; :func:`describe_mesh` is a
  small JSON-friendly record of a mesh for results and provenance.
* :func:`save_growth` writes a scalar growth indicator theta interpolated into H1 on a mesh as
  an ``.npz`` file; :func:`load_growth` reads it back onto the same mesh (the whole dof vector,
  an exact round trip) or reads plain per-vertex data (``.npz``, ``.csv``, ``.txt``);
  :func:`ramped_growth` turns the loaded field into the load-dependent indicator of a run.

Intended use: a run writes its mesh and its growth field,
``save_mesh("o/mesh.vol", mesh)`` and ``save_growth("o/growth.npz", mesh, theta, order)``;
a later run starts from them with ::

    ngincompat run custom --out o2 --set mesh=o/mesh.vol --set theta_file=o/growth.npz

and ramps the growth linearly in the load parameter t in [0, 1],

    theta(X, t) = 1 + t (theta_data(X) - 1),

so that t = 0 is the ungrown body and t = 1 the stored growth field.
"""

import contextlib
import gzip
import hashlib
import io as _stdio
import logging
import math
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import ngsolve as ngs
import numpy as np

from ngincompat.atomic import atomic_path
from ngincompat.errors import ParameterError, require

log = logging.getLogger(__name__)

#: File names :func:`load_mesh` reads.
MESH_EXTENSIONS = (".vol", ".vol.gz", ".msh")
#: File names :func:`load_growth` reads.
GROWTH_EXTENSIONS = (".npz", ".csv", ".txt")

#: Marker and version of the files :func:`save_growth` writes.
GROWTH_FORMAT = "ngincompat-growth"
GROWTH_FORMAT_VERSION = 1

#: Vertices of two meshes are the same when they agree to this fraction of the diameter
#: plus _COORD_ATOL (a ``.vol`` file stores coordinates with 16 decimals, not the exact
#: binary value).
_COORD_RTOL = 1e-9
_COORD_ATOL = 1e-15

#: An interior point of each reference element, where :func:`save_growth` records the field
#: to check that the dofs read back mean the same field.
_INTERIOR_POINTS = {
    ngs.ET.TET: (0.25, 0.25, 0.25),
    ngs.ET.PYRAMID: (0.25, 0.25, 0.25),
    ngs.ET.PRISM: (1 / 3, 1 / 3, 0.5),
    ngs.ET.HEX: (0.5, 0.5, 0.5),
}

#: Seconds the separate process that test-reads a geometry may take.
_GEOMETRY_PROBE_TIMEOUT = 60


# ---------------------------------------------------------------------------------------------
# meshes
# ---------------------------------------------------------------------------------------------

def load_mesh(path, curve_order=None):
    """Read a volume mesh from a Netgen or Gmsh file.

    Parameters
    ----------
    path : str or os.PathLike
        A Netgen mesh ``*.vol`` or gzip-compressed ``*.vol.gz`` (as written by
        ``mesh.ngmesh.Save`` or :func:`save_mesh`), or a Gmsh mesh ``*.msh``.

        Gmsh files are read with ``netgen.read_gmsh.ReadGmsh``, which understands only the
        legacy **ASCII MSH format 2** (versions 2.0, 2.1 and 2.2). MSH 4.x, MSH 1 and binary
        files are refused with a message saying how to export format 2 (``gmsh -3 -format
        msh22 file.geo``, or ``Mesh.MshFileVersion = 2.2;`` and ``Mesh.Binary = 0;``).
        First-order elements only: tetrahedra, hexahedra, prisms and pyramids (triangles and
        quadrilaterals on the boundary); second-order elements (``Mesh.ElementOrder = 2``)
        are refused.
    curve_order : int, optional
        None (default): the elements as the file has them. 1: straight-sided elements.
        2 or more: curve the elements to this order with the geometry stored in the file;
        only ``.vol`` files written by Netgen from an OCC geometry carry one (the bodies of
        :mod:`geometries` do), for others this is a :class:`ParameterError`.

    Returns
    -------
    ngsolve.Mesh
        The 3-D mesh with the material and boundary names of the file. The vertex order is
        that of the file (``points`` of a ``.vol``, ``$Nodes`` of a ``.msh``): per-vertex data
        for :func:`load_growth` is given in that order.

    Raises
    ------
    ParameterError
        The file is missing, a directory, has another extension, cannot be read or is
        damaged (the message says what Netgen or the check found), is not a 3-D mesh, has
        no volume elements, has nodes outside the elements, or cannot be curved.

    Notes
    -----
    Names. Each material region should carry a name (``.vol``: ``materials``; Gmsh: a named
    ``Physical Volume``); the growth law and the material apply per region by name, and
    unnamed regions are called ``default``. The outer surface should be covered by boundary
    elements, grouped and named where the run needs them (``.vol``: ``bcnames``; Gmsh: named
    ``Physical Surface``): clamped faces for ``dirichlet`` and mirror planes for
    ``symmetry`` are chosen by these names. Gmsh names must not contain blanks (Netgen's
    reader cuts them at the first blank), and every physical group of a Gmsh file needs a
    name in ``$PhysicalNames``. The orientation of Gmsh boundary triangles is kept: ngsolve's
    boundary normal follows it, so it should point out of the body. A file without boundary
    elements is read (with a warning): its whole surface is then traction-free and nothing
    can be clamped by name.

    Curved geometry. A Gmsh file gives straight-sided elements and has no geometry, so its
    mesh cannot be curved. A ``.vol`` file written from a curved mesh holds the curved
    elements (section ``curvedelements``) and reads back curved, and one written by Netgen
    from an OCC geometry holds that geometry too, which ``curve_order >= 2`` uses. Do not
    call ``mesh.Curve`` on the returned mesh yourself: the geometry is read only for
    ``curve_order >= 2``, and without it Netgen curves towards the geometry the process
    meshed last, which silently gives a wrong body.
    """
    path = _check_input_file(path, MESH_EXTENSIONS, "mesh file")
    require(curve_order is None or (isinstance(curve_order, int) and 1 <= curve_order <= 8),
            "curve_order", curve_order, "None or an integer in [1, 8]")
    curve = curve_order is not None and curve_order > 1
    if _suffix(path, MESH_EXTENSIONS) == ".msh":
        if curve:
            raise _error(path, "a Gmsh file carries no geometry to curve the mesh to: "
                               "curve_order must be None or 1")
        ngmesh = _read_gmsh(path)
    else:
        ngmesh = _read_vol(path, curve=curve)
    mesh = _check_volume_mesh(path, ngmesh)
    if curve_order is not None:
        mesh.Curve(curve_order)
    log.info("read %s: %d elements, %d vertices, materials %s, boundaries %s", path, mesh.ne,
             mesh.nv, _unique(mesh.GetMaterials()), _unique(mesh.GetBoundaries()))
    return mesh


def save_mesh(path, mesh):
    """Write a mesh as a Netgen ``.vol`` or ``.vol.gz`` file, atomically.

    The file holds the material and boundary names, the curved elements of a curved mesh
    and, for a mesh Netgen generated from an OCC geometry, the geometry (with which
    :func:`load_mesh` can curve it to another order).

    Parameters
    ----------
    path : str or os.PathLike
        Ends in ``.vol`` or ``.vol.gz`` (compressed).
    mesh : ngsolve.Mesh

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    suffix = _suffix(path, (".vol", ".vol.gz"))
    if suffix is None:
        raise _error(path, "a mesh is saved as .vol or .vol.gz")
    with atomic_path(path) as tmp:
        # Netgen compresses when the name ends in .vol.gz, so the temporary name must too.
        named = tmp.with_name(tmp.name + suffix)
        try:
            mesh.ngmesh.Save(str(named))
            os.replace(named, tmp)
        finally:
            if named.exists():
                named.unlink()
    return path


def describe_mesh(mesh):
    """A JSON-friendly summary of a mesh for results and provenance.

    Parameters
    ----------
    mesh : ngsolve.Mesh

    Returns
    -------
    dict
        ``dim``, ``ne`` (volume elements), ``nv`` (vertices), ``nse`` (boundary elements),
        ``materials`` and ``boundaries`` (distinct names, in region order),
        ``curve_order`` (1: straight-sided), ``bounding_box`` ([min xyz, max xyz]) and
        ``fingerprint`` (vertex and element counts and SHA-256 labels of the connectivity
        and of the vertex coordinates, as stored by :func:`save_growth`).
    """
    coords = _vertex_coordinates(mesh)
    return {
        "dim": int(mesh.dim),
        "ne": int(mesh.ne),
        "nv": int(mesh.nv),
        "nse": int(mesh.GetNE(ngs.BND)),
        "materials": _unique(mesh.GetMaterials()),
        "boundaries": _unique(mesh.GetBoundaries()),
        "curve_order": int(mesh.ngmesh.GetCurveOrder()),
        "bounding_box": [coords.min(axis=0).tolist(), coords.max(axis=0).tolist()],
        "fingerprint": _fingerprint(mesh),
    }


# ---------------------------------------------------------------------------------------------
# growth fields
# ---------------------------------------------------------------------------------------------

def save_growth(path, mesh, theta, order):
    """Write a scalar growth indicator as H1 data on ``mesh`` (an ``.npz`` file), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Ends in ``.npz``.
    mesh : ngsolve.Mesh
        The mesh the data belongs to; save it too (:func:`save_mesh`), a later run needs the
        same mesh to read the full field back.
    theta : ngsolve.CoefficientFunction or float
        The growth indicator, e.g. a GridFunction of a computed growth field or an analytic
        expression. It is interpolated into ``H1(mesh, order)`` (projection-based
        interpolation: exact at the vertices, and for fields of that space).
    order : int
        Polynomial order of the stored field, >= 1.

    Returns
    -------
    pathlib.Path

    Notes
    -----
    The file holds

    * ``dofs``: the H1 dof vector and ``order``;
    * the mesh fingerprint ``nv``, ``ne``, ``elements_sha256`` (the vertex numbers of the
      volume elements) and ``vertices_sha256`` (the coordinates, rounded to 1e-10 of the
      diameter), and ``ngsolve_version``;
    * plain data: ``vertices`` (nv x 3 coordinates) and ``vertex_values`` (theta there);
    * ``element_values``: the field at one interior point of each element, with which
      :func:`load_growth` checks that the dofs still mean the same field.

    Non-positive or non-finite vertex values are written (with a warning); reading them
    back as a growth field fails.
    """
    path = Path(path)
    if _suffix(path, (".npz",)) is None:
        raise _error(path, "growth data is saved as .npz")
    require(isinstance(order, (int, np.integer)) and order >= 1, "order", order,
            "an integer >= 1")
    if not isinstance(theta, ngs.CoefficientFunction):
        theta = ngs.CoefficientFunction(theta)
    require(theta.dim == 1, "theta", theta, "a scalar CoefficientFunction")
    gf = ngs.GridFunction(ngs.H1(mesh, order=int(order)))
    gf.Set(theta, dual=True)
    dofs = gf.vec.FV().NumPy().copy()
    coords = _vertex_coordinates(mesh)
    vertex_values = dofs[:mesh.nv].copy()
    bad = _first_bad(vertex_values)
    if bad is not None:
        log.warning("%s: theta = %r at vertex %d %s; growth needs theta > 0", path,
                    float(vertex_values[bad]), bad, _point(coords[bad]))
    fp = _fingerprint(mesh)
    data = {
        "format": np.array(GROWTH_FORMAT),
        "format_version": np.array(GROWTH_FORMAT_VERSION),
        "order": np.array(int(order)),
        "dofs": dofs,
        "nv": np.array(fp["nv"]),
        "ne": np.array(fp["ne"]),
        "elements_sha256": np.array(fp["elements_sha256"]),
        "vertices_sha256": np.array(fp["vertices_sha256"]),
        "ngsolve_version": np.array(ngs.__version__),
        "vertices": coords,
        "vertex_values": vertex_values,
        "element_values": _element_values(gf, mesh),
    }
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, **data)
    log.info("wrote %s: theta in H1 order %d, %d dofs", path, order, len(dofs))
    return path


def load_growth(path, mesh):
    """Read a growth indicator given as data on ``mesh``.

    Parameters
    ----------
    path : str or os.PathLike
        One of

        * an ``.npz`` written by :func:`save_growth`: read back as the full H1 field of the
          order it was written with. The mesh must be the one it was written on (same
          vertices in the same order, same elements), typically read from the ``.vol``
          file that run wrote;
        * user data with one value per mesh vertex, in the mesh's vertex order (see
          :func:`load_mesh`): an ``.npz`` with an array ``theta`` (or a single array), or a
          ``.csv`` / ``.txt`` with one number per line (``#`` starts a comment, a first line
          that is not a number is taken as a header). It becomes the piecewise linear
          (H1 order 1) field with these vertex values.
    mesh : ngsolve.Mesh

    Returns
    -------
    ngsolve.GridFunction
        theta_data in H1; ramp it with :func:`ramped_growth`.

    Raises
    ------
    ParameterError
        The file is missing, a directory, has another extension or cannot be read; the
        stored field was written on another mesh (the message says what differs); the
        user data has another length than the mesh has vertices; or a value is not finite
        or not positive (the message names the first such vertex and its coordinates:
        growth indicators must be > 0).
    """
    path = _check_input_file(path, GROWTH_EXTENSIONS, "growth file")
    if _suffix(path, GROWTH_EXTENSIONS) == ".npz":
        arrays = _read_npz(path)
        if "format" in arrays and str(arrays["format"]) == GROWTH_FORMAT:
            return _stored_growth(path, arrays, mesh)
        values = _user_array(path, arrays)
    else:
        values = _read_table(path)
    return _vertex_growth(path, values, mesh)


def ramped_growth(theta_data, time):
    """The growth indicator of a run ramped in the load parameter.

    Parameters
    ----------
    theta_data : ngsolve.CoefficientFunction
        The growth field at full load, e.g. from :func:`load_growth`.
    time : ngsolve.Parameter or float
        The load parameter t in [0, 1].

    Returns
    -------
    ngsolve.CoefficientFunction
        theta(X, t) = 1 + t (theta_data(X) - 1): no growth at t = 0, theta_data at t = 1.
    """
    return 1 + time * (theta_data - 1)


# ---------------------------------------------------------------------------------------------
# checks shared by both readers
# ---------------------------------------------------------------------------------------------

def _error(path, reason):
    return ParameterError(f"{path}: {reason}")


def _suffix(path, allowed):
    name = Path(path).name.lower()
    for ext in sorted(allowed, key=len, reverse=True):
        if name.endswith(ext):
            return ext
    return None


def _check_input_file(path, allowed, what):
    try:
        path = Path(os.fspath(path))
    except TypeError:
        raise ParameterError(f"{what} {path!r} is not a file name") from None
    if path.is_dir():
        raise _error(path, f"is a directory, not a {what}")
    if not path.exists():
        raise _error(path, f"{what} does not exist")
    if _suffix(path, allowed) is None:
        raise _error(path, f"unknown {what} extension '{''.join(path.suffixes) or path.name}';"
                           f" allowed: {', '.join(allowed)}")
    if not os.access(path, os.R_OK):
        raise _error(path, f"{what} cannot be read (permission denied)")
    return path


def _one_line(exc):
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def _unique(names):
    out = []
    for name in names:
        if name not in out:
            out.append(name)
    return out


def _point(p):
    return "(" + ", ".join(f"{float(c):.6g}" for c in p) + ")"


def _first_bad(values):
    """Index of the first value that is not finite or not > 0, or None."""
    bad = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
    return int(bad[0]) if len(bad) else None


# ---------------------------------------------------------------------------------------------
# Netgen .vol
# ---------------------------------------------------------------------------------------------

#: Sections of the mesh part of a .vol file whose rows are checked: name -> row kind.
_VOL_CHECKED = {
    "points": "points",
    "volumeelements": "volume",
    "surfaceelements": "surface",
    "surfaceelementsgi": "surface",
    "surfaceelementsuv": "surface",
}


def _read_vol_text(path):
    try:
        if path.name.lower().endswith(".gz"):
            with gzip.open(path, "rt", encoding="utf-8") as f:
                return f.read()
        return path.read_text(encoding="utf-8")
    except (EOFError, gzip.BadGzipFile) as exc:
        raise _error(path, f"damaged gzip data: {_one_line(exc)}") from None
    except UnicodeDecodeError:
        raise _error(path, "is not a text file: not a Netgen mesh") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {_one_line(exc)}") from None


def _check_vol(path, text):
    """Check the mesh part of a .vol file; return (mesh part, geometry part).

    Netgen's reader does not report a damaged file: it crashes, hangs, or returns an empty
    mesh. So the structure is checked here: the ``mesh3d`` header, a 3-D dimension, the row
    counts of the points and elements, the point numbers of the elements and the final
    ``endmesh`` line.
    """
    lines = text.split("\n")
    n = len(lines)
    i = 0

    def next_data(i):
        while i < n and (not lines[i].strip() or lines[i].lstrip().startswith("#")):
            i += 1
        return i

    i = next_data(i)
    if i >= n or lines[i].strip() != "mesh3d":
        raise _error(path, "is not a Netgen mesh (the file does not start with 'mesh3d')")
    i += 1
    npoints, max_point, nvol, section = None, 0, 0, "mesh3d"
    end = None
    while True:
        i = next_data(i)
        if i >= n:
            raise _error(path, f"is truncated: the file ends in section '{section}' without "
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
                raise _error(path, f"is not a 3-D mesh (dimension {dim}): a volume mesh is "
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
            raise _error(path, f"section '{word}' (line {i}) does not start with a row count")
        rows = lines[i + 1:i + 1 + count]
        if len(rows) < count or not all(r.strip() for r in rows):
            found = sum(1 for r in rows if r.strip())
            raise _error(path, f"is truncated or damaged: section '{word}' announces {count} "
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
        raise _error(path, "has no volume elements: a 3-D volume mesh is needed")
    if npoints is None:
        raise _error(path, "has no 'points' section")
    if max_point > npoints:
        raise _error(path, f"is damaged: an element uses point {max_point} but the file has "
                           f"{npoints} points")
    return "\n".join(lines[:end]) + "\n", "\n".join(lines[end:])


def _check_point_rows(path, rows):
    try:
        xyz = np.array(" ".join(rows).split(), dtype=float)
    except ValueError as exc:
        raise _error(path, f"is damaged: section 'points' has a value that is not a number "
                           f"({_one_line(exc)})") from None
    if xyz.size != 3 * len(rows):
        raise _error(path, "is damaged: section 'points' has rows that are not 3 coordinates")
    if not np.isfinite(xyz).all():
        raise _error(path, "is damaged: section 'points' has coordinates that are not finite")


def _check_element_rows(path, section, rows, first):
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
            raise _error(path, f"is damaged: row {k + 1} of section '{section}' is not an "
                               f"element: {row.strip()[:80]!r}")
        largest = max(largest, max(pts))
    return largest


def _read_vol(path, curve):
    from netgen.meshing import Mesh as NetgenMesh

    text = _read_vol_text(path)
    mesh_part, geometry_part = _check_vol(path, text)
    has_geometry = bool(geometry_part.strip())
    if curve and not has_geometry:
        raise _error(path, "carries no geometry to curve the mesh to (only .vol files that "
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
            raise _error(path, f"Netgen could not read it: {_one_line(exc)}") from None
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
_GEOMETRIES_READ = set()


def _probe_geometry(path, geometry_part):
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
            raise _error(path, f"its geometry (after 'endmesh') could not be read: Netgen did "
                               f"not finish in {_GEOMETRY_PROBE_TIMEOUT} s; read the mesh without "
                               "curving it again") from None
    if done.returncode != 0:
        if done.returncode < 0:
            reason = f"Netgen crashed (signal {-done.returncode})"
        else:
            tail = [s for s in done.stderr.strip().splitlines() if s.strip()]
            reason = _one_line(tail[-1]) if tail else f"exit status {done.returncode}"
        raise _error(path, f"its geometry (after 'endmesh') could not be read: {reason}; "
                           "read the mesh without curving it again")
    _GEOMETRIES_READ.add(digest)


# ---------------------------------------------------------------------------------------------
# Gmsh .msh
# ---------------------------------------------------------------------------------------------

_GMSH_EXPORT = ("export ASCII format 2: gmsh -3 -format msh22 file.geo, or "
                "Mesh.MshFileVersion = 2.2; Mesh.Binary = 0;")


def _check_gmsh_header(path):
    """Check the format line and the physical names, which come before $Nodes."""
    try:
        with open(path, encoding="utf-8") as f:
            first = ""
            for line in f:
                if line.strip():
                    first = line.strip()
                    break
            if first in ("$NOD", "$NOE"):
                raise _error(path, f"is a Gmsh format 1 file, which is not read; {_GMSH_EXPORT}")
            if first != "$MeshFormat":
                raise _error(path, "is not a Gmsh mesh (the file does not start with "
                                   "$MeshFormat)")
            fields = f.readline().split()
            if len(fields) < 2:
                raise _error(path, "is damaged: no format line after $MeshFormat")
            version, binary = fields[0], fields[1]
            if not version.startswith("2"):
                raise _error(path, f"is Gmsh format {version}; only ASCII format 2 (2.0-2.2) is "
                                   f"read; {_GMSH_EXPORT}")
            if binary != "0":
                raise _error(path, f"is a binary Gmsh file; {_GMSH_EXPORT}")
            for line in f:
                word = line.strip()
                if word == "$PhysicalNames":
                    _check_physical_names(path, f)
                elif word == "$Nodes":
                    return
    except UnicodeDecodeError:
        raise _error(path, f"is not a text file (a binary Gmsh file?); {_GMSH_EXPORT}") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {_one_line(exc)}") from None
    raise _error(path, "is truncated or damaged: no $Nodes section")


def _check_physical_names(path, f):
    try:
        count = int(f.readline())
    except ValueError:
        raise _error(path, "is damaged: $PhysicalNames does not start with a count") from None
    for _ in range(count):
        line = f.readline().strip()
        parts = line.split(maxsplit=2)
        if len(parts) < 3 or not parts[2].startswith('"') or not parts[2].endswith('"'):
            raise _error(path, f"is damaged: $PhysicalNames line {line!r} is not "
                               "'dim tag \"name\"'")
        if len(parts[2][1:-1].split()) != 1:
            raise _error(path, f"physical name {parts[2]} contains blanks, which Netgen's Gmsh "
                               "reader cannot read: rename it")


def _read_gmsh(path):
    from netgen.read_gmsh import ReadGmsh

    _check_gmsh_header(path)
    printed = _stdio.StringIO()
    try:
        with contextlib.redirect_stdout(printed):
            ngmesh = ReadGmsh(str(path))
    except Exception as exc:
        reason = _diagnose_gmsh(path) or f"Netgen's Gmsh reader failed: {_one_line(exc)}"
        raise _error(path, reason) from None
    finally:
        if printed.getvalue().strip():
            log.debug("ReadGmsh(%s): %s", path, printed.getvalue().strip())
    return ngmesh


def _diagnose_gmsh(path):
    """After ReadGmsh failed: find the first reason in the file, or None."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    names = {d: {0} for d in range(4)}
    nodes = set()
    announced, rows = {}, {}
    section, k = None, 0
    try:
        while k < len(lines):
            word = lines[k].strip()
            k += 1
            if word.startswith("$"):
                section = None if word.startswith("$End") else word
                if section in ("$PhysicalNames", "$Nodes", "$Elements"):
                    announced[section], rows[section] = int(lines[k].split()[0]), 0
                    k += 1
                continue
            if section not in rows:
                continue
            fields = word.split()
            if not fields:
                return f"is damaged: line {k} in {section} is empty"
            rows[section] += 1
            if section == "$PhysicalNames":
                names[int(fields[0])].add(int(fields[1]))
            elif section == "$Nodes":
                nodes.add(int(fields[0]))
            else:
                reason = _diagnose_gmsh_element(fields, names, nodes)
                if reason:
                    return reason
    except (ValueError, IndexError, KeyError):
        return f"is truncated or damaged: line {k} in {section} is malformed"
    if "$Elements" not in announced:
        return "is truncated or damaged: no $Elements section"
    for key, count in announced.items():
        if rows[key] != count:
            return f"is truncated or damaged: {key} announces {count} rows but has {rows[key]}"
    return None


#: Dimension of each Gmsh element type Netgen's reader knows.
_GMSH_DIM = {1: 1, 2: 2, 3: 2, 4: 3, 5: 3, 6: 3, 7: 3, 8: 1, 9: 2, 11: 3, 15: 0, 16: 2, 17: 3,
             18: 3, 19: 3}


def _diagnose_gmsh_element(fields, names, nodes):
    etype, ntags = int(fields[1]), int(fields[2])
    if etype not in _GMSH_DIM:
        return f"element {fields[0]} has type {etype}, which Netgen's Gmsh reader does not know"
    if ntags < 2:
        return (f"element {fields[0]} has {ntags} tags; Netgen's reader needs the physical and "
                "the elementary tag")
    physical, dim = int(fields[3]), _GMSH_DIM[etype]
    if physical not in names[dim]:
        return (f"physical group {physical} (dimension {dim}) has no name in $PhysicalNames; "
                "Netgen's reader needs a name for every physical group")
    for node in fields[3 + ntags:]:
        if int(node) not in nodes:
            return f"element {fields[0]} uses node {node}, which is not in $Nodes"
    return None


# ---------------------------------------------------------------------------------------------
# the mesh Netgen read
# ---------------------------------------------------------------------------------------------

def _check_volume_mesh(path, ngmesh):
    """Check a Netgen mesh for what a volume-growth run needs; return the ngsolve.Mesh."""
    if ngmesh.dim != 3:
        raise _error(path, f"is a {ngmesh.dim}-D mesh: a 3-D volume mesh is needed")
    elements = ngmesh.Elements3D().NumPy()
    if len(elements) == 0:
        raise _error(path, "has no volume elements: a 3-D volume mesh is needed")
    mesh = ngs.Mesh(ngmesh)
    npoints = len(ngmesh.Points())
    if npoints != mesh.nv:
        raise _error(path, f"has {npoints - mesh.nv} nodes that are not element corners "
                           "(second-order elements?): only first-order meshes are read")
    used = np.zeros(npoints + 1, dtype=bool)
    used[elements["nodes"].ravel()] = True
    unused = np.flatnonzero(~used[1:])
    if len(unused):
        k = int(unused[0])
        raise _error(path, f"{len(unused)} of its {npoints} nodes belong to no volume element, "
                           f"the first is node {k + 1} at {_point(ngmesh.Coordinates()[k])}; "
                           "remove them")
    if mesh.GetNE(ngs.BND) == 0:
        log.warning("%s has no boundary elements: the whole surface is traction-free and no "
                    "boundary can be clamped by name", path)
    return mesh


def _vertex_coordinates(mesh):
    return np.array(mesh.ngmesh.Coordinates()[:mesh.nv], dtype=float).reshape(mesh.nv, -1)


def _element_nodes(mesh):
    return np.ascontiguousarray(mesh.ngmesh.Elements3D().NumPy()["nodes"], dtype="<i8")


def _fingerprint(mesh):
    coords = _vertex_coordinates(mesh)
    diameter = float(np.ptp(coords, axis=0).max()) if len(coords) else 0.0
    rounded = np.round(coords / (diameter or 1.0), 10) + 0.0     # + 0.0: no negative zeros
    return {
        "nv": int(mesh.nv),
        "ne": int(mesh.ne),
        "elements_sha256": hashlib.sha256(_element_nodes(mesh).tobytes()).hexdigest(),
        "vertices_sha256": hashlib.sha256(np.ascontiguousarray(rounded, dtype="<f8")
                                          .tobytes()).hexdigest(),
    }


def _element_values(gf, mesh):
    rules = {et: ngs.IntegrationRule([p], [1.0]) for et, p in _INTERIOR_POINTS.items()}
    return np.asarray(gf(mesh.MapToAllElements(rules, ngs.VOL)), dtype=float).ravel()


# ---------------------------------------------------------------------------------------------
# growth data
# ---------------------------------------------------------------------------------------------

def _read_npz(path):
    try:
        with np.load(path, allow_pickle=False) as data:
            return {key: data[key] for key in data.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        raise _error(path, f"is not a readable .npz file: {_one_line(exc)}") from None


def _user_array(path, arrays):
    if "theta" in arrays:
        return arrays["theta"]
    if len(arrays) == 1:
        return next(iter(arrays.values()))
    raise _error(path, f"holds the arrays {sorted(arrays)}: name the per-vertex values "
                       "'theta'")


def _read_table(path):
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise _error(path, "is not a text file") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {_one_line(exc)}") from None
    delimiter = "," if path.name.lower().endswith(".csv") else None
    lines = text.splitlines()
    data = [k for k, s in enumerate(lines) if s.split("#", 1)[0].strip()]
    if data:
        first = lines[data[0]].split("#", 1)[0]
        try:
            [float(v) for v in first.split(delimiter)]
        except ValueError:
            lines[data[0]] = ""         # a header line
    try:
        table = np.loadtxt(lines, delimiter=delimiter, comments="#", ndmin=2, dtype=float)
    except ValueError as exc:
        raise _error(path, f"is not a table of numbers: {_one_line(exc)}") from None
    if table.shape[1] != 1:
        raise _error(path, f"has {table.shape[1]} columns: expected one value per line "
                           "(per mesh vertex)")
    return table[:, 0]


def _vertex_growth(path, values, mesh):
    values = np.asarray(values)
    if values.dtype.kind not in "biuf":
        raise _error(path, f"holds {values.dtype} data, not numbers")
    values = values.astype(float)
    if values.ndim != 1:
        values = values.squeeze()
    if values.ndim != 1:
        raise _error(path, f"holds an array of shape {values.shape}: expected one value per "
                           f"mesh vertex ({mesh.nv})")
    if len(values) != mesh.nv:
        raise _error(path, f"has {len(values)} values, expected {mesh.nv} (one per mesh "
                           "vertex, in the mesh's vertex order)")
    _check_positive(path, values, mesh)
    gf = ngs.GridFunction(ngs.H1(mesh, order=1))
    gf.vec.FV().NumPy()[:] = values
    log.info("read %s: theta at %d vertices in [%g, %g]", path, len(values), values.min(),
             values.max())
    return gf


def _check_positive(path, values, mesh):
    bad = _first_bad(values)
    if bad is not None:
        what = "is not finite" if not math.isfinite(values[bad]) else "is not > 0"
        raise _error(path, f"theta = {float(values[bad])!r} {what} at vertex {bad} "
                           f"{_point(_vertex_coordinates(mesh)[bad])}: growth indicators must "
                           "be finite and > 0")


def _stored_growth(path, arrays, mesh):
    required = ("format_version", "order", "dofs", "nv", "ne", "elements_sha256", "vertices",
                "vertex_values", "element_values")
    missing = [key for key in required if key not in arrays]
    if missing:
        raise _error(path, f"is damaged: the growth data lacks {', '.join(missing)}")
    version = int(arrays["format_version"])
    if version > GROWTH_FORMAT_VERSION:
        raise _error(path, f"has growth format version {version}; this ngincompat reads up to "
                           f"{GROWTH_FORMAT_VERSION}")
    nv, ne = int(arrays["nv"]), int(arrays["ne"])
    if nv != mesh.nv:
        raise _error(path, f"was written on a mesh with {nv} vertices, this one has {mesh.nv}")
    if ne != mesh.ne:
        raise _error(path, f"was written on a mesh with {ne} elements, this one has {mesh.ne}")
    if str(arrays["elements_sha256"]) != _fingerprint(mesh)["elements_sha256"]:
        raise _error(path, f"was written on a mesh with as many vertices ({nv}) and elements "
                           f"({ne}) but other elements (a new mesh of the geometry?); read the "
                           "mesh it was written on")
    coords = _vertex_coordinates(mesh)
    stored = np.asarray(arrays["vertices"], dtype=float)
    diameter = float(np.ptp(coords, axis=0).max())
    if stored.shape != coords.shape:
        raise _error(path, f"is damaged: vertices of shape {stored.shape}, expected "
                           f"{coords.shape}")
    distance = np.abs(stored - coords).max(axis=1)
    far = np.flatnonzero(distance > _COORD_RTOL * diameter + _COORD_ATOL)
    if len(far):
        k = int(far[0])
        raise _error(path, f"was written on a mesh with vertex {k} at {_point(stored[k])}, in "
                           f"this one it is at {_point(coords[k])} ({len(far)} vertices moved)")
    order = int(arrays["order"])
    gf = ngs.GridFunction(ngs.H1(mesh, order=order))
    dofs = np.asarray(arrays["dofs"], dtype=float)
    if len(dofs) != len(gf.vec):
        raise _error(path, f"holds {len(dofs)} dofs of H1 order {order}, on this mesh the space "
                           f"has {len(gf.vec)}")
    if not np.isfinite(dofs).all():
        raise _error(path, "holds dofs that are not finite")
    _check_positive(path, dofs[:nv], mesh)
    gf.vec.FV().NumPy()[:] = dofs
    expected = np.asarray(arrays["element_values"], dtype=float)
    got = _element_values(gf, mesh)
    scale = max(1.0, float(np.abs(expected).max())) if len(expected) else 1.0
    if got.shape != expected.shape or np.abs(got - expected).max() > 1e-8 * scale:
        written = str(arrays.get("ngsolve_version", "unknown"))
        raise _error(path, f"its dofs do not give back the stored field on this mesh (dof "
                           f"numbering of ngsolve {written} vs {ngs.__version__}?)")
    log.info("read %s: theta in H1 order %d, %d dofs", path, order, len(dofs))
    return gf
