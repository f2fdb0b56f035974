"""Where a solve's time goes: the seconds spent in each kind of work.

The solver and the terms wrap their costly calls in :func:`part` (``with part("assembly"):
...``); :func:`totals` is the running sum per kind since the process started, and a stage's
share is the difference of two totals (:func:`since`), which
:func:`~ngincompat.workflow.pipeline.solve_stages` keeps in each stage's
:class:`~ngincompat.fem.solver.SolverHistory` (``work``). The kinds are exclusive: a part
called inside another counts for the inner one only, so the kinds of a stage add up to at
most its wall time; the rest is Python between the calls and what no part names.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

#: The kinds of work, with what they cover.
KINDS = {
    "assembly": "the tangent's assembly (AssembleLinearization; with it the setup of a BDDC "
                "preconditioner registered with the form)",
    "factorisation": "the tangent's (or its preconditioner's) sparse factorisation",
    "linear solve": "the Newton direction from the factorised tangent (GMRES iterations, "
                    "back substitutions, static condensation)",
    "residual": "the residual (Apply)",
    "energy": "the energies the line search and the relaxations test",
    "contact search": "the pairs of a self-contact boundary (ContactBoundary.Update)",
    "eigenpairs": "the smallest eigenpairs of the tangent (buckling), with its assembly",
}

_totals = dict.fromkeys(KINDS, 0.0)
_running: list[list] = []      # [kind, start, seconds of inner parts] of each open part


@contextmanager
def part(kind: str) -> Iterator[None]:
    """Count the block's wall time, less that of the parts inside it, as ``kind``."""
    if kind not in KINDS:
        raise ValueError(f"kind of work {kind!r}: allowed {', '.join(KINDS)}")
    entry: list = [kind, time.perf_counter(), 0.0]
    _running.append(entry)
    try:
        yield
    finally:
        _running.pop()
        elapsed = time.perf_counter() - entry[1]
        _totals[kind] += elapsed - entry[2]
        if _running:
            _running[-1][2] += elapsed


def totals() -> dict[str, float]:
    """Seconds per kind of work since the process started (a copy)."""
    return dict(_totals)


def since(before: dict[str, float]) -> dict[str, float]:
    """Seconds per kind of work since ``before`` (an earlier :func:`totals`)."""
    return {kind: seconds - before.get(kind, 0.0) for kind, seconds in _totals.items()}
