"""Inputs that users bring: their own mesh file and a growth field given as data on it.

This is what the ``custom`` scene reads when a run is not built from a geometry of
:mod:`geometries` and an expression for theta, but from files:

* :func:`load_mesh` reads a Netgen ``.vol`` / ``.vol.gz`` file, or a Gmsh, VTK, Abaqus or
  MEDIT file through meshio (:mod:`ngincompat.workflow.meshfiles`), and checks it, so that a
  damaged file is a :class:`~ngincompat.errors.ParameterError` naming the parameter, the
  file and the problem, not a crash;
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

import gzip
import hashlib
import logging
import math
import os
import zipfile
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np

from ngincompat.atomic import atomic_path
from ngincompat.errors import ParameterError, require
from ngincompat.workflow import io, meshfiles, volfile
from ngincompat.workflow.meshfiles import (
    MESHIO_FORMATS,
    file_error,
    one_line,
    point,
    suffix_of,
)

log = logging.getLogger(__name__)

#: File names :func:`load_mesh` reads.
MESH_EXTENSIONS = (*volfile.EXTENSIONS, *MESHIO_FORMATS)

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

# ---------------------------------------------------------------------------------------------
# meshes
# ---------------------------------------------------------------------------------------------


def load_mesh(path: str | os.PathLike, curve_order: int | None = None) -> ngs.Mesh:
    """Read a volume mesh file: Netgen's own, or one of the formats meshio reads.

    Parameters
    ----------
    path : str or os.PathLike
        A Netgen mesh ``*.vol`` or gzip-compressed ``*.vol.gz`` (as written by
        ``mesh.ngmesh.Save`` or :func:`save_mesh`), read by Netgen; or a file that meshio
        reads: Gmsh ``*.msh`` (formats 2.2 and 4.x, ASCII or binary, e.g. as Gmsh or
        ``ngmesh.Export(path, "Gmsh2 Format")`` write it), VTK ``*.vtu`` / ``*.vtk``,
        Abaqus ``*.inp``, MEDIT ``*.mesh``. Tetrahedra, hexahedra, prisms and pyramids,
        with triangles and quadrilaterals on the boundary; second-order cells are read with
        their corners only (straight-sided, with a warning).
    curve_order : int, optional
        None (default): the elements as the file has them. 1: straight-sided elements.
        2 or more: curve the elements to this order with the geometry stored in the file;
        only ``.vol`` files written by Netgen from an OCC geometry carry one (the bodies of
        :mod:`geometries` do), for others this is a :class:`ParameterError`.

    Returns
    -------
    ngsolve.Mesh
        The 3-D mesh with the material and boundary names of the file. Its vertices are the
        nodes of the file that are element corners, in the order of the file (``points`` of
        a ``.vol``, ``$Nodes`` of a ``.msh``): per-vertex data for :func:`load_growth` is
        given in that order.

    Raises
    ------
    ParameterError
        Naming ``mesh``, the file and the reason: the file is missing, a directory, has
        another extension, is truncated or damaged, is not a 3-D volume mesh (a surface or
        2-D mesh), has cells of another type, degenerate or inverted cells or nodes outside
        the elements (``.vol``), or cannot be curved.

    Notes
    -----
    Names. The growth law and the material apply per region by name; clamped faces for
    ``dirichlet`` and mirror planes for ``symmetry`` are chosen by boundary name. A ``.vol``
    file has them in ``materials`` and ``bcnames``. In the other formats regions are the
    Gmsh physical groups (named in ``$PhysicalNames``), MEDIT references, an integer cell
    array (``CellEntityIds`` or the only one) or the element sets of an Abaqus file.
    Groups without a name are called ``region<tag>`` and ``boundary<tag>`` (as
    ``ngmesh.Export`` writes Gmsh files), untagged cells ``default``; outer faces without a
    boundary cell in the file are added as boundary ``default``, so the surface is always
    closed. Boundary faces are oriented with the normal out of the region they bound, and
    cells of negative orientation are turned, whatever the file's convention; each of these
    is logged as a warning.

    Curved geometry. Only ``.vol`` files carry a geometry. A ``.vol`` file written from a
    curved mesh holds the curved elements (section ``curvedelements``) and reads back
    curved, and one written by Netgen from an OCC geometry holds that geometry too, which
    ``curve_order >= 2`` uses. Do not call ``mesh.Curve`` on the returned mesh yourself:
    the geometry is read only for ``curve_order >= 2``, and without it Netgen curves
    towards the geometry the process meshed last, which silently gives a wrong body.
    """
    path = _check_input_file(path, MESH_EXTENSIONS, "mesh")
    require(curve_order is None or (isinstance(curve_order, int) and 1 <= curve_order <= 8),
            "curve_order", curve_order, "None or an integer in [1, 8]")
    curve = curve_order is not None and curve_order > 1
    suffix = suffix_of(path, MESH_EXTENSIONS)
    if suffix in volfile.EXTENSIONS:
        mesh = volfile.read(path, curve=curve)
    elif curve:
        raise file_error(path, "this format carries no geometry to curve the mesh to: "
                               "curve_order must be None or 1")
    else:
        mesh = meshfiles.read(path, suffix)  # type: ignore[arg-type]  # a known one: checked
    if curve_order is not None:
        mesh.Curve(curve_order)
    log.info("read %s: %d elements, %d vertices, materials %s, boundaries %s", path, mesh.ne,
             mesh.nv, _unique(mesh.GetMaterials()), _unique(mesh.GetBoundaries()))
    return mesh


def save_mesh(path: str | os.PathLike, mesh: ngs.Mesh) -> Path:
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
    suffix = suffix_of(path, (".vol", ".vol.gz"))
    if suffix is None:
        raise file_error(path, "a mesh is saved as .vol or .vol.gz", "path")
    with atomic_path(path) as tmp:
        # Netgen compresses when the name ends in .vol.gz, so the temporary name must too.
        named = tmp.with_name(tmp.name + suffix)
        try:
            mesh.ngmesh.Save(str(named))
            _check_saved(named, path)
            os.replace(named, tmp)
        finally:
            if named.exists():
                named.unlink()
    return path


def _check_saved(path: Path, final: Path) -> None:
    """Raise an OSError unless Netgen wrote the whole mesh into ``path`` (its writer reports
    no failed write, e.g. on a full disk): the file holds the mesh's ``endmesh``; the message
    names ``final``, the file's final name."""
    try:
        opener = gzip.open if path.name.endswith(".gz") else open
        with opener(path, "rb") as f:
            whole = b"endmesh" in f.read()
    except (OSError, EOFError):
        whole = False
    if not whole:
        raise io.incomplete(final)


def describe_mesh(mesh: ngs.Mesh) -> dict[str, Any]:
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

def save_growth(path: str | os.PathLike, mesh: ngs.Mesh, theta: ngs.CoefficientFunction | float,
                order: int) -> Path:
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
    if suffix_of(path, (".npz",)) is None:
        raise file_error(path, "growth data is saved as .npz", "path")
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
                    float(vertex_values[bad]), bad, point(coords[bad]))
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


def load_growth(path: str | os.PathLike, mesh: ngs.Mesh) -> ngs.GridFunction:
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
    if suffix_of(path, GROWTH_EXTENSIONS) == ".npz":
        arrays = _read_npz(path)
        if "format" in arrays and str(arrays["format"]) == GROWTH_FORMAT:
            return _stored_growth(path, arrays, mesh)
        values = _user_array(path, arrays)
    else:
        values = _read_table(path)
    return _vertex_growth(path, values, mesh)


def ramped_growth(theta_data: ngs.CoefficientFunction,
                  time: ngs.Parameter | float) -> ngs.CoefficientFunction:
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
# shared helpers
# ---------------------------------------------------------------------------------------------

def _check_input_file(path: str | os.PathLike, allowed: Sequence[str], name: str) -> Path:
    """The path of an existing, readable file with an allowed extension."""
    try:
        path = Path(os.fspath(path))
    except TypeError:
        raise ParameterError(f"{name} = {path!r} is not a file name") from None
    try:
        if path.is_dir():
            raise file_error(path, "is a directory, not a file", name)
        if not path.exists():
            raise file_error(path, "does not exist", name)
    except OSError as err:      # e.g. a name longer than the file system allows
        raise file_error(path, f"cannot be looked up: {err.strerror}", name) from None
    if suffix_of(path, allowed) is None:
        raise file_error(path, f"unknown extension '{''.join(path.suffixes) or path.name}'; "
                               f"allowed: {', '.join(allowed)}", name)
    if not os.access(path, os.R_OK):
        raise file_error(path, "cannot be read (permission denied)", name)
    return path


def _unique(names: Iterable[str]) -> list[str]:
    out = []
    for name in names:
        if name not in out:
            out.append(name)
    return out


def _error(path: Path, reason: str) -> ParameterError:
    return file_error(path, reason, "theta_file")


def _first_bad(values: np.ndarray) -> int | None:
    """Index of the first value that is not finite or not > 0, or None."""
    bad = np.flatnonzero(~(np.isfinite(values) & (values > 0)))
    return int(bad[0]) if len(bad) else None


# ---------------------------------------------------------------------------------------------
# fingerprints of a mesh
# ---------------------------------------------------------------------------------------------


def _vertex_coordinates(mesh: ngs.Mesh) -> np.ndarray:
    return np.array(mesh.ngmesh.Coordinates()[:mesh.nv], dtype=float).reshape(mesh.nv, -1)


def _element_nodes(mesh: ngs.Mesh) -> np.ndarray:
    return np.ascontiguousarray(mesh.ngmesh.Elements3D().NumPy()["nodes"], dtype="<i8")


def _fingerprint(mesh: ngs.Mesh) -> dict[str, Any]:
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


def _element_values(gf: ngs.GridFunction, mesh: ngs.Mesh) -> np.ndarray:
    rules = {et: ngs.IntegrationRule([p], [1.0]) for et, p in _INTERIOR_POINTS.items()}
    return np.asarray(gf(mesh.MapToAllElements(rules, ngs.VOL)), dtype=float).ravel()


# ---------------------------------------------------------------------------------------------
# growth data
# ---------------------------------------------------------------------------------------------

def _read_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            return {key: data[key] for key in data.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        raise _error(path, f"is not a readable .npz file: {one_line(exc)}") from None


def _user_array(path: Path, arrays: Mapping[str, np.ndarray]) -> np.ndarray:
    if "theta" in arrays:
        return arrays["theta"]
    if len(arrays) == 1:
        return next(iter(arrays.values()))
    raise _error(path, f"holds the arrays {sorted(arrays)}: name the per-vertex values "
                       "'theta'")


def _read_table(path: Path) -> np.ndarray:
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise _error(path, "is not a text file") from None
    except OSError as exc:
        raise _error(path, f"cannot be read: {one_line(exc)}") from None
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
        raise _error(path, f"is not a table of numbers: {one_line(exc)}") from None
    if table.shape[1] != 1:
        raise _error(path, f"has {table.shape[1]} columns: expected one value per line "
                           "(per mesh vertex)")
    return table[:, 0]


def _vertex_growth(path: Path, values: np.ndarray, mesh: ngs.Mesh) -> ngs.GridFunction:
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


def _check_positive(path: Path, values: np.ndarray, mesh: ngs.Mesh) -> None:
    bad = _first_bad(values)
    if bad is not None:
        what = "is not finite" if not math.isfinite(values[bad]) else "is not > 0"
        raise _error(path, f"theta = {float(values[bad])!r} {what} at vertex {bad} "
                           f"{point(_vertex_coordinates(mesh)[bad])}: growth indicators must "
                           "be finite and > 0")


def _stored_growth(path: Path, arrays: Mapping[str, np.ndarray],
                   mesh: ngs.Mesh) -> ngs.GridFunction:
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
        raise _error(path, f"was written on a mesh with vertex {k} at {point(stored[k])}, in "
                           f"this one it is at {point(coords[k])} ({len(far)} vertices moved)")
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
