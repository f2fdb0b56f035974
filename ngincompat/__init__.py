"""ngincompat: finite volume growth of soft tissue and the geometric incompatibility it leaves.

F = Fe Fg; Curl Fg, G = (1/Jg) Fg Curl Fg and b = G^T n (Lee et al., JMPS 146 (2021) 104177),
with the residual stress that growth causes, on NGSolve/Netgen.

The public API is flat::

    from ngincompat import CubeScene, Results, configure
    configure(threads=2)
    results = CubeScene(order=2).run()

The layers underneath, each a subpackage that imports only the ones below it (the contracts in
``pyproject.toml``, checked by ``lint-imports``):

=========================  ================================================================
``cli``                    the command line (argparse only there)
``studies``                drivers that run scenes many times: paper, benchmarks, sweeps
``scenes``                 one module per scene of the paper: typed parameters and ``build()``
``workflow``               pipeline, :class:`Results`, output folder, input files, plots
``fem`` | ``references``   discretisation and solvers | independent solutions for checks
``mechanics``              kinematics, growth tensors and laws, materials, direction fields
``incompatibility``        Curl Fg, G, Burgers vectors, curvature of the growth metric
base modules               errors, the names of scenes, axons and footprints, typed
                           parameters, config, atomic files, MPI, progress, sampling points
=========================  ================================================================

Importing the package changes nothing in NGSolve; :func:`configure` sets threads and heap.
The names below are loaded on first use, so ``import ngincompat`` stays light and the
``geometries`` package (which imports :mod:`ngincompat.errors`) never meets a half-imported
``ngincompat``.
"""

from ngincompat.config import VERSION as __version__
from ngincompat.config import configure
from ngincompat.errors import ConvergenceError, NgincompatError, ParameterError

_SCENES = ("AtrophyScene", "CubeScene", "CustomScene", "CylinderScene", "DiscScene",
           "FoldingScene", "HemisphereScene", "SkinExpansionScene", "SCENES", "get_scene")

__all__ = ["ConvergenceError", "NgincompatError", "ParameterError", "Results", "__version__",
           "configure", *_SCENES]


def __getattr__(name):
    if name in _SCENES:
        from ngincompat import scenes
        return getattr(scenes, name)
    if name == "Results":
        from ngincompat.workflow.results import Results
        return Results
    raise AttributeError(f"module 'ngincompat' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
