"""ngincompat: finite volume growth of soft tissue and the geometric incompatibility it leaves.

F = Fe Fg; Curl Fg, G = (1/Jg) Fg Curl Fg and b = G^T n (Lee et al., JMPS 146 (2021) 104177),
with the residual stress that growth causes, on NGSolve/Netgen.

Importing the package raises NGSolve's local heap to 200 MB: high-order (p >= 5) element
matrices of matrix-valued spaces overflow the default heap ("Local Heap overflow"); and it
runs NGSolve's task manager on :data:`THREADS` threads.
"""

import os as _os

import ngsolve as _ngs

__version__ = "0.1.0"

#: NGSolve threads: ``NGS_NUM_THREADS`` if set, else one. The task manager's threads wait
#: actively for each other at every parallel loop, so on cores that other jobs share they
#: cost more than they give: on the 2 shared cores at load 9-10 the disc's Newton solve took
#: 17-19 s on two threads and 6-7 s on one (alternating runs).
THREADS = int(_os.environ.get("NGS_NUM_THREADS") or 1)

_ngs.SetHeapSize(200 * 1000 * 1000)
_ngs.SetNumThreads(THREADS)
