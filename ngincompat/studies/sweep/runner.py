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
writes the table with every case: those that had not finished are rows "interrupted".
"""

import concurrent.futures
import contextlib
import dataclasses
import json
import multiprocessing
import os
import signal
import threading
import time
import traceback
import uuid
from collections import deque
from pathlib import Path

from ngincompat import config
from ngincompat.atomic import atomic_path
from ngincompat.errors import ConvergenceError, Interrupted, ParameterError
from ngincompat.progress import SILENT, Progress
from ngincompat.studies.sweep.table import (
    FIXED_COLUMNS,
    JOURNAL,
    RECORD,
    make_table,
    write_table,
)
from ngincompat.workflow import io, output, tables
from ngincompat.workflow.results import DONE, INTERRUPTED

#: Status of a case that raised, or whose scene rejected its parameters.
FAILED = "failed"
#: Name of a failed case's traceback file, in its folder.
ERROR_FILE = "error.txt"


# --------------------------------------------------------------------------- one case

def run_case(task):
    """Run one case (in a worker); returns its outcome and never raises.

    Parameters
    ----------
    task : dict
        ``scene`` (a Scene), ``folder``, ``threads`` (NGSolve threads, or None to keep the
        worker's setting) and ``quiet`` (no progress report; else plain lines on the worker's
        standard error, each naming the case).

    Returns
    -------
    dict
        ``status`` ("done", "not converged", "interrupted" or "failed"), ``metrics``,
        ``seconds`` (the sum of the run's timings; for a failed case the wall time until the
        failure) and ``error`` (message, or None).

    A local worker takes Ctrl-C only while it runs a case (:func:`_init_worker`): the case is
    then "interrupted", its results.json says so, and nothing is printed; after the sweep
    was stopped (:data:`_stop`) a case still queued is "interrupted" without running.
    """
    start = time.perf_counter()
    folder = Path(task["folder"])
    if _stop is not None and _stop.is_set():
        return _interrupted(None)
    results = error = None
    try:
        with _interruptible():
            if task.get("threads"):
                config.configure(threads=task["threads"])
            progress = Progress(quiet=task["quiet"], bars=False)
            try:
                results = task["scene"].run(folder, overwrite=True, progress=progress,
                                            label=folder.name)
            except ConvergenceError as err:
                results, error = err.results, _message(err)
    except (Interrupted, KeyboardInterrupt) as err:
        if results is None:     # else the run had ended and written its results
            return _interrupted(getattr(err, "results", None), time.perf_counter() - start,
                                str(err))
    except Exception as err:
        return _failed(folder, err, time.perf_counter() - start, traceback.format_exc())
    (folder / ERROR_FILE).unlink(missing_ok=True)
    return _outcome(results, error)


#: Set by the sweep (in a local worker: the event :func:`_init_worker` was given) once it is
#: interrupted: a case that has not started does not start.
_stop = None


@contextlib.contextmanager
def _interruptible():
    """Ctrl-C raises KeyboardInterrupt in the block (in a local worker, which ignores it
    otherwise); off the main thread (a Dask worker's task) nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def _sigint_held():
    """Ctrl-C held back on the calling thread in the block and delivered at its end; a worker
    process started in the block inherits the held signal mask, so that a Ctrl-C arriving
    while it still imports stays pending until :func:`_init_worker` discards it."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _interrupted(results, seconds=None, message=""):
    """The outcome of a case stopped by Ctrl-C (``results``: its record, if it had begun)."""
    metrics = {} if results is None else results.metrics
    error = results.error if results is not None else message
    return {"status": INTERRUPTED, "metrics": metrics, "seconds": seconds,
            "error": error or "interrupted"}


def _outcome(results, error=None):
    """The outcome of a case from its :class:`~ngincompat.workflow.results.Results`."""
    return {"status": results.status, "warnings": len(results.warnings),
            "metrics": results.metrics, "seconds": sum(results.timings.values()),
            "error": error}


def _failed(folder, err, seconds, text):
    """The outcome of a case that raised ``err``; ``text`` goes to its error.txt."""
    try:
        with atomic_path(Path(folder) / ERROR_FILE) as tmp:
            tmp.write_text(text)
    except OSError:
        pass
    return {"status": FAILED, "metrics": {}, "seconds": seconds, "error": _message(err)}


def _init_worker(threads, stop):
    """Initializer of a local worker process: its number of NGSolve threads, Ctrl-C ignored
    but while a case runs (:func:`_interruptible`; an idle worker would print the
    KeyboardInterrupt of its wait for work), and the sweep's ``stop`` event."""
    global _stop
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    config.configure(threads=threads)
    _stop = stop


def _message(err):
    text = " ".join(str(err).split())
    return f"{type(err).__name__}: {text}" if text else type(err).__name__


def _finished(scene, folder):
    """The :class:`~ngincompat.workflow.results.Results` in ``folder`` if they are done and of
    ``scene`` (same name and parameters), else None."""
    try:
        results = output.read(folder)
    except ParameterError:
        return None
    same = (results.scene == scene.name
            and results.params == io.jsonable(scene.settings()))
    return results if same and results.status == DONE else None


# --------------------------------------------------------------------------- executors

class _Local:
    """Local worker processes ("spawn") with a fixed number of NGSolve threads each."""

    def __init__(self, workers, threads, progress):
        cores = os.cpu_count() or 1
        self.window = workers
        threads = threads or max(1, cores // workers)
        if workers * threads > cores:
            progress.line(f"warning: {workers} workers x {threads} NGSolve threads exceed "
                          f"the {cores} cores")
        progress.line(f"local pool: {workers} workers x {threads} NGSolve threads")
        context = multiprocessing.get_context("spawn")
        self.stop = context.Event()
        self.executor = concurrent.futures.ProcessPoolExecutor(
            max_workers=workers, mp_context=context,
            initializer=_init_worker, initargs=(threads, self.stop))

    def submit(self, task):
        """Submit ``task``; a worker it starts prints no KeyboardInterrupt of its imports
        (:func:`_sigint_held`)."""
        with _sigint_held():
            return self.executor.submit(run_case, task)

    def wait(self, futures):
        done, _ = concurrent.futures.wait(futures, return_when=concurrent.futures.FIRST_COMPLETED)
        return done

    def close(self, cancel):
        """Shut the workers down; with ``cancel`` (an interruption) no case starts any more
        and the running ones are interrupted (a Ctrl-C at a terminal has reached them
        already), and their ends are awaited: they write their records quickly."""
        if cancel:
            self.stop.set()
            for process in list(getattr(self.executor, "_processes", {}).values()):
                with contextlib.suppress(OSError):
                    os.kill(process.pid, signal.SIGINT)
        self.executor.shutdown(wait=True, cancel_futures=cancel)


class _Dask:
    """An existing Dask cluster, by the address of its scheduler (or a Client)."""

    def __init__(self, scheduler, workers, threads, progress):
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
        self.futures = set()

    def submit(self, task):
        key = f"ngincompat-{Path(task['folder']).name}-{uuid.uuid4().hex[:8]}"
        future = self.client.submit(run_case, {**task, "threads": self.threads}, key=key,
                                    pure=False)
        self.futures.add(future)
        return future

    def wait(self, futures):
        self.distributed.wait(list(futures), return_when="FIRST_COMPLETED")
        done = [f for f in futures if f.done()]
        self.futures.difference_update(done)
        return done

    def close(self, cancel):
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
    table: object
    files: list
    computed: int
    reused: int
    pending: int

    @property
    def columns(self):
        """Columns of the table."""
        return self.table.columns

    @property
    def rows(self):
        """Rows of the table."""
        return self.table.rows

    @property
    def done(self):
        """Number of cases that are done."""
        return sum(row["status"] == DONE for row in self.rows)

    @property
    def failed(self):
        """Number of finished cases that are not done (failed or not converged)."""
        return len(self.rows) - self.done

    def summary(self):
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


def run_sweep(sweep, out, *, workers=None, threads=None, scheduler=None, resume=False,
              max_cases=None, progress=SILENT):
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


def _sweep_in(sweep, out, workers, threads, scheduler, resume, max_cases, progress):
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
            outcomes[case.index] = {"varied": case.varied, **_outcome(results)}
    reused = len(outcomes)
    if max_cases is not None:
        todo = todo[:max_cases]
    progress.line(f"sweep {out}: {len(cases)} cases, {reused} done, {len(todo)} to run")

    journal = out / JOURNAL

    def finish(case, outcome):
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
                err = rejected[case.index]
                finish(case, _failed(out / case.name, err, 0.0, f"{_message(err)}\n"))
        if runnable:
            _run_all(runnable, scenes, out, workers, threads, scheduler, progress, finish)
    except KeyboardInterrupt:
        for case in todo:           # the cases the interruption kept from ending
            outcomes.setdefault(case.index, {"varied": case.varied, **_interrupted(None)})
        raise
    finally:
        # the whole table once, also when interrupted; the journal is then redundant
        table = make_table(sweep, outcomes)
        files = write_table(out, table, record)
        journal.unlink(missing_ok=True)
    return SweepReport(out, table, files, len(todo), reused, len(cases) - reused - len(todo))


def _run_all(cases, scenes, out, workers, threads, scheduler, progress, finish):
    """Run ``cases`` (a deque) on local processes or Dask, ``finish(case, outcome)`` as each
    ends; on an interruption the running cases are cancelled and the error re-raised."""
    if scheduler is not None:
        backend = _Dask(scheduler, workers, threads, progress)
    else:
        backend = _Local(workers or min(2, len(cases)), threads, progress)
    running = {}
    finished = False
    try:
        while cases or running:
            while cases and len(running) < backend.window:
                case = cases.popleft()
                task = {"scene": scenes[case.index], "folder": str(out / case.name),
                        "threads": None, "quiet": progress.quiet}
                running[backend.submit(task)] = case
            for future in backend.wait(set(running)):
                case = running.pop(future)
                finish(case, _result(future))
        finished = True
    finally:
        backend.close(cancel=not finished)
        if not finished:
            for future, case in running.items():    # ended by the interruption
                if future.done() and not future.cancelled():
                    finish(case, _result(future))
            progress.line(f"sweep interrupted; the table {out / RECORD} holds the finished "
                          "cases; run the sweep again to go on")


def _result(future):
    try:
        return future.result()
    except Exception as err:  # the worker died (or the cluster lost it)
        return {"status": FAILED, "metrics": {}, "seconds": None, "error": _message(err)}


def _describe(varied):
    return "(" + ", ".join(f"{k}={v!r}" for k, v in varied.items()) + ")"


def _check_record(out, record, resume):
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
