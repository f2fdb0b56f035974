"""Progress of long work: which case, which stage, which load step, and every cut step.

On a terminal a stage that marches in load or time shows a named bar (tqdm) and the other
stages a line each; when the output is not a terminal (a log file, a pipe, a batch system)
every event is one plain line, flushed at once, so a log shows where a run is. Step cuts are
reported as they happen in both cases. ``Progress(quiet=True)`` reports nothing.

Library code reports through a :class:`Progress` it is handed (never ``print``); the command
line makes one on standard error.

A marching stage reads "[folding] buckling (stage 3 of 5): t = 61.25/75 day (3 Newton
iterations)": the stage's place in the case's :meth:`Progress.plan` (when the plan has more
than one stage), times to four significant digits, and the unit of the marching parameter
(none for the load fraction of prescribed growth, which runs from 0 to 1).

A case that writes nothing for :data:`STILL` seconds (the meshing or a Newton step of a large
problem) says that it goes on: "[folding] still computing (60 s since: meshing ...)".
"""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from typing import TextIO

from tqdm.auto import tqdm

#: Seconds without a line after which a case says that it is still computing: a silent minute
#: is too long for a user to tell a run from a hang (meshing a large body, or the first step
#: on a fine mesh, can take minutes without a word).
STILL = 60.0


class Progress:
    """Reports cases, stages and steps to a text stream.

    Parameters
    ----------
    quiet : bool
        Report nothing.
    stream : text stream, optional
        Where to write (default: standard error at the time of writing).
    bars : bool, optional
        Draw tqdm bars for marching stages; default: when ``stream`` is a terminal.
    """

    def __init__(self, quiet: bool = False, stream: TextIO | None = None,
                 bars: bool | None = None):
        self.quiet = quiet
        self._stream = stream
        self._bars = bars
        self.case_name = ""
        self._plan: list[str] = []
        self._outcome: str | None = None
        self._lock = threading.Lock()
        self._written, self._last = time.monotonic(), ""

    @property
    def stream(self) -> TextIO:
        return self._stream if self._stream is not None else sys.stderr

    @property
    def bars(self) -> bool:
        if self._bars is not None:
            return self._bars
        isatty = getattr(self.stream, "isatty", None)
        return bool(isatty and isatty())

    def line(self, message: str) -> None:
        """One plain line, prefixed with the current case."""
        if self.quiet:
            return
        self._write(message)
        self._last = message

    def _write(self, message: str) -> None:
        prefix = f"[{self.case_name}] " if self.case_name else ""
        text = f"{prefix}{message}"
        with self._lock:
            if self.bars:
                tqdm.write(text, file=self.stream)
            else:
                self.stream.write(text + "\n")
                self.stream.flush()
            self._written = time.monotonic()

    def _still(self, stop: threading.Event) -> None:
        """Until ``stop``: after :data:`STILL` seconds without a line, one saying so."""
        while not stop.wait(min(1.0, STILL / 4)):
            quiet = time.monotonic() - self._written
            if quiet >= STILL:
                self._write(f"still computing ({quiet:.0f} s since: {self._last})")

    @contextlib.contextmanager
    def case(self, name: str) -> Iterator[Progress]:
        """Everything reported inside belongs to the case ``name``."""
        outer, self.case_name = self.case_name, name
        outer_plan, self._plan = self._plan, []
        outer_outcome, self._outcome = self._outcome, None
        start = time.perf_counter()
        self.line("started")
        stop = threading.Event()
        if not self.quiet and not outer:        # one watch, for the outermost case
            threading.Thread(target=self._still, args=(stop,), name="progress-still",
                             daemon=True).start()
        try:
            yield self
        except BaseException:
            self._outcome = self._outcome or "stopped"
            raise
        finally:
            stop.set()
            seconds = time.perf_counter() - start
            self.line(f"finished in {seconds:.1f} s" if self._outcome in (None, "done")
                      else f"{self._outcome} after {seconds:.1f} s")
            self.case_name, self._plan, self._outcome = outer, outer_plan, outer_outcome

    def outcome(self, status: str) -> None:
        """How the current case ended ("done", "not converged", "interrupted"), for its last
        line: "finished in 4.4 s" only for a case that did."""
        self._outcome = status

    def plan(self, stages: Iterable[str]) -> None:
        """The names of the current case's stages, in order, so that each is reported as
        "stage i of n" (a case may plan again when it learns that it skips some)."""
        self._plan = list(stages)

    def stage_label(self, stage: str) -> str:
        """``stage`` with its place in the plan, "buckling (stage 3 of 5)"; the bare name
        when it is not planned or is the only stage."""
        if stage in self._plan and len(self._plan) > 1:
            return f"{stage} (stage {self._plan.index(stage) + 1} of {len(self._plan)})"
        return stage

    @contextlib.contextmanager
    def phase(self, name: str) -> Iterator[None]:
        """A stage without steps (meshing, projection, output): one line when it starts."""
        self.line(f"{name} ...")
        yield

    def march(self, stage: str, t_start: float, t_end: float, unit: str = "") -> StageProgress:
        """A stage that marches a load or time parameter from ``t_start`` to ``t_end``."""
        return StageProgress(self, stage, t_start, t_end, unit)


class StageProgress:
    """Progress of one marching stage; made by :meth:`Progress.march`."""

    def __init__(self, progress: Progress, stage: str, t_start: float, t_end: float,
                 unit: str):
        self.progress, self.stage, self.unit = progress, stage, unit
        self.label = progress.stage_label(stage)
        self.t_end = t_end
        self._bar = None
        if not progress.quiet and progress.bars:
            case = f"{progress.case_name}: " if progress.case_name else ""
            self._bar = tqdm(total=t_end - t_start, desc=f"{case}{self.label}",
                             file=progress.stream, bar_format="{l_bar}{bar}| {postfix}",
                             leave=False)
        else:
            progress.line(f"{self.label}: from {t_start:.4g} to {t_end:.4g}{self._unit}")

    @property
    def _unit(self) -> str:
        return f" {self.unit}" if self.unit else ""

    def step(self, t: float, dt: float, iterations: int) -> None:
        """A converged step to ``t`` of size ``dt`` in ``iterations`` Newton iterations."""
        if self._bar is not None:
            self._bar.update(dt)
            self._bar.set_postfix_str(f"t={t:.4g}/{self.t_end:.4g}{self._unit}, "
                                      f"{iterations} Newton")
            self.progress._written = time.monotonic()      # the bar moved: not silent
        else:
            self.progress.line(f"{self.label}: t = {t:.4g}/{self.t_end:.4g}{self._unit} "
                               f"({iterations} Newton iterations)")

    def cut(self, t: float, dt: float, reason: str) -> None:
        """The step from ``t`` of size ``dt`` failed and is retried at half the size."""
        self.progress.line(f"{self.label}: step from t = {t:.4g}{self._unit} by {dt:.3g} "
                           f"failed ({reason}); retrying with {dt / 2:.3g}")

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


#: A Progress that reports nothing: the default of library functions.
SILENT = Progress(quiet=True)
