"""The time series of a time-dependent run: chosen fields frozen at increasing times.

A case keeps one :class:`Frames` and calls :meth:`Frames.take` wherever its state is one to
show (after a converged load or time step, a record of a march, the end of a stage); it
hands the frames to its :class:`~ngincompat.workflow.results.Results` (``results.frames =
list(frames)``), and :func:`ngincompat.workflow.output.write` writes one ``fields_NNN.vtu``
per frame and the collection ``fields.pvd`` that orders them by time (on a distributed mesh
every frame in parts and the collection ``fields_series.pvd``).

The times of a series only increase. A frame taken at a time at or before the last one's
replaces the frames from that time on: the state of a stage that started again from an
earlier one (a fallback path, a step retried) supersedes the states of the attempt that
was given up, so the series is always the path the run took.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any, Self

import ngsolve as ngs

from ngincompat.workflow import output

#: A frame's time is rounded to this many decimals: the sum of a stage's steps (ten of 0.1
#: make 0.9999999999999999) then falls on the time a later frame is taken at (1), which
#: replaces it.
TIME_DECIMALS = 12


@dataclass(eq=False)
class Frames:
    """Frozen copies of ``fields()`` (name -> CoefficientFunction or GridFunction on ``mesh``)
    at the times :meth:`take` is called, interpolated for the VTK file at ``order``
    (:func:`ngincompat.workflow.output.interpolated`: GridFunctions copied, other fields
    their element-wise interpolants). ``names`` keeps only those fields (all if None); a
    series that is not ``enabled`` (a run without VTK output) takes nothing."""

    mesh: Any
    order: int
    fields: Callable[[], dict]
    names: tuple[str, ...] | None = None
    enabled: bool = True
    taken: list[tuple[float, dict]] = field(default_factory=list)

    @classmethod
    def of(cls, scene: Any, mesh: ngs.Mesh, fields: Callable[[], dict],
           names: tuple[str, ...] | None = None) -> Self:
        """The series of a scene's run: enabled when its ``outputs`` ask for vtk, at the
        order of the VTK file (the displacement's, at most
        :data:`~ngincompat.workflow.output.VTK_ORDER`)."""
        return cls(mesh, min(scene.order, output.VTK_ORDER), fields, names,
                   "vtk" in scene.output_set())

    def take(self, t: float, fields: dict | None = None) -> None:
        """Freeze the fields of the current state (``fields`` if given, else ``fields()``) as
        the frame of time ``t``, replacing the frames at ``t`` and after."""
        if not self.enabled:
            return
        t = round(float(t), TIME_DECIMALS) + 0.0       # + 0.0: no -0.0
        chosen = self.fields() if fields is None else fields
        if self.names is not None:
            chosen = {k: chosen[k] for k in self.names if k in chosen}
        self.taken = [frame for frame in self.taken if frame[0] < t]
        self.taken.append((t, output.interpolated(chosen, self.mesh, self.order, copy=True)))

    def times(self) -> list[float]:
        return [t for t, _ in self.taken]

    def __iter__(self) -> Iterator[tuple[float, dict]]:
        return iter(self.taken)

    def __len__(self) -> int:
        return len(self.taken)
