"""ngincompat: finite volume growth of soft tissue and the geometric incompatibility it leaves.

F = Fe Fg; Curl Fg, G = (1/Jg) Fg Curl Fg and b = G^T n (Lee et al., JMPS 146 (2021) 104177),
with the residual stress that growth causes, on NGSolve/Netgen.

Importing the package raises NGSolve's local heap to 200 MB: high-order (p >= 5) element
matrices of matrix-valued spaces overflow the default heap ("Local Heap overflow").
"""

import ngsolve as _ngs

__version__ = "0.1.0"

_ngs.SetHeapSize(200 * 1000 * 1000)
