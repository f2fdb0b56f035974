"""A run's folder: checked before any computation, written from a :class:`Results` only.

:func:`prepare` runs first: the folder must be a folder (or creatable), not a system folder
(:data:`SYSTEM`), writable, not in use by another run (:data:`LOCK`, held until
:func:`release`), and not hold another run unless ``overwrite`` is given, which removes the
files the old run wrote (listed in its results.json or summary.json; a scene's run records
their SHA-256, and a file whose content is no longer what the run wrote, or that it did not
write, is kept) and nothing else. A folder that holds no run but files of the names a scene's
run writes (:data:`RUN_FILES`: someone's own fields.vtu or figures) is refused too unless
``overwrite``: the run would replace them. :func:`write`
writes results.json, the
VTK fields, the figures and the growth field as data, each atomically, so an interrupted run
never leaves a half-written file; :func:`read` reads results.json back into a
:class:`Results` (without the NGSolve fields).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import socket
import sys
import tempfile
import time
from collections.abc import Iterable, Iterator
from pathlib import Path

import ngsolve as ngs

from ngincompat import parallel
from ngincompat.errors import ParameterError
from ngincompat.parameters import OUTPUTS as OUTPUTS  # the names, re-exported
from ngincompat.parameters import Outputs
from ngincompat.workflow import io, plots
from ngincompat.workflow.inputs import save_growth, save_mesh
from ngincompat.workflow.results import Results

log = logging.getLogger(__name__)

#: Files that mark a folder as holding a run (a scene's, or a summary of several).
MARKERS = ("results.json", "summary.json")
#: The file by which a run holds its folder while it computes: its process, host, start and
#: command line. A second run into the folder is refused while the holder lives; the file of a
#: process that died (killed, a crashed machine) is removed with a warning.
LOCK = ".ngincompat.lock"
#: Folders :func:`prepare` created in this process (removed by :func:`release` if empty).
_created: set[Path] = set()
#: Folders no run writes into: the root of the file system and its system folders, and
#: anything in the kernel's (:data:`KERNEL`).
SYSTEM = ("/", "/bin", "/boot", "/dev", "/etc", "/lib", "/lib32", "/lib64", "/proc", "/run",
          "/sbin", "/sys", "/usr", "/var")
#: The kernel's folders: no run writes anywhere in them.
KERNEL = ("/dev", "/proc", "/sys")
#: The names of the files a scene's run writes besides results.json (glob patterns): a
#: folder without a run that holds such files is not written into without ``overwrite``.
RUN_FILES = ("fields*.vtu", "fields*.pvd", "*.png", "mesh.vol", "growth.npz",
             "checkpoint.npz")


def prepare(out: str | os.PathLike, overwrite: bool = False, resume: bool = False,
            run_files: Iterable[str] = ()) -> Path:
    """Check that ``out`` can take a run's files, before anything is computed.

    Parameters
    ----------
    out : path-like
        The output folder; created if missing.
    overwrite : bool
        Replace a run already in the folder: the files it lists are removed now.
    resume : bool
        The run continues the one in the folder (its checkpoint is kept).
    run_files : sequence of str
        Glob patterns of the files the run writes (:data:`RUN_FILES` for a scene's run).

    Raises
    ------
    ParameterError
        ``out`` is empty, a system folder, a file or lies under one, cannot be created or
        written, or holds another run or files matching ``run_files`` and neither
        ``overwrite`` nor ``resume`` is given.
    """
    if not str(out).strip():
        raise ParameterError("--out '' is empty: give a folder")
    out = Path(out)
    where: Path | str
    where = out.resolve()
    if str(where) in SYSTEM or any(Path(k) in where.parents for k in KERNEL):
        raise ParameterError(f"--out {out} is a system folder ({where}): give a folder of "
                             "your own")
    if out.is_symlink():
        log.warning("--out %s is a symbolic link: the run is written into %s", out,
                    out.resolve())
    for parent in [out, *out.parents]:
        if parent.exists() and not parent.is_dir():
            where = "is a file" if parent == out else f"lies under the file {parent}"
            raise ParameterError(f"--out {out} {where}: give a folder")
    if not out.exists():
        _created.add(out.absolute())
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ParameterError(f"--out {out} cannot be created: {err.strerror}") from None
    _check_writable(out)
    _acquire(out)
    try:
        marker = next((out / m for m in MARKERS if (out / m).is_file()), None)
        if marker is None and not (overwrite or resume):
            _refuse_foreign(out, run_files)
        if marker is None or resume:
            return out
        if not overwrite:
            raise ParameterError(f"--out {out} holds another run ({marker.name}): choose "
                                 "another folder, or pass --overwrite to replace it")
        _remove_run(out)
    except BaseException:
        release(out)
        raise
    return out


def _check_writable(out: Path) -> None:
    """Refuse a folder marked read-only (no write permission for anyone: root, whom the bits
    do not stop, is held to them too) or one a file cannot be created in (tried: a read-only
    file system, access control lists)."""
    if not out.stat().st_mode & 0o222:
        raise ParameterError(f"--out {out} is read-only (no write permission): choose "
                             "another folder, or make it writable")
    try:
        descriptor, probe = tempfile.mkstemp(prefix=".ngincompat-probe-", dir=out)
    except OSError as err:
        raise ParameterError(f"--out {out} is not writable: {err.strerror}") from None
    os.close(descriptor)
    os.unlink(probe)


@contextlib.contextmanager
def folder(out: str | os.PathLike, overwrite: bool = False, resume: bool = False) -> Iterator[Path]:
    """:func:`prepare` the folder for the block (yielding its path) and :func:`release` it
    after."""
    out = prepare(out, overwrite=overwrite, resume=resume)
    try:
        yield out
    finally:
        release(out)


def release(out: str | os.PathLike) -> None:
    """Let go of the folder :func:`prepare` took (nothing if this process does not hold it)."""
    path = Path(out) / LOCK
    holder = _holder(path)
    if holder.get("pid") == os.getpid() and holder.get("host") == socket.gethostname():
        path.unlink(missing_ok=True)
    folder = Path(out).absolute()
    if folder in _created:          # made for a run that wrote nothing: not left behind
        _created.discard(folder)
        _remove_if_empty(folder)


def _refuse_foreign(out: Path, patterns: Iterable[str]) -> None:
    """Refuse a folder that holds files matching ``patterns`` though no run wrote them."""
    found = sorted({p.name for pattern in patterns for p in out.glob(pattern) if p.is_file()})
    if found:
        shown = ", ".join(found[:3]) + (f" and {len(found) - 3} more" if len(found) > 3 else "")
        raise ParameterError(f"--out {out} holds files of the names a run writes ({shown}) "
                             "but no run: choose another folder, or pass --overwrite to "
                             "replace them")


def _acquire(out: Path) -> None:
    """Take the folder's :data:`LOCK`, or raise naming the live run that holds it."""
    path = out / LOCK
    record = {"pid": os.getpid(), "host": socket.gethostname(),
              "started": time.strftime("%Y-%m-%d %H:%M:%S"), "argv": sys.argv}
    for _ in range(3):
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            holder = _holder(path)
            if holder.get("pid") == os.getpid() and holder.get("host") == record["host"]:
                raise ParameterError(f"--out {out} is in use by this process's own run: "
                                     "choose another folder") from None
            if _alive(holder):
                raise ParameterError(
                    f"--out {out} is in use by another run (process {holder.get('pid')} on "
                    f"{holder.get('host')}, since {holder.get('started')}): wait for it, or "
                    "choose another folder") from None
            log.warning("%s: removing the lock of a run that no longer lives (process %s, "
                        "since %s)", out, holder.get("pid"), holder.get("started"))
            path.unlink(missing_ok=True)
            continue
        with os.fdopen(fd, "w") as f:
            json.dump(record, f)
        return
    raise ParameterError(f"--out {out}: its lock {LOCK} could not be taken (another run "
                         "keeps starting there)")


def _holder(path: Path) -> dict:
    """The record in a lock file ({} for none, or one being written)."""
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return {}


def _alive(holder: dict) -> bool:
    """Does the process that wrote ``holder`` live? One on another host is taken to live; a
    record without a process (being written this instant) too."""
    pid = holder.get("pid")
    if not isinstance(pid, int) or holder.get("host") != socket.gethostname():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_run(out: Path) -> None:
    """Remove what the run in ``out`` wrote: the files its records list, the records, and the
    folders of the runs a summary lists."""
    for name in MARKERS:
        path = out / name
        if not path.is_file():
            continue
        try:
            record = io.read_json(path)
        except (OSError, ValueError):
            record = {}
        hashes = record.get("file_hashes")
        for entry in record.get("files", []):
            if entry == name:
                continue            # the record itself, removed below
            target = (out / entry).resolve()
            if out.resolve() not in target.parents:
                continue            # never outside the folder
            if target.is_dir():
                _remove_run(target)
                _remove_if_empty(target)
            elif hashes is None or (target.is_file() and hashes.get(entry) == _sha256(target)):
                target.unlink(missing_ok=True)
            elif target.exists():
                log.warning("%s: kept %s: the run did not write it as it is now", out, entry)
        path.unlink(missing_ok=True)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _remove_if_empty(folder: Path) -> None:
    try:
        folder.rmdir()
    except OSError:
        pass


def wanted(results: Results) -> set[str]:
    """The optional outputs (:data:`OUTPUTS`) the scene's ``outputs`` parameter asks for, as
    results.json records it ("vtk,figures", "none")."""
    return set(Outputs(results.params.get("outputs", "none")))


def write(results: Results, out: str | os.PathLike, outputs: set[str] | None = None) -> Results:
    """Write a run into the folder ``out``, as the scene's ``outputs`` ask.

    results.json always; ``fields.vtu`` (every field: scalars, vectors, and tensors as 9
    components in row order, their units in results.json's ``field_units``), the figures
    and ``mesh.vol`` + ``growth.npz`` (the growth field as data, for a later run's ``--set
    mesh=... --set theta_file=...``) of the measured state, and with ``results.frames``
    (also of an interrupted or unfinished run) ``fields_NNN.vtu`` per frame and their time
    series ``fields.pvd``. ``results.files`` lists what was written; results.json is written
    last. A state with a metric that is not finite (:meth:`Results.non_finite`) was not
    computed: none of its files are written, only results.json and the frames.

    Interrupted (Ctrl-C), the files finished so far are in ``results.files`` (the time
    series then lists exactly the frames written) and the exception goes on. A write the
    machine refuses (OSError: a full disk) removes the files it had written before the error
    goes on: without their record no run owns them.

    On a distributed mesh every rank writes its part of the VTK output (``fields.pvd`` and
    one ``.vtu`` per part); rank 0 alone writes results.json and the figures; the growth
    field as data is not written (it is for serial reruns)."""
    start = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    outputs = wanted(results) if outputs is None else outputs
    files: list[str] = []
    try:
        try:
            if not _write_outputs(results, out, outputs, files):
                return results
        finally:
            results.files = [*files, *[f for f in results.files if f not in files]]
        results.files = ["results.json", *[f for f in results.files if f != "results.json"]]
        results.timings["output"] = time.perf_counter() - start
        # what the run wrote, by content: --overwrite removes these files only as they were
        hashes = {f: _sha256(out / f) for f in results.files if (out / f).is_file()}
        units = field_units(results.fields, results.units) if "vtk" in outputs else {}
        io.write_json(out / "results.json", {**results.to_dict(), "field_units": units,
                                             "file_hashes": hashes})
    except OSError:
        _discard(out, results.files)
        raise
    return results


def _discard(out: Path, names: Iterable[str]) -> None:
    """Remove the files ``names`` of a write that failed (a full disk, permissions taken
    away): without their results.json no run would own them, and the next run into the
    folder would refuse them as another's."""
    for name in names:
        with contextlib.suppress(OSError):
            (out / name).unlink(missing_ok=True)


def _write_outputs(results: Results, out: Path, outputs: set[str], files: list[str]) -> bool:
    """The files of :func:`write` but results.json, each appended to ``files`` once written;
    False on the ranks of a distributed run other than 0 (which write no more)."""
    state = bool(results.fields) and not results.non_finite()
    distributed = results.domain is not None and parallel.distributed(results.domain)
    if results.domain is not None and "vtk" in outputs:
        subdivision = 2 if results.mesh.order >= 3 else 1
        if state:
            vtk = interpolated(results.fields, results.domain,
                               min(results.mesh.order, VTK_ORDER))
            if distributed:
                files += io.write_vtk_parallel(out / "fields", results.domain, vtk,
                                               subdivision=subdivision)
            else:
                io.write_vtk(out / "fields.vtu", results.domain, vtk, subdivision=subdivision)
                files.append("fields.vtu")
        if distributed:
            files += _write_frames_parallel(out, results, subdivision)
        else:
            _write_frames(out, results, subdivision, files)
    if state and "growth" in outputs and "theta" in results.fields and not distributed:
        save_mesh(out / "mesh.vol", results.domain)
        files.append("mesh.vol")
        save_growth(out / "growth.npz", results.domain, results.fields["theta"],
                    order=max(results.mesh.order, 2))
        files.append("growth.npz")
    if not parallel.is_root():
        return False
    if "figures" in outputs and not results.non_finite():
        for figure in results.figures:
            if all(k in results.profiles.get(figure.profile, {}) for k in figure.keys()):
                plots.draw(results, figure, out / figure.file)
                files.append(figure.file)
    return True


def _write_frames(out: Path, results: Results, subdivision: int, files: list[str]) -> None:
    """The time series of ``results.frames``: one ``fields_NNN.vtu`` per frame and the
    collection ``fields.pvd`` that orders them by time (written last), appended to
    ``files``. Interrupted or failing part-way, the collection of the frames written so far
    is written before the exception goes on: it lists exactly the frame files there are."""
    datasets = []
    try:
        for k, (t, fields) in enumerate(results.frames):
            name = f"fields_{k:03d}.vtu"
            io.write_vtk(out / name, results.domain, fields, subdivision=subdivision)
            datasets.append((t, name))
            files.append(name)
    except BaseException:
        if datasets:
            with contextlib.suppress(OSError):      # a full disk: the frames stay unlisted
                io.write_pvd(out / "fields.pvd", datasets)
                files.append("fields.pvd")
        raise
    if datasets:
        io.write_pvd(out / "fields.pvd", datasets)
        files.append("fields.pvd")


def _write_frames_parallel(out: Path, results: Results, subdivision: int) -> list[str]:
    """The time series of ``results.frames`` on a distributed mesh: per frame
    ``fields_NNN.pvd`` and its parts ``fields_NNN_procK.vtu`` (every rank writes its own),
    and the collection ``fields_series.pvd`` of every frame's parts by time (rank 0, last).
    Collective: call on every rank."""
    datasets, files = [], []
    for k, (t, fields) in enumerate(results.frames):
        written = io.write_vtk_parallel(out / f"fields_{k:03d}", results.domain, fields,
                                        subdivision=subdivision)
        files += written
        parts = sorted(name for name in written if name.endswith(".vtu"))
        datasets += [(t, name, part) for part, name in enumerate(parts)]
    if not datasets:
        return []
    if parallel.is_root():
        io.write_pvd(out / "fields_series.pvd", datasets)
    return [*files, "fields_series.pvd"]


#: Highest order of the interpolants in the VTK file: order 4 costs a quarter of order 5 on
#: the hemisphere's stresses and stays within 1.4e-4 of the field in relative L2, which
#: cannot be seen in a plot (``docs/measurements/solver-costs.md``, the prescribed scenes).
VTK_ORDER = 4


def interpolated(fields: dict, mesh: ngs.Mesh, order: int, copy: bool = False) -> dict:
    """The fields for the VTK file: GridFunctions as they are (copies if ``copy``, so later
    changes of the state do not reach them: a frame of a time series), every other field as
    its element-wise (L2) interpolant of ``order``.

    VTK output evaluates a CoefficientFunction point by point; the interpolant evaluates it
    once at the integration points, vectorised: a tenth of the time for a stress from the
    symbolic derivative of the GOH energy on the disc (``docs/measurements/solver-costs.md``,
    the prescribed scenes), and the file differs from the field by its interpolation error.
    Metrics and profiles never read the file."""
    out = {}
    for name, cf in fields.items():
        if isinstance(cf, ngs.GridFunction):
            out[name] = cf
            if copy:
                out[name] = ngs.GridFunction(cf.space, name=name)
                out[name].vec.data = cf.vec
            continue
        # one space of cf.dim components, not the product space L2**dim: the same values,
        # set in one pass instead of one per component
        out[name] = ngs.GridFunction(ngs.L2(mesh, order=order, dim=cf.dim))
        out[name].Set(cf)
    return out


#: The quantity each field measures, by its name or the start of its name (``S11``,
#: ``sigma_max_principal``, ``u_released``), spelled in a scene's units by :func:`field_units`;
#: every other field is a ratio (theta, J, Je, Fg, Fe, concentrations, modes). An energy
#: density is a stress.
FIELD_QUANTITIES = (("curlFg_sq", "1/length^2"), ("scalar_curvature", "1/length^2"),
                    ("einstein_norm_g", "1/length^2"), ("Psi", "stress"), ("sigma", "stress"),
                    ("P", "stress"), ("S", "stress"), ("u", "length"), ("G", "1/length"),
                    ("b_", "1/length"), ("|b", "1/length"))


def field_units(fields: dict, units: dict) -> dict[str, str]:
    """Field name -> unit in the scene's ``units`` ("-" for a ratio), for results.json."""
    out = {}
    for name in fields:
        quantity = next((q for prefix, q in FIELD_QUANTITIES if name.startswith(prefix)), None)
        if quantity is None:
            out[name] = "-"
            continue
        for key, symbol in units.items():
            quantity = quantity.replace(key, symbol)
        out[name] = quantity
    return out


def read(out: str | os.PathLike) -> Results:
    """The :class:`Results` in ``out/results.json`` (profiles as arrays; no fields)."""
    path = Path(out)
    path = path / "results.json" if path.is_dir() else path
    try:
        return Results.from_dict(io.read_json(path))
    except FileNotFoundError:
        raise ParameterError(f"{path} does not exist: no results to read") from None
    except (ValueError, KeyError, TypeError) as err:
        raise ParameterError(f"{path} is not a results file of ngincompat ({err})") from None
