"""Whether a run's results can be trusted: the accuracy indicators each scene names, with
their thresholds.

A run that passes every check of its solver can still be wrong: a mesh that does not resolve
a nearly incompressible response, a formulation that locks, a solve that took so many Newton
iterations per step that the problem is nearly singular. Each scene lists
:class:`Indicator` s over its own metrics (``Scene.indicators``) and may add warnings from its
settings (``Scene.trust``); every run gets the solver-effort check of :func:`solver_effort`.
A run past a threshold still writes its results, with one line per indicator in
``Results.warnings`` (results.json ``"warnings"``), each logged as a warning.
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ngincompat.workflow.results import Results

#: Newton iterations per converged load or time step, on average over a run, above which the
#: solve is flagged: well above what runs at the scenes' defaults take, well below a locking
#: formulation's (``docs/measurements/stability.md``, "Where the locking warning starts").
NEWTON_PER_STEP = 20


@dataclass(frozen=True)
class Indicator:
    """A metric that must stay at or below ``limit`` for the results to be trusted;
    ``meaning`` says what a larger value means and what to do."""

    metric: str
    limit: float
    meaning: str

    def check(self, metrics: Mapping[str, float]) -> str | None:
        """The warning line, or None when the metric is within its limit (or not reported)."""
        value = metrics.get(self.metric)
        if value is None or not math.isfinite(value) or value <= self.limit:
            return None
        return f"{self.metric} = {value:.3g} > {self.limit:g}: {self.meaning}"


def solver_effort(results: Results, limit: float = NEWTON_PER_STEP) -> str | None:
    """A warning when the run's converged steps took more than ``limit`` Newton iterations
    each on average (None otherwise)."""
    steps = [s for h in results.solver.values() for s in h.steps if s.converged]
    if not steps:
        return None
    mean = sum(s.iterations for s in steps) / len(steps)
    if mean <= limit:
        return None
    return (f"Newton iterations per step = {mean:.3g} > {limit}: the problem is nearly "
            "singular (locking, near-incompressibility or a steep gradient); refine, or use "
            "formulation=mixed where the scene has it")


def warnings(scene: Any, results: Results) -> list[str]:
    """Every warning of ``scene``'s indicators, its own checks and the solver effort."""
    found = [indicator.check(results.metrics) for indicator in scene.indicators]
    found += [*scene.trust(results), solver_effort(results)]
    return [w for w in found if w]
