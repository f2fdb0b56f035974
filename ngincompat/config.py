"""The package's version and NGSolve's run-time settings: threads and local heap.

Importing :mod:`ngincompat` changes nothing in NGSolve. The settings apply where the package
runs NGSolve's task manager (:func:`task_manager`) or builds high-order spaces
(:func:`ensure_heap`), so a notebook that calls NGSolve itself keeps NGSolve's own defaults::

    import ngincompat
    ngincompat.configure(threads=2, heap=400_000_000)

Threads: :func:`configure`'s value, else ``NGS_NUM_THREADS``, else one. The task manager's
threads wait actively for each other at every parallel loop, so on cores that other jobs share
they cost more than they give; one is the safe default, more a choice (the performance pages
of the documentation measure both).

Heap: NGSolve's local heap holds the element matrices. High-order element matrices of
matrix-valued spaces overflow NGSolve's default ("Local Heap overflow"), so the package keeps
at least :data:`DEFAULT_HEAP` bytes, or what :func:`configure` sets, and raises it further
where an order needs more (:func:`ensure_heap`).
"""

import contextlib
import os
from collections.abc import Iterator, Mapping
from importlib import metadata

from ngincompat.errors import require


def _version() -> str:
    """The package's version from its installed metadata (``pyproject.toml``'s, written by
    pip); "0+unknown" for a source tree on the path that was never installed."""
    try:
        return metadata.version("ngincompat")
    except metadata.PackageNotFoundError:
        return "0+unknown"


#: The package's version (one place: ``pyproject.toml``, read through the metadata).
VERSION = _version()

#: The local heap (bytes) the package keeps at least, unless :func:`configure` says otherwise.
DEFAULT_HEAP = 200 * 1000 * 1000

_configured: dict[str, int | None] = {"threads": None, "heap": None}
_heap_in_force = 0
_depth = 0


def configure(threads: int | None = None, heap: int | None = None) -> dict:
    """Set NGSolve's thread count and the package's local heap for everything that follows.

    Parameters
    ----------
    threads : int, optional
        NGSolve threads of the task manager, >= 1 (None: leave as configured, by default
        ``NGS_NUM_THREADS`` or one).
    heap : int, optional
        Local heap in bytes, >= 1e6 (None: leave as configured, by default
        :data:`DEFAULT_HEAP`). Only ever raised: NGSolve cannot shrink a heap it handed out.

    Returns
    -------
    dict
        The settings in force: ``{"threads": ..., "heap": ...}``.
    """
    if threads is not None:
        require(isinstance(threads, int) and not isinstance(threads, bool) and threads >= 1,
                "threads", threads, "an integer >= 1")
        _configured["threads"] = threads
    if heap is not None:
        require(isinstance(heap, int) and not isinstance(heap, bool) and heap >= 10**6,
                "heap", heap, "an integer >= 1e6 (bytes)")
        _configured["heap"] = heap
    ensure_heap(0)
    return settings()


#: The most threads ``NGS_NUM_THREADS`` may ask for: far past any core count this package runs
#: on (more threads than cores only wait for each other); NGSolve itself fails to import at a
#: few thousand.
MAX_THREADS = 256


def check_environment(environ: Mapping[str, str] | None = None) -> None:
    """Raise ParameterError, naming the variable and its allowed values, if an environment
    variable NGSolve reads at import is unusable: ``NGS_NUM_THREADS`` must be an
    integer in [1, :data:`MAX_THREADS`] or unset (0 ran NGSolve's loops on no thread and
    computed garbage, and so did an empty value, which NGSolve reads as 0; a word or a
    number out of range broke NGSolve's import)."""
    variables = os.environ if environ is None else environ
    if "NGS_NUM_THREADS" not in variables:
        return
    value = variables["NGS_NUM_THREADS"]
    text = value.strip()
    require(text.isascii() and text.isdigit() and 1 <= int(text) <= MAX_THREADS,
            "NGS_NUM_THREADS", value,
            f"an integer in [1, {MAX_THREADS}] (NGSolve threads), or unset")


def threads() -> int:
    """The NGSolve threads the package runs on: configured, else ``NGS_NUM_THREADS``, else 1."""
    if _configured["threads"] is not None:
        return _configured["threads"]
    check_environment()
    return int(os.environ.get("NGS_NUM_THREADS", "").strip() or 1)


def settings() -> dict:
    """The settings in force, ``{"threads": ..., "heap": ...}``."""
    return {"threads": threads(), "heap": max(_heap_in_force, _floor())}


def _floor() -> int:
    return _configured["heap"] or DEFAULT_HEAP


def ensure_heap(nbytes: int) -> None:
    """Make NGSolve's local heap at least ``nbytes`` and at least the configured floor."""
    global _heap_in_force
    need = max(int(nbytes), _floor())
    if need > _heap_in_force:
        import ngsolve

        ngsolve.SetHeapSize(need)
        _heap_in_force = need


@contextlib.contextmanager
def task_manager() -> Iterator[None]:
    """NGSolve's task manager on :func:`threads` threads, with the heap of :func:`ensure_heap`;
    NGSolve's own thread count comes back after the outermost one."""
    global _depth
    import ngsolve
    from pyngcore import GetNumThreads

    ensure_heap(0)
    if _depth == 0:      # the thread count cannot change inside a running task manager
        with ngsolve.TaskManager():             # NGSolve's count, read where it is defined
            before = GetNumThreads()
        ngsolve.SetNumThreads(threads())
    _depth += 1
    try:
        with ngsolve.TaskManager():
            yield
    finally:
        _depth -= 1
        if _depth == 0:
            ngsolve.SetNumThreads(before)


@contextlib.contextmanager
def using(threads: int | None = None) -> Iterator[dict]:
    """:func:`configure` the threads for the block only; those configured before come back."""
    before = _configured["threads"]
    configure(threads=threads)
    try:
        yield settings()
    finally:
        _configured["threads"] = before
