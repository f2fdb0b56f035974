"""Distributed runs on NGSolve's MPI support: ``mpiexec -n N ngincompat run SCENE ...``.

Launched by an MPI launcher with more than one rank, rank 0 builds the mesh, partitions it
with METIS into ``N - 1`` parts and sends them to the other ranks (rank 0 keeps no elements);
every rank then assembles its part. NGSolve's ``Integrate``, ``InnerProduct`` and ``Norm`` are
global over the ranks; what is rank-local (``BilinearForm.Energy``, maxima over elements,
point evaluation, element and dof counts) is reduced here. Files are written by rank 0, except
the VTK output, which every rank writes its part of (a ``.pvd`` collection).

Serial runs (no launcher, or one rank) never import mpi4py: everything here is then the
identity. mpi4py and an MPI come from the ``[mpi]`` extra (``pip install ngincompat[mpi]``:
mpi4py and the mpich wheel, whose ``mpiexec`` launches the ranks).
"""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import sys
import traceback
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, SupportsFloat, TypeVar

import numpy as np

if TYPE_CHECKING:     # NGSolve is imported where a mesh is made
    import ngsolve as ngs

#: What :func:`on_root` returns.
T = TypeVar("T")

#: Environment variables by which MPI launchers (MPICH's Hydra, Open MPI, Slurm) announce
#: the number of ranks of the job.
_SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "PMIX_SIZE")


def launcher() -> str | None:
    """The ``mpiexec`` that launches this Python's ranks: the one beside the interpreter (the
    mpich wheel's, in the same environment), else the first on PATH; None without one."""
    beside = Path(sys.executable).parent / "mpiexec"
    return str(beside) if beside.exists() else shutil.which("mpiexec")


@functools.cache
def world() -> Any:
    """The MPI world communicator (mpi4py) of a run launched with more than one rank, else
    None.

    Raises
    ------
    ImportError
        Launched with several ranks but mpi4py is not installed (``pip install .[mpi]``).
    """
    sizes = [int(os.environ[v]) for v in _SIZE_VARIABLES if os.environ.get(v, "").isdigit()]
    if not sizes or max(sizes) <= 1:
        return None
    try:
        from mpi4py import MPI
    except ImportError as err:
        raise ImportError("this run was launched on several MPI ranks but mpi4py is not "
                          "installed: pip install 'ngincompat[mpi]'") from err
    comm = MPI.COMM_WORLD
    return comm if comm.size > 1 else None


def is_root() -> bool:
    """True on rank 0 and in serial runs: the rank that writes files and prints."""
    comm = world()
    return comm is None or comm.rank == 0


def distributed(mesh: ngs.Mesh) -> bool:
    """Whether ``mesh`` (an ngsolve.Mesh) is one part of a distributed mesh."""
    return mesh.comm.size > 1


def distribute(build: Callable[[], ngs.Mesh]) -> ngs.Mesh:
    """The mesh of ``build()``, distributed over the ranks if this is an MPI run.

    Parameters
    ----------
    build : callable
        Returns an ngsolve.Mesh; called on rank 0 only (and in serial runs).

    Returns
    -------
    ngsolve.Mesh
        The whole mesh (serial), or this rank's part (rank 0: no elements).

    Notes
    -----
    A distributed run uses one NGSolve thread per rank: with a rank per core, more threads
    oversubscribe the cores, and BDDC's many short parallel loops then cost a hundred times
    their work on a loaded machine (``docs/measurements/solver-costs.md``, the cube's tangent).
    """
    comm = world()
    if comm is None:
        return build()
    import netgen.meshing
    import ngsolve as ngs

    from ngincompat import config

    config.configure(threads=1)    # a rank per core; threads on top oversubscribe the cores
    if comm.rank == 0:
        ngmesh = build().ngmesh
        ngmesh.Distribute(comm)
    else:
        ngmesh = netgen.meshing.Mesh.Receive(comm)
    return ngs.Mesh(ngmesh)


def distribute_geometry(geometry: Any, maxh: float, curve_order: int = 1) -> ngs.Mesh:
    """The tetrahedral mesh of an OCC ``geometry`` (built on every rank) of size ``maxh``,
    curved to ``curve_order``, distributed over the ranks if this is an MPI run (as
    :func:`distribute`).

    A curved mesh cannot be distributed (the ranks crash): rank 0 distributes the straight
    mesh, and every rank curves its part with the geometry, which the received parts lack.
    """
    import netgen.meshing
    import ngsolve as ngs

    comm = world()
    if comm is None:
        ngmesh = geometry.GenerateMesh(netgen.meshing.MeshingParameters(maxh=maxh))
    else:
        from ngincompat import config

        config.configure(threads=1)    # as in distribute
        if comm.rank == 0:
            ngmesh = geometry.GenerateMesh(netgen.meshing.MeshingParameters(maxh=maxh))
            ngmesh.Distribute(comm)
        else:
            ngmesh = netgen.meshing.Mesh.Receive(comm)
            ngmesh.SetGeometry(geometry)
    mesh = ngs.Mesh(ngmesh)
    if curve_order > 1:
        mesh.Curve(curve_order)
    return mesh


def total(mesh: ngs.Mesh, value: SupportsFloat) -> float:
    """The sum over the ranks of a rank-local number (e.g. ``BilinearForm.Energy``)."""
    return mesh.comm.Sum(float(value)) if distributed(mesh) else float(value)


def maximum(mesh: ngs.Mesh, value: float) -> float:
    """The largest over the ranks of a rank-local number (-inf on a rank without elements)."""
    return mesh.comm.Max(float(value)) if distributed(mesh) else float(value)


def first_found(mesh: ngs.Mesh, values: np.ndarray) -> np.ndarray:
    """Point values that each rank found for its own elements (NaN where it found none),
    made the values of the lowest rank that found each point, on every rank."""
    if not distributed(mesh):
        return values
    comm = mesh.comm.mpi4py
    gathered = comm.allgather(np.asarray(values, dtype=float))
    out = np.full_like(gathered[0], np.nan)
    for part in reversed(gathered):
        found = ~np.isnan(part)
        out[found] = part[found]
    return out


def gather_rows(mesh: ngs.Mesh, rows: np.ndarray) -> np.ndarray:
    """The rows of every rank stacked (rank order), on every rank; ``rows`` in serial."""
    if not distributed(mesh):
        return rows
    return np.concatenate(mesh.comm.mpi4py.allgather(np.asarray(rows)), axis=0)


def per_rank(value: SupportsFloat) -> list[float]:
    """A rank-local number of every rank, in rank order, on every rank (collective: every
    rank calls it); ``[value]`` in a serial run."""
    comm = world()
    if comm is None:
        return [float(value)]
    return [float(v) for v in comm.allgather(float(value))]


@contextlib.contextmanager
def alone_ends_the_job(collective: tuple[type[BaseException], ...]) -> Iterator[None]:
    """In a distributed run, an exception raised inside this context that is not one of the
    ``collective`` kinds (those every rank raises together: a residual or a check reduced
    over the ranks) ends the whole job (``MPI_Abort``, exit code 1) after its traceback is
    printed: raised on some ranks alone, it would leave the others waiting for them in their
    next collective operation, for ever (seen: a worker's KeyError in the transport's set-up
    while rank 0, which holds no elements, went on into an integral over the ranks). In a
    serial run the exception passes."""
    try:
        yield
    except collective:
        raise
    except BaseException:
        comm = world()
        if comm is None:
            raise
        traceback.print_exc()
        sys.stderr.flush()
        comm.Abort(1)
        raise                       # not reached: Abort ends the process


def on_root(function: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """``function(*args, **kwargs)`` evaluated on rank 0, its result (or exception, raised on
    every rank) broadcast to all: for file-system checks that must agree across the ranks."""
    comm = world()
    if comm is None:
        return function(*args, **kwargs)
    outcome: tuple[bool, Any] | None = None
    if comm.rank == 0:
        try:
            outcome = (True, function(*args, **kwargs))
        except Exception as err:            # re-raised below on every rank
            outcome = (False, err)
    ok, value = comm.bcast(outcome, root=0)
    if not ok:
        raise value
    return value


def counts(mesh: ngs.Mesh) -> tuple[int, int]:
    """Numbers of elements and vertices of the whole mesh (not only this rank's part)."""
    if not distributed(mesh):
        return mesh.ne, mesh.nv
    import ngsolve as ngs

    return int(total(mesh, mesh.ne)), ngs.H1(mesh, order=1).ndofglobal
