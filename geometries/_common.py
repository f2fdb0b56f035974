"""Shared helpers of the geometry builders."""

import contextlib
import ctypes
import logging
import os
import signal
import sys
import threading
import time

import ngsolve as ngs
from netgen.meshing import MeshingParameters
from netgen.occ import OCCGeometry

from ngincompat.errors import require

log = logging.getLogger(__name__)


def check_mesh_args(maxh, curve_order, scale):
    """Validate the arguments every builder has."""
    require(maxh > 0, "maxh", maxh, "> 0")
    require(maxh <= 10 * scale, "maxh", maxh, f"<= {10 * scale:g} (10 x the body's size)")
    require(isinstance(curve_order, int) and 1 <= curve_order <= 8, "curve_order", curve_order,
            "an integer in [1, 8]")


def mesh_shape(shape, maxh, curve_order, refine_at=()):
    """Mesh an OCC shape with tetrahedra and curve it to ``curve_order``.

    ``refine_at`` lists points (x, y, z, h) around which the element size is at most h.
    """
    params = MeshingParameters(maxh=maxh)
    for x, y, z, h in refine_at:
        params.RestrictH(x, y, z, h)
    mesh = ngs.Mesh(interruptible(lambda: OCCGeometry(shape).GenerateMesh(params)))
    if curve_order > 1:
        mesh.Curve(curve_order)
    return mesh


def interruptible(meshing):
    """``meshing()`` (a call into Netgen's mesher) run in a thread of its own and awaited in
    steps of :data:`WAIT` seconds, so that Ctrl-C and SIGTERM, which Python handles on the
    main thread only between its own steps, stop it at once: Netgen releases the GIL while
    it meshes, and a run waiting on it directly took Ctrl-C only when the mesh was done (a
    1000 mm cylinder meshed for 8 minutes with Ctrl-C ignored). Interrupted, the wait sets
    Netgen's terminate flag (the mesher's own stop, which it checks in its loops), awaits the
    thread's end, clears the flag and raises the interrupt. The end is a flag the thread
    sets, polled with ``time.sleep``: not ``Thread.join``, which, interrupted by Ctrl-C,
    marks the thread ended while it still runs (CPython's ``_wait_for_tstate_lock`` up to
    3.12), and a mesher left running with the flag cleared crashed the interpreter's exit at
    random (a segmentation fault after the process had said all it had to say); nor
    ``Event.wait``, which, interrupted, can release its condition's lock twice ("release
    unlocked lock"). The thread blocks SIGINT and SIGTERM, which the kernel would otherwise
    hand to any thread (one that reached the mesher's thread aborted the process at its
    exit).

    So in every process: the command line, a sweep's or the paper job's worker (where the
    pool's Ctrl-C or SIGTERM reaches the case), a script, a notebook's kernel (whose
    "interrupt" is SIGINT), each of which can go on meshing after the stop. Off the main
    thread (a Dask worker's task) no signal arrives, and the mesh is awaited."""
    from netgen.libngpy import _meshing

    outcome = {}
    ended = threading.Event()

    def run():
        if hasattr(signal, "pthread_sigmask"):   # the signals are the waiting thread's
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        try:
            outcome["mesh"] = meshing()
        except BaseException as err:     # handed to the waiting thread
            outcome["error"] = err
        finally:
            ended.set()

    _meshing._SetTerminate(False)       # an earlier interrupt's flag may still be set
    threading.Thread(target=run, name="netgen-meshing", daemon=True).start()
    try:
        while not ended.is_set():
            time.sleep(WAIT)
    except BaseException:
        started = time.perf_counter()
        with _quiet_stdout():           # the stopped mesher's complaints of unmeshed faces
            _meshing._SetTerminate(True)
            while not ended.is_set():       # a second Ctrl-C leaves the flag set: it stops
                time.sleep(WAIT)
        _meshing._SetTerminate(False)
        log.info("Netgen's mesher stopped %.2f s after the interrupt",
                 time.perf_counter() - started)
        raise
    if "error" in outcome:
        raise outcome["error"]
    return outcome["mesh"]


@contextlib.contextmanager
def _quiet_stdout():
    """The process's standard output (file descriptor 1, where Netgen prints) sent to the
    null device in the block, C's buffers flushed at both ends."""
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    libc.fflush(None)
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        yield
    finally:
        libc.fflush(None)
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


#: Seconds between the checks of an interrupt while Netgen meshes.
WAIT = 0.1
