"""What the cases of all scenes share (the case of :mod:`ngincompat.workflow.pipeline`).

A scene builds a case; the case solves its stages into a
:class:`~ngincompat.workflow.pipeline.Solution` and measures the result. A run that stops
before its measurement (interrupted, or a stage not converged) is recorded by
:meth:`SceneCase.interrupted`, written once here: the scene's parameters, the solver
histories, the unknowns, the metrics the case noted on its way, the frames it took, and what
the case keeps beside them (:meth:`SceneCase.keep`).
"""

import abc
from collections.abc import Iterable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

import ngsolve as ngs

from ngincompat.progress import Progress
from ngincompat.scenes.base import Scene
from ngincompat.workflow.pipeline import Solution
from ngincompat.workflow.results import Results


class SceneCase(abc.ABC):
    """The base of every scene's case (a dataclass with ``scene`` and ``mesh``).

    Attributes a case may override
    ------------------------------
    noted : mapping
        Metrics measured while solving (an onset, the state at the end of a hold), which a
        stopped run reports too; none by default.
    frames : sequence
        The frames of the time series taken so far; none by default.
    """

    scene: Scene
    mesh: ngs.Mesh
    noted: Mapping[str, float] = MappingProxyType({})
    frames: Iterable[tuple[float, dict[str, Any]]] = ()

    @abc.abstractmethod
    def solve(self, solution: Solution, progress: Progress,
              workdir: Path | None = None) -> None:
        """Walk the stages into ``solution``."""

    @abc.abstractmethod
    def measure(self, solution: Solution, progress: Progress) -> Results:
        """Fields, metrics, profiles and figures of the solved state."""

    def ndof(self, solution: Solution) -> int | None:
        """The unknowns of the solved problem: by default those of ``solution.state`` (None
        before there is one)."""
        return None if solution.state is None else solution.state.ndof

    def keep(self, results: Results) -> None:  # noqa: B027 - a hook: most cases keep nothing more
        """Add to the record of a stopped run what the case keeps beside its metrics and
        frames (profiles of a series, checkpoint files); nothing by default."""

    def interrupted(self, solution: Solution) -> Results:
        """The record of a run that stopped: parameters, histories, unknowns, the metrics
        noted so far, the frames and what :meth:`keep` adds."""
        results = self.scene.record(self.mesh, status=solution.status, error=solution.error,
                                    solver=dict(solution.histories))
        ndof = self.ndof(solution)
        if ndof is not None:
            results.mesh.ndof = ndof
        results.metrics = dict(self.noted)
        results.frames = list(self.frames)
        self.keep(results)
        return results
