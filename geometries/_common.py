"""Shared helpers of the geometry builders."""

import logging
import signal
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
    thread's end (a thread left meshing crashed the interpreter's exit), clears the flag and
    raises the interrupt. The thread blocks SIGINT and SIGTERM, which the kernel would
    otherwise hand to any thread (one that reached the mesher's thread aborted the process
    at its exit).

    Only where :data:`threaded` is set (by the command line's process, which ends at once
    after a stopped meshing: :func:`ngincompat.cli.run`); elsewhere ``meshing()`` is called
    directly and an interrupt waits for the mesh. A process that goes on after a stopped
    meshing can crash in Netgen's teardown of it: a sweep's worker did, a broken pool."""
    if not threaded:
        return meshing()
    from netgen.libngpy import _meshing

    outcome = {}

    def run():
        if hasattr(signal, "pthread_sigmask"):   # the signals are the waiting thread's
            signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        try:
            outcome["mesh"] = meshing()
        except BaseException as err:     # handed to the waiting thread
            outcome["error"] = err

    _meshing._SetTerminate(False)       # an earlier interrupt's flag may still be set
    thread = threading.Thread(target=run, name="netgen-meshing", daemon=True)
    thread.start()
    try:
        while thread.is_alive():
            thread.join(WAIT)
    except BaseException:
        started = time.perf_counter()
        _meshing._SetTerminate(True)
        while thread.is_alive():        # a second Ctrl-C leaves the flag set: it stops
            thread.join(WAIT)
        _meshing._SetTerminate(False)
        stopped.append(time.perf_counter() - started)
        log.info("Netgen's mesher stopped %.2f s after the interrupt", stopped[-1])
        raise
    if "error" in outcome:
        raise outcome["error"]
    return outcome["mesh"]


#: Seconds between the checks of an interrupt while Netgen meshes.
WAIT = 0.1
#: Whether :func:`interruptible` meshes in a thread of its own (see there).
threaded = False
#: The seconds each stopped meshing took to stop, in this process. After one, the
#: interpreter's exit can crash in Netgen's teardown (at random, about every other time: a
#: segmentation fault after the process has said all it had to say), which the command line
#: avoids by ending at once (:func:`ngincompat.cli.run`).
stopped = []
