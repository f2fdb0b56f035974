"""Running scene runs side by side in local worker processes: the cases of a sweep
(:mod:`ngincompat.studies.sweep`) and the runs of the paper job (:mod:`.paper`).

Each case is a task ``{"scene", "folder", "threads", "quiet"}`` that :func:`run_case` runs in
a worker ("spawn") and turns into an outcome (status, metrics, seconds, error) without ever
raising: a run that does not converge, fails or is interrupted is an outcome like the others.
:func:`run_side_by_side` keeps a pool (or another backend with the same ``window``,
``submit``, ``wait`` and ``close``) busy and hands each outcome to a callback as it ends.

Ctrl-C: a worker ignores it but while it runs a case (the case then ends "interrupted" and
its results.json says so); on an interruption the pool starts no further case, interrupts the
running ones, awaits their records and re-raises the KeyboardInterrupt.
"""

import concurrent.futures
import contextlib
import multiprocessing
import os
import signal
import threading
import time
import traceback
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any

from ngincompat import config
from ngincompat.atomic import atomic_path
from ngincompat.errors import ConvergenceError, Interrupted
from ngincompat.progress import Progress
from ngincompat.workflow.results import INTERRUPTED, Results

if TYPE_CHECKING:     # the pool's event; its module is imported where a pool starts
    from multiprocessing.synchronize import Event

#: Status of a case that raised, or whose scene rejected its parameters.
FAILED = "failed"
#: Name of a failed case's traceback file, in its folder.
ERROR_FILE = "error.txt"


def run_case(task: dict[str, Any]) -> dict[str, Any]:
    """Run one case (in a worker); returns its outcome and never raises.

    Parameters
    ----------
    task : dict
        ``scene`` (a Scene), ``folder``, ``threads`` (NGSolve threads, or None to keep the
        worker's setting), ``quiet`` (no progress report; else plain lines on the worker's
        standard error, each naming the case) and optionally ``after``, a picklable callable
        given the run's results (also those of a run that did not converge) in the worker,
        where its NGSolve fields live (the paper job draws its figures there).

    Returns
    -------
    dict
        ``status`` ("done", "not converged", "interrupted" or "failed"), ``metrics``,
        ``seconds`` (the sum of the run's timings; for a failed case the wall time until the
        failure) and ``error`` (message, or None).

    A local worker takes Ctrl-C only while it runs a case (:func:`_init_worker`): the case is
    then "interrupted", its results.json says so, and nothing is printed; after the cases
    were stopped (:data:`_stop`) a case still queued is "interrupted" without running.
    """
    start = time.perf_counter()
    folder = Path(task["folder"])
    if _stop is not None and _stop.is_set():
        return interrupted(None)
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
                results, error = err.results, error_message(err)
            if task.get("after") is not None:
                task["after"](results)
    except (Interrupted, KeyboardInterrupt) as err:
        if results is None:     # else the run had ended and written its results
            return interrupted(getattr(err, "results", None), time.perf_counter() - start,
                                str(err))
    except Exception as err:
        return failed(folder, err, time.perf_counter() - start, traceback.format_exc())
    (folder / ERROR_FILE).unlink(missing_ok=True)
    return outcome(results, error)


#: Whether the process was started with Ctrl-C ignored (by a shell, for a job in the
#: background): then its cases ignore Ctrl-C too, as its own process does.
_SIGINT_IGNORED = signal.getsignal(signal.SIGINT) is signal.SIG_IGN

#: Set once the cases are interrupted (in a local worker: the event :func:`_init_worker` was
#: given): a case that has not started does not start.
_stop: "Event | None" = None


@contextlib.contextmanager
def _interruptible() -> Iterator[None]:
    """The first Ctrl-C or SIGTERM raises KeyboardInterrupt in the block, the next ones are
    ignored (a local worker ignores them outside it, :func:`_ignore`): a batch system's stop,
    sent to every process of the job, ends the case "interrupted" with its record and its
    folder's lock released, where the default SIGTERM killed the worker (a broken pool, a
    stale lock); and the stop arrives twice (to the whole job, then from the pool,
    :meth:`LocalPool.close`), where a second KeyboardInterrupt, raised while the case wrote
    its record and released its lock, left the lock behind. Ctrl-C stays ignored in a
    process started with it ignored (:data:`_SIGINT_IGNORED`). Off the main thread (a Dask
    worker's task) nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    taken: list[int] = []

    def once(signum: int, frame: FrameType | None) -> None:
        if not taken:
            taken.append(signum)
            raise KeyboardInterrupt

    previous = (signal.signal(signal.SIGINT, signal.SIG_IGN if _SIGINT_IGNORED else once),
                signal.signal(signal.SIGTERM, once))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous[0])
        signal.signal(signal.SIGTERM, previous[1])


def _ignore(signum: int, frame: FrameType | None) -> None:
    """A local worker's Ctrl-C and SIGTERM outside a case: nothing. A handler rather than
    SIG_IGN, which, set while a signal is pending, makes Python print a traceback ("Signal
    15 ignored due to race condition")."""


@contextlib.contextmanager
def _sigint_held() -> Iterator[None]:
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


def interrupted(results: Results | None, seconds: float | None = None,
                message: str = "") -> dict[str, Any]:
    """The outcome of a case stopped by Ctrl-C (``results``: its record, if it had begun)."""
    metrics = {} if results is None else results.metrics
    error = results.error if results is not None else message
    return {"status": INTERRUPTED, "metrics": metrics, "seconds": seconds,
            "error": error or "interrupted"}


def outcome(results: Results, error: str | None = None) -> dict[str, Any]:
    """The outcome of a case from its :class:`~ngincompat.workflow.results.Results`."""
    return {"status": results.status, "warnings": len(results.warnings),
            "metrics": results.metrics, "seconds": sum(results.timings.values()),
            "error": error}


def failed(folder: str | os.PathLike, err: BaseException, seconds: float,
           text: str) -> dict[str, Any]:
    """The outcome of a case that raised ``err``; ``text`` goes to its error.txt."""
    try:
        with atomic_path(Path(folder) / ERROR_FILE) as tmp:
            tmp.write_text(text)
    except OSError:
        pass
    return {"status": FAILED, "metrics": {}, "seconds": seconds, "error": error_message(err)}


def _init_worker(threads: int, stop: "Event") -> None:
    """Initializer of a local worker process: its number of NGSolve threads, Ctrl-C and
    SIGTERM ignored but while a case runs (:func:`_interruptible`; an idle worker would print
    the KeyboardInterrupt of its wait for work), and the pool's ``stop`` event."""
    global _stop
    signal.signal(signal.SIGINT, signal.SIG_IGN if _SIGINT_IGNORED else _ignore)
    signal.signal(signal.SIGTERM, _ignore)     # the pool ends an idle worker itself
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    config.configure(threads=threads)
    _stop = stop
    threading.Thread(target=_stop_when_set, args=(stop,), name="stop-watch",
                     daemon=True).start()


def _stop_when_set(stop: "Event") -> None:
    """A local worker's watch: once the pool's cases are interrupted (``stop`` set by
    :meth:`LocalPool.close`), a SIGTERM to itself, which stops its case
    (:func:`_interruptible`) or, between cases, does nothing."""
    stop.wait()
    os.kill(os.getpid(), signal.SIGTERM)


def error_message(err: BaseException) -> str:
    text = " ".join(str(err).split())
    return f"{type(err).__name__}: {text}" if text else type(err).__name__


class LocalPool:
    """Local worker processes ("spawn") with a fixed number of NGSolve threads each."""

    def __init__(self, workers: int, threads: int | None, progress: Progress) -> None:
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

    def submit(self, task: dict[str, Any]) -> concurrent.futures.Future:
        """Submit ``task``; a worker it starts prints no KeyboardInterrupt of its imports
        (:func:`_sigint_held`)."""
        with _sigint_held():
            return self.executor.submit(run_case, task)

    def wait(self, futures: Iterable[concurrent.futures.Future]
             ) -> set[concurrent.futures.Future]:
        done, _ = concurrent.futures.wait(futures, return_when=concurrent.futures.FIRST_COMPLETED)
        return done

    def close(self, cancel: bool) -> None:
        """Shut the workers down; with ``cancel`` (an interruption) no case starts any more
        and the running ones are interrupted (a Ctrl-C at a terminal has reached them
        already), and their ends are awaited: they write their records quickly."""
        if cancel:
            self.stop.set()     # each worker stops its case (:func:`_stop_when_set`)
        self.executor.shutdown(wait=True, cancel_futures=cancel)


def run_side_by_side(tasks: deque[tuple[Any, dict[str, Any]]], backend: Any,
                     finish: Callable[[Any, dict[str, Any]], object]) -> None:
    """Run ``tasks`` (a deque of (key, task)) on ``backend`` (e.g. a :class:`LocalPool`),
    at most ``backend.window`` at a time, calling ``finish(key, outcome)`` as each ends.
    On an interruption no further task starts, the running ones are interrupted, those
    that ended are still finished, and the KeyboardInterrupt is re-raised."""
    running: dict[concurrent.futures.Future, Any] = {}
    completed = False
    try:
        while tasks or running:
            while tasks and len(running) < backend.window:
                key, task = tasks.popleft()
                running[backend.submit(task)] = key
            for future in backend.wait(set(running)):
                # dropped from running only once finished: an interruption inside finish
                # leaves it to the finishing below, so that no ended task is lost
                finish(running[future], result(future))
                del running[future]
        completed = True
    finally:
        backend.close(cancel=not completed)
        if not completed:
            for future, key in running.items():     # ended by the interruption
                if future.done() and not future.cancelled():
                    finish(key, result(future))


def result(future: concurrent.futures.Future) -> dict[str, Any]:
    """The outcome of a finished future; a worker that died (or a cluster that lost it) is
    a failed case."""
    try:
        return future.result()
    except Exception as err:
        return {"status": FAILED, "metrics": {}, "seconds": None, "error": error_message(err)}
