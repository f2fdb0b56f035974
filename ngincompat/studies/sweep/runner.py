"""Running a sweep: its cases in local processes or on a Dask cluster, resumably.

Before anything runs, every case's scene is built from its parameters (:meth:`Case.build`): a
case whose value the scene rejects fails at once (a row with the error), the others go on.
Case ``i`` then runs ``scene.run(OUT/case_<i>_<hash>, overwrite=True, progress=...)`` (see
:func:`ngincompat.workflow.pipeline.run`): its folder name holds the case index (three digits or
more)
and a short hash of the scene and all its parameters. A case is done when its folder holds a
results.json (:func:`ngincompat.workflow.output.read`) with status "done" of the same scene and
parameters; done cases are never run again (a second run of a sweep, with or without
``resume``, runs the cases that are missing, failed or not converged). A folder that holds a
*different* sweep is refused unless ``resume`` is given, which then reuses the finished cases
they share.

Cases run in local processes ("spawn"; ``workers``, NGSolve threads per worker so that
workers x threads <= cores) or, with ``scheduler``, on an existing Dask cluster whose workers
see the same file system and can import ngincompat (give the workers one thread each: a case
uses NGSolve's task manager, ``threads`` NGSolve threads, default 1).

Each finished case appends one line (its row, JSON) to ``OUT/sweep.journal.jsonl``, a constant
cost per case (rewriting the whole table after each case was quadratic: 1,000 cases took
94 s of writing); the table (:mod:`.table`) is written atomically before the cases run and
once at the end, also when the sweep is interrupted, and the journal is then removed. After a
hard kill the journal holds the cases the table misses; the next run of the sweep finds them
done anyway (from their folders). A case that does not converge is a row "not converged" with
the metrics of its last converged state; one that raises is a row "failed" with the error,
its traceback in ``OUT/case_.../error.txt``. Interrupted (Ctrl-C), the sweep stops its workers
(a case not started does not start, a running one ends "interrupted" in its results.json) and
writes the table with every case, each row of the cases it ran taken from what the case's
folder holds: a complete results.json of the case is its row whatever the pool said (a case
can finish between the Ctrl-C and the pool's shutdown), a case without one is "interrupted".
"""

import dataclasses
import json
import os
import uuid
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from ngincompat.errors import ParameterError
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes.base import Scene
from ngincompat.studies.sweep.spec import Case, Sweep
from ngincompat.studies.sweep.table import (
    FIXED_COLUMNS,
    JOURNAL,
    RECORD,
    SweepTable,
    make_table,
    write_table,
)
from ngincompat.studies.workers import (
    LocalPool,
    error_message,
    failed,
    interrupted,
    outcome,
    run_case,
    run_side_by_side,
)
from ngincompat.workflow import io, output, tables
from ngincompat.workflow.results import DONE, INTERRUPTED, Results


def _record(scene: Scene, folder: Path) -> Results | None:
    """The :class:`~ngincompat.workflow.results.Results` in ``folder`` if it holds a complete
    results.json of ``scene`` (same name and parameters), whatever its status, else None."""
    try:
        results = output.read(folder)
    except ParameterError:
        return None
    same = (results.scene == scene.name
            and results.params == io.jsonable(scene.settings()))
    return results if same else None


def _finished(scene: Scene, folder: Path) -> Results | None:
    """The record in ``folder`` (:func:`_record`) if it is done, else None."""
    results = _record(scene, folder)
    return results if results is not None and results.status == DONE else None


def _settled(case: Case, scene: Scene, folder: Path,
             said: dict[str, Any] | None) -> dict[str, Any]:
    """The outcome of an interrupted sweep's ``case``: what its folder holds, whatever the
    pool ``said`` (None if nothing). A case can end and write its record between the Ctrl-C
    and the pool's shutdown (or be hit by the signal just after writing it); its folder, not
    the pool's view, is the one source of truth. A case whose folder holds no record of its
    own keeps what the pool said, or is "interrupted"."""
    results = _record(scene, folder)
    if results is None or results.status == INTERRUPTED:
        if said is not None and said["status"] != INTERRUPTED:
            return said
        return {"varied": case.varied, **interrupted(results)}
    return {"varied": case.varied, **outcome(results, None if results.status == DONE
                                              else results.error)}



# --------------------------------------------------------------------------- executors

class _Dask:
    """An existing Dask cluster, by the address of its scheduler (or a Client)."""

    def __init__(self, scheduler: Any, workers: int | None, threads: int | None,
                 progress: Progress) -> None:
        try:
            from dask import distributed
        except ImportError:
            raise ParameterError("--scheduler needs dask.distributed: pip install "
                                 "'dask[distributed]' (or ngincompat[dask])") from None
        self.distributed = distributed
        self.own = not isinstance(scheduler, distributed.Client)
        if self.own:
            try:
                self.client = distributed.Client(scheduler)
            except (OSError, ValueError) as err:
                raise ParameterError(f"--scheduler {scheduler}: cannot connect: {err}") from None
        else:
            self.client = scheduler
        self.threads = threads or 1
        self.window = workers or max(1, sum(self.client.nthreads().values()))
        progress.line(f"Dask cluster {self.client.scheduler.address}: up to {self.window} "
                      f"cases at a time, {self.threads} NGSolve threads each")
        self.futures: set[Any] = set()

    def submit(self, task: dict[str, Any]) -> Any:
        key = f"ngincompat-{Path(task['folder']).name}-{uuid.uuid4().hex[:8]}"
        future = self.client.submit(run_case, {**task, "threads": self.threads}, key=key,
                                    pure=False)
        self.futures.add(future)
        return future

    def wait(self, futures: Iterable[Any]) -> list[Any]:
        self.distributed.wait(list(futures), return_when="FIRST_COMPLETED")
        done = [f for f in futures if f.done()]
        self.futures.difference_update(done)
        return done

    def close(self, cancel: bool) -> None:
        if cancel and self.futures:
            self.client.cancel(list(self.futures))
        if self.own:
            self.client.close()


# --------------------------------------------------------------------------- running

@dataclasses.dataclass
class SweepReport:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    out : Path
        The sweep folder.
    table : SweepTable
        One row per finished case, in case order (as written).
    files : list of str
        The table's files in ``out``.
    computed : int
        Cases finished by this call (those whose parameters the scene rejected included).
    reused : int
        Cases taken over from an earlier run (their results.json).
    pending : int
        Cases left to run (``max_cases``).
    """

    out: Path
    table: SweepTable
    files: list
    computed: int
    reused: int
    pending: int

    @property
    def columns(self) -> list[str]:
        """Columns of the table."""
        return self.table.columns

    @property
    def rows(self) -> list[dict[str, Any]]:
        """Rows of the table."""
        return self.table.rows

    @property
    def done(self) -> int:
        """Number of cases that are done."""
        return sum(row["status"] == DONE for row in self.rows)

    @property
    def failed(self) -> int:
        """Number of finished cases that are not done (failed or not converged)."""
        return len(self.rows) - self.done

    def summary(self) -> list[str]:
        """Lines for the command line: the table (errors below it), the counts, the files."""
        columns = [c for c in self.columns if c != "error"]
        lines = [tables.markdown(self.rows, columns, self.table.units)]
        lines += [f"case {row['case']}: {row['error']}" for row in self.rows if row["error"]]
        lines.append(f"{len(self.rows)} cases: {self.done} done, {self.failed} failed; run now "
                     f"{self.computed}, taken over {self.reused}"
                     + (f", left for the next run {self.pending}" if self.pending else ""))
        missing = [c for c in columns if c not in self.table.varied and c not in FIXED_COLUMNS
                   and any(r["status"] == DONE and r[c] is None for r in self.rows)]
        if missing:
            lines.append(f"not reported by every case that is done: {', '.join(missing)}")
        lines.append(f"table written to {', '.join(str(self.out / f) for f in self.files)}")
        return lines


def run_sweep(sweep: Sweep, out: str | os.PathLike, *, workers: int | None = None,
              threads: int | None = None, scheduler: Any = None, resume: bool = False,
              max_cases: int | None = None, progress: Progress = SILENT) -> SweepReport:
    """Run the cases of a sweep that are not done yet and write the table.

    Parameters
    ----------
    sweep : Sweep
        From :func:`load_sweep` or :func:`parse_sweep`.
    out : path-like
        The sweep folder: one folder per case, the table (:mod:`.table`).
    workers : int, optional
        Local worker processes (default min(2, cases to run)); with ``scheduler``: cases
        submitted at a time (default: the cluster's threads).
    threads : int, optional
        NGSolve threads per case (default: cores // workers locally, 1 on Dask).
    scheduler : str or dask.distributed.Client, optional
        Run on this Dask cluster instead of local processes.
    resume : bool
        Accept a folder that holds a different sweep, reusing the finished cases they share.
        (An unchanged sweep always resumes: done cases are skipped, the others run again.)
    max_cases : int, optional
        Run at most this many cases now; the rest stay for the next run.
    progress : Progress
        Where the sweep reports each finished case, and each case its stages (plain lines
        from the workers); default: nowhere.

    Returns
    -------
    SweepReport

    Raises
    ------
    ParameterError
        A bad option, a folder that cannot take the sweep or holds another run (see
        :func:`ngincompat.workflow.output.prepare`) or another sweep (without ``resume``).
    """
    for name, value, low in (("workers", workers, 1), ("threads", threads, 1),
                             ("max_cases", max_cases, 0)):
        if value is not None and not (isinstance(value, int) and value >= low):
            raise ParameterError(f"{name} = {value!r} is out of range: allowed an integer "
                                 f">= {low}")
    with output.folder(out) as folder:
        return _sweep_in(sweep, folder.resolve(), workers, threads, scheduler, resume,
                         max_cases, progress)


def _sweep_in(sweep: Sweep, out: Path, workers: int | None, threads: int | None, scheduler: Any,
              resume: bool, max_cases: int | None, progress: Progress) -> SweepReport:
    """:func:`run_sweep` in its folder, prepared and held."""
    record = sweep.record()
    _check_record(out, record, resume)
    cases = sweep.cases()
    scenes, rejected = {}, {}
    for case in cases:
        try:
            scenes[case.index] = case.build()
        except ParameterError as err:
            rejected[case.index] = err

    outcomes, todo = {}, []
    for case in cases:
        results = None if case.index in rejected else _finished(scenes[case.index],
                                                                out / case.name)
        if results is None:
            todo.append(case)
        else:
            outcomes[case.index] = {"varied": case.varied, **outcome(results)}
    reused = len(outcomes)
    if max_cases is not None:
        todo = todo[:max_cases]
    progress.line(f"sweep {out}: {len(cases)} cases, {reused} done, {len(todo)} to run")

    journal = out / JOURNAL

    def finish(case: Case, outcome: dict[str, Any]) -> None:
        outcomes[case.index] = {"varied": case.varied, **outcome}
        line = json.dumps(io.jsonable({"case": case.index, **outcomes[case.index]}))
        with open(journal, "a", encoding="utf-8") as stream:
            stream.write(line + "\n")
        done = sum(o["status"] == DONE for o in outcomes.values())
        what = f"in {outcome['seconds']:.2f} s" if outcome["error"] is None else \
            f"({outcome['error']})"
        progress.line(f"{case.name} {_describe(case.varied)}: {outcome['status']} {what}; "
                      f"{len(outcomes)} of {len(cases)} finished, "
                      f"{len(outcomes) - done} not done")

    write_table(out, make_table(sweep, outcomes), record)
    journal.unlink(missing_ok=True)
    runnable = deque(case for case in todo if case.index not in rejected)
    try:
        for case in todo:
            if case.index in rejected:
                err = rejected[case.index]  # type: ignore[misc]  # not the except clause's
                finish(case, failed(out / case.name, err, 0.0,  # type: ignore[misc]
                                    f"{error_message(err)}\n"))  # type: ignore[misc]
        if runnable:
            _run_all(runnable, scenes, out, workers, threads, scheduler, progress, finish)
    except KeyboardInterrupt:
        for case in todo:           # each row as its folder has it (see _settled)
            if case.index not in rejected:
                outcomes[case.index] = _settled(case, scenes[case.index], out / case.name,
                                                outcomes.get(case.index))
        raise
    finally:
        # the whole table once, also when interrupted; the journal is then redundant
        table = make_table(sweep, outcomes)
        files = write_table(out, table, record)
        journal.unlink(missing_ok=True)
    return SweepReport(out, table, files, len(todo), reused, len(cases) - reused - len(todo))


def _run_all(cases: deque[Case], scenes: Mapping[int, Scene], out: Path, workers: int | None,
             threads: int | None, scheduler: Any, progress: Progress,
             finish: Callable[[Case, dict[str, Any]], None]) -> None:
    """Run ``cases`` (a deque) on local processes or Dask, ``finish(case, outcome)`` as each
    ends; on an interruption the running cases are cancelled and the error re-raised."""
    if scheduler is not None:
        backend: _Dask | LocalPool = _Dask(scheduler, workers, threads, progress)
    else:
        backend = LocalPool(workers or min(2, len(cases)), threads, progress)
    tasks = deque((case, {"scene": scenes[case.index], "folder": str(out / case.name),
                          "threads": None, "quiet": progress.quiet}) for case in cases)
    try:
        run_side_by_side(tasks, backend, finish)
    except KeyboardInterrupt:
        progress.line(f"sweep interrupted; the table {out / RECORD} holds the finished "
                      "cases; run the sweep again to go on")
        raise


def _describe(varied: Mapping[str, Any]) -> str:
    return "(" + ", ".join(f"{k}={v!r}" for k, v in varied.items()) + ")"


def _check_record(out: Path, record: Mapping[str, Any], resume: bool) -> None:
    """Refuse a folder that holds another sweep, unless resuming."""
    path = out / RECORD
    if resume or not path.is_file():
        return
    try:
        old = io.read_json(path)
    except (OSError, ValueError):
        return
    if old.get("cases") != io.jsonable(record["cases"]):
        raise ParameterError(
            f"--out {out} holds a different sweep ({len(old.get('cases', []))} cases of scene "
            f"{old.get('scene')!r}): pass --resume to reuse its finished cases, or choose "
            "another folder")
