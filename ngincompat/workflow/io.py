"""Results on disk: results.json with provenance, VTK fields, all written atomically.

Every file is first written under a temporary name in the target folder and then renamed over
the final name (``os.replace`` is atomic on POSIX), so an interrupted run never leaves a
half-written result behind.
"""

from __future__ import annotations

import datetime
import errno
import functools
import json
import math
import os
import platform
import shlex
import subprocess
import sys
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ngincompat import config
from ngincompat.atomic import atomic_path

if TYPE_CHECKING:     # NGSolve is imported where VTK is written
    import ngsolve as ngs

#: The folder that holds the package ``ngincompat``: a git checkout's top level when the
#: package runs from one (an editable install, PYTHONPATH), site-packages otherwise.
SOURCE_ROOT = Path(__file__).resolve().parents[2]


def versions() -> dict[str, str]:
    """Versions of the packages a result depends on."""
    import netgen
    import ngsolve
    import scipy

    return {
        "ngincompat": config.VERSION,
        "ngsolve": ngsolve.__version__,
        "netgen": getattr(netgen, "__version__", ngsolve.__version__),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "python": platform.python_version(),
    }


def _git(*args: str, cwd: Path) -> str | None:
    """The output of ``git args`` in ``cwd`` (stripped), or None if git fails or is absent.
    GIT_DIR and GIT_WORK_TREE of the caller's environment are not passed on: the question is
    about the checkout at ``cwd``."""
    env = {k: v for k, v in os.environ.items() if k not in ("GIT_DIR", "GIT_WORK_TREE")}
    try:
        done = subprocess.run(["git", *args], cwd=cwd, env=env, capture_output=True,
                              text=True, timeout=20, check=True)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip()


@functools.lru_cache(maxsize=None)
def git_state(root: str | os.PathLike = SOURCE_ROOT) -> dict[str, Any] | None:
    """``{"commit": sha, "dirty": bool}`` of the git checkout whose top level is ``root``,
    or None when ``root`` is not one (an installed package: a git repository around
    site-packages is not the package's) or git is not installed.

    ``dirty``: tracked files differ from the commit (untracked files are left out: output
    folders and notes do not change what ran). Asked once per process."""
    root = Path(root).resolve()
    top = _git("rev-parse", "--show-toplevel", cwd=root)
    if top is None or Path(top).resolve() != root:
        return None
    commit = _git("rev-parse", "HEAD", cwd=root)
    status = _git("status", "--porcelain", "--untracked-files=no", cwd=root)
    if not commit or status is None:
        return None
    return {"commit": commit, "dirty": bool(status)}


def run_record() -> dict[str, Any]:
    """Where, when and how a result was produced: the date (ISO 8601, UTC), the host and
    platform, the NGSolve settings in force (:func:`ngincompat.config.settings`: threads,
    heap), the full command line (the interpreter's, ``sys.orig_argv``, as one shell line)
    and its working folder, the Python executable, and ``git`` (:func:`git_state`) when the
    package runs from a checkout."""
    record = {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "host": platform.node(),
        "platform": platform.platform(),
        **config.settings(),
        "command": shlex.join(getattr(sys, "orig_argv", sys.argv)),
        "cwd": os.getcwd(),
        "executable": sys.executable,
    }
    git = git_state()
    if git is not None:
        record["git"] = git
    return record


def jsonable(value: Any) -> Any:
    """``value`` with arrays as lists, numpy scalars as Python ones, NaN and inf as None."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, Path):
        return str(value)
    return value


def write_json(path: str | os.PathLike, data: Any) -> Path:
    """Write ``data`` as JSON atomically; NaN and inf become null, arrays become lists."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(jsonable(data), indent=2, sort_keys=False) + "\n")
    return Path(path)


def read_json(path: str | os.PathLike) -> Any:
    return json.loads(Path(path).read_text())


def write_vtk(path: str | os.PathLike, mesh: ngs.Mesh,
              fields: Mapping[str, ngs.CoefficientFunction], subdivision: int = 1) -> Path:
    """Write CoefficientFunctions as a VTK unstructured grid (``path`` ends in ``.vtu``).

    Parameters
    ----------
    fields : dict
        name -> CoefficientFunction (scalar, 3-vector or 3x3 tensor).
    subdivision : int
        Refinements of each element for the output (high-order fields need some).
    """
    import ngsolve as ngs

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    stem = path.with_suffix("")
    tmp_stem = stem.with_name(f".{stem.name}.tmp{os.getpid()}")
    vtk = ngs.VTKOutput(mesh, coefs=list(fields.values()), names=list(fields.keys()),
                        filename=str(tmp_stem), subdivision=subdivision, legacy=False)
    written = tmp_stem.with_name(tmp_stem.name + ".vtu")
    try:
        written = Path(vtk.Do())
        if written.suffix != ".vtu":
            written = written.with_name(written.name + ".vtu")
        complete(written, b"</VTKFile>", path)
        os.replace(written, path)
    except BaseException:       # a full disk, Ctrl-C: no temporary file is left behind
        written.unlink(missing_ok=True)
        raise
    return path


def complete(path: str | os.PathLike, ending: bytes,
             final: str | os.PathLike | None = None) -> None:
    """Raise an OSError unless the file ``path`` ends in ``ending`` (white space aside); the
    message names ``final``, the name the file is written for (default ``path``).

    NGSolve's and Netgen's writers do not report a failed write (a full disk), so a file is
    checked before it is renamed to its final name: a truncated file is never committed."""
    path = Path(path)
    try:
        with open(path, "rb") as f:
            size = f.seek(0, os.SEEK_END)
            f.seek(max(0, size - 256))
            tail = f.read().rstrip()
    except FileNotFoundError:
        tail = b""
    if not tail.endswith(ending):
        raise incomplete(final or path)


def incomplete(final: str | os.PathLike) -> OSError:
    """The error for a file its writer left incomplete (as on a full disk), naming the file
    by its final name."""
    final = Path(final)
    return OSError(errno.ENOSPC, f"{final.name} was not written completely (is the disk "
                                 "full?)", str(final))


def write_pvd(path: str | os.PathLike,
              datasets: Iterable[tuple[float, str] | tuple[float, str, int]]) -> Path:
    """Write a ParaView collection (``path`` ends in ``.pvd``) atomically: a time series of
    VTK files given as (time, file name relative to the collection's folder), or as (time,
    file name, part) where a time has one file per part of a distributed mesh."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>",
             *(f'    <DataSet timestep="{float(t)!r}" group="" part="{part}" file="{name}"/>'
               for t, name, part in ((*d, 0) if len(d) == 2 else d for d in datasets)),
             "  </Collection>", "</VTKFile>"]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")
    return Path(path)


def write_vtk_parallel(stem: str | os.PathLike, mesh: ngs.Mesh,
                       fields: Mapping[str, ngs.CoefficientFunction],
                       subdivision: int = 1) -> list[str]:
    """Write CoefficientFunctions on a distributed mesh: every rank writes its part; the
    collection ``stem.pvd`` names the parts. Collective: call on every rank.

    Returns
    -------
    list of str
        The files written, relative to the folder of ``stem`` (on every rank).
    """
    import ngsolve as ngs

    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    vtk = ngs.VTKOutput(mesh, coefs=list(fields.values()), names=list(fields.keys()),
                        filename=str(stem), subdivision=subdivision, legacy=False)
    vtk.Do()
    comm = mesh.comm.mpi4py
    comm.Barrier()
    names = None
    if comm.rank == 0:
        names = sorted(p.name for p in stem.parent.glob(f"{stem.name}*")
                       if p.suffix in (".pvd", ".vtu"))
    return comm.bcast(names, root=0)


def provenance() -> dict[str, Any]:
    """What produced a result: package versions, the command line and the
    :func:`run_record` (date, host, threads, git commit)."""
    return {"versions": versions(), "argv": list(sys.argv), "provenance": run_record()}
