"""The hostile-input corpus through the whole command line: ``ngincompat bench inputs``.

What a hostile user would type, tried as the command line takes it, each try ending in one
of :data:`OUTCOMES`:

* every numeric parameter of every scene (:func:`parameter_tries`), given each value of
  :data:`HOSTILE` (huge, non-finite, wrong, subnormal and tiny; an integer parameter also
  :data:`HOSTILE_INT`) and the ends of its own declared range: each end, and the nearest
  number past it (:func:`boundary_values`), as ``ngincompat run SCENE --preset preview --set
  KEY=VALUE`` on the scene's :data:`QUICK` settings (a value the scene accepts then runs to
  its end in seconds);
* the environment variables the documentation names or the program reads
  (:data:`ENVIRONMENT`), each under ``ngincompat run cube --preset preview``;
* the paper job's options (:data:`PAPER_OPTIONS`) and its interrupts: SIGINT (a terminal's
  Ctrl-C, to the whole process group) and SIGTERM (a batch system's stop) while it meshes
  and while it solves (:data:`INTERRUPTS`).

A try's outcome, from its exit code and standard error: "done" (exit 0, every metric of its
results.json finite), "refused" (2), "not converged" (3), "interrupted" (130), "time limit"
(stopped at the time limit while it still reported progress: a long run, such as a year of
growth in half-day steps, not a hang), and the
defects: "traceback" (a Python traceback on the standard error, whatever the code), "hang"
(no end within the time limit, and no progress reported for :data:`QUIET` seconds before
it), "signal" (ended by a signal: a crash), "non-finite" (exit 0
with a metric that is not a finite number), "lock left" (an interrupted job's folder still
locked) and "other" (any other exit code).

The values of one parameter run in one process, which calls :func:`ngincompat.cli.main`
once per value (:func:`drive`), its standard error captured per value; a value that hangs
or crashes the process is recorded and the process started again after it. The environment
and interrupt tries each run in a process of their own.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import importlib
import io
import json
import math
import os
import queue
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from collections import Counter
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from ngincompat.parameters import _Float, _Floats, _Int, _Kind, _WordsOrFloats
from ngincompat.progress import SILENT, Progress
from ngincompat.workflow import tables

if TYPE_CHECKING:     # the scenes are imported where a try is made (drive() runs without them)
    from ngincompat.scenes.base import Scene

#: Huge, non-finite, wrong, and tiny: a subnormal, and positive values far below any physical
#: floor (each passed the "(0, x]" ranges once and broke deep in meshing, solving or
#: measuring).
HOSTILE = ("1e308", "inf", "-inf", "nan", "0", "-1", "-1e308", "two", "", "1e-320", "1e-300",
           "1e-10")
#: What an integer parameter gets besides: a number no machine integer holds.
HOSTILE_INT = ("100000000000000000000",)

#: Settings under which an accepted value of each scene runs in seconds, on top of its preview
#: preset (a key the try sets itself is left out): the small bilayer grown in one step before
#: its onset, the small brain for four years, the skin inflated to 3 cc and grown half a day.
QUICK = {
    "folding": {"length": "0.5", "height": "0.3", "maxh": "0.15", "t_end": "10", "dt": "10",
                "onset_dt": "10", "release": "false", "cortex_maxh": "0.025"},
    "atrophy": {"maxh": "1", "semi_axes": "3,2.5,2", "gray_thickness": "0.5",
                "seed": "0,0,-2", "t_end": "4", "dt": "1", "snapshots": "1", "g_order": "2"},
    "skin": {"maxh": "3", "order": "1", "growth_order": "0", "g_order": "2", "volume": "3",
             "inflation_steps": "1", "theta_crit": "1", "hold_days": "0.5", "dt": "0.5"},
}

#: Values of the environment variables: NGSolve's threads (read when NGSolve is imported)
#: and the MPI launchers' rank counts (a run started without a launcher).
ENVIRONMENT = {
    "NGS_NUM_THREADS": ("0", "-1", "abc", "1.5", "100000", "1e308", "nan", "", " 2 ", "1",
                        "2"),
    "PMI_SIZE": ("0", "1", "2", "abc", "99999999999999999999"),
    "OMPI_COMM_WORLD_SIZE": ("2", "-3"),
}
#: The command each environment try runs (after ``ngincompat``).
ENVIRONMENT_COMMAND = ("run", "cube", "--preset", "preview")

#: Options of the paper job, each with values a user might mistype (its sections: the fast
#: ones, so that an accepted value runs in seconds).
PAPER_OPTIONS = {
    "--only": ("", " , ", "3.9", "all", "3.1,3.1", "3.1"),
    "--jobs": ("0", "-1", "1e308", "two", "100000", "1"),
    "--resolution": ("", "fine", "PREVIEW"),
}
#: The sections an option try of the paper job runs when the option is not ``--only``.
PAPER_SECTIONS = "3.1"


@dataclass(frozen=True)
class Interrupt:
    """A signal sent to the process group of ``args`` once a line of its standard error
    contains ``when``, ``delay`` seconds later."""

    name: str
    args: tuple
    signum: int
    when: str
    delay: float = 1.0


#: The paper job stopped as a terminal and a batch system stop it: while its workers mesh and
#: while they solve.
INTERRUPTS = tuple(
    Interrupt(f"{sig.name} while {phase}", ("paper", "--only", "3.1,3.4", "--jobs", "2"), sig,
              when, delay)
    for sig in (signal.SIGINT, signal.SIGTERM)
    for phase, when, delay in (("meshing", "meshing ...", 0.2),
                              ("solving", "growth: from", 0.2)))

#: The outcomes, the expected ones first.
OUTCOMES = ("done", "refused", "not converged", "interrupted", "time limit", "traceback",
            "hang", "signal", "non-finite", "lock left", "other")
#: The outcomes that are defects.
DEFECTS = OUTCOMES[5:]
#: Exit codes of the command line and their outcomes.
CODES = {0: "done", 2: "refused", 3: "not converged", 130: "interrupted"}
#: The command line's main function, which :func:`drive` calls.
ENTRY = "ngincompat.cli:main"
#: The program of a try run alone: the command line, Ctrl-C taken as from a terminal even
#: where the corpus runs in the background (whose shell ignores Ctrl-C and would pass that
#: on: the job would rightly ignore the interrupt tries' SIGINT).
ALONE = ("import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
         "from ngincompat.cli import main; sys.exit(main(sys.argv[1:]))")
#: Seconds a try may take before it is a hang (an accepted value runs in seconds).
LIMIT = 600.0
#: What ``--quick`` tries: every value of two parameters of the cube, and one environment
#: variable's.
QUICK_TRIES = (("cube", "side"), ("cube", "nu"))


@dataclass
class Try:
    """One input: ``group`` (a scene, "environment" or "paper"), ``key`` (the parameter,
    variable or option), ``value`` (as typed), the command line's ``args`` (after
    ``ngincompat``), the ``env`` it runs under, and its ``outcome``, ``code``, ``seconds``
    and the last line of its standard error (``message``) once it ran."""

    group: str
    key: str
    value: str
    args: list
    env: dict = field(default_factory=dict)
    outcome: str = ""
    code: int | None = None
    seconds: float | None = None
    message: str = ""


def boundary_values(kind: _Kind) -> list[str]:
    """The ends of a number kind's declared range as texts: each closed end and the nearest
    number past it, each open end and the nearest number inside it (for a float; for an
    integer, the end and the next integer past it)."""
    kind = kind.floats if isinstance(kind, _WordsOrFloats) else kind
    item = kind.item if isinstance(kind, _Floats) else kind
    span = item.range
    if span is None:
        return []
    values = []
    for end, is_open, outward in ((span.low, span.low_open, -math.inf),
                                  (span.high, span.high_open, math.inf)):
        if end is None:
            continue
        if isinstance(item, _Int):
            values += [str(int(end)), str(int(end) + (1 if outward > 0 else -1))]
        else:
            inward = math.nextafter(end, -outward)
            values += [repr(end), repr(math.nextafter(end, outward) if not is_open else inward)]
    texts = []
    for v in values:
        text = ",".join([v] * (kind.length or 1)) if isinstance(kind, _Floats) else v
        if text not in texts:
            texts.append(text)
    return texts


def numeric_parameters(cls: type[Scene]) -> list[str]:
    """The keys of a scene's numeric parameters (numbers, tuples of numbers, words or
    numbers)."""
    return [key for key, p in cls.declarations().items()
            if isinstance(p.kind, (_Float, _Int, _Floats, _WordsOrFloats))]


def parameter_tries(scene: str, key: str, folder: str | os.PathLike) -> list[Try]:
    """The tries of one parameter of ``scene``, their runs in ``folder``/<k>."""
    from ngincompat.scenes import SCENES

    cls = SCENES[scene]
    p = cls.declarations()[key]
    kind = p.kind.floats if isinstance(p.kind, _WordsOrFloats) else p.kind
    hostile = HOSTILE + (HOSTILE_INT if isinstance(p.kind, _Int) else ())
    if isinstance(kind, _Floats):
        hostile = tuple(",".join([v] * (kind.length or 1)) if v else v for v in hostile)
    values = list(dict.fromkeys([*hostile, *boundary_values(p.kind)]))
    preset = ["--preset", "preview"] if "preview" in cls.preset_names() else []
    quick = [w for k, v in QUICK.get(scene, {}).items() if k != key
             for w in ("--set", f"{k}={v}")]
    return [Try(scene, key, value, ["run", scene, *preset, *quick, "--set", f"{key}={value}",
                                    "--out", str(Path(folder) / f"{key}-{k}")])
            for k, value in enumerate(values)]


def environment_tries(folder: str | os.PathLike) -> list[Try]:
    """A try per value of each variable of :data:`ENVIRONMENT`."""
    return [Try("environment", name, value,
                [*ENVIRONMENT_COMMAND, "--out", str(Path(folder) / f"{name}-{k}"), "-q"],
                {name: value})
            for name, values in ENVIRONMENT.items() for k, value in enumerate(values)]


def paper_tries(folder: str | os.PathLike) -> list[Try]:
    """A try per value of each option of :data:`PAPER_OPTIONS`."""
    tries = []
    for option, values in PAPER_OPTIONS.items():
        for k, value in enumerate(values):
            only = [] if option == "--only" else ["--only", PAPER_SECTIONS]
            tries.append(Try("paper", option, value,
                             ["paper", option, value, *only, "--out",
                              str(Path(folder) / f"paper{option}-{k}"), "-q"]))
    return tries


def drive() -> None:
    """The process that runs a list of tries (JSON on its standard input: ``entry``, the
    command line's main function as "module:name", and ``tries``, a list of argument lists):
    for each, a line "started", the function with its standard output and error captured,
    and a line with its exit code, whether a traceback was printed, and the last line of
    its standard error; while the try writes to its standard error (its progress), a line
    "alive" at most every :data:`BEAT` seconds."""
    given = json.loads(sys.stdin.read())
    records = os.fdopen(os.dup(1), "w")     # what Netgen prints to file 1 goes elsewhere
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
    module, _, name = given["entry"].partition(":")
    main = getattr(importlib.import_module(module), name)

    def record(**fields: Any) -> None:
        records.write(json.dumps(fields) + "\n")
        records.flush()

    for k, args in enumerate(given["tries"]):
        record(k=k)
        err = _Heartbeat(lambda k=k: record(k=k, alive=True))
        start = time.perf_counter()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                code = main(args)
            except BaseException:       # what the program's own exit would print
                traceback.print_exc()
                code = 1
        text = err.getvalue()
        record(k=k, code=code, seconds=time.perf_counter() - start,
               traceback="Traceback (most recent call last)" in text,
               message=(text.strip().splitlines() or [""])[-1][:300])


#: Seconds between the "alive" lines of a try that reports progress.
BEAT = 1.0
#: A try stopped at the limit is a hang when its last progress is older than this (or than
#: half the limit); a try still reporting progress then is a long run stopped at the limit
#: ("time limit").
QUIET = 120.0


class _Heartbeat(io.StringIO):
    """A captured standard error that calls ``beat`` on a write, at most every :data:`BEAT`
    seconds."""

    def __init__(self, beat: Callable[..., object]) -> None:
        super().__init__()
        self.beat, self.last = beat, -math.inf

    def write(self, text: str) -> int:
        if time.perf_counter() - self.last >= BEAT:
            self.last = time.perf_counter()
            self.beat()
        return super().write(text)


def _classify(record: Mapping[str, Any], out: str | None) -> str:
    """The outcome of a try from its exit code, whether it printed a traceback, and the
    metrics of its results.json in ``out`` (each a finite number after exit 0)."""
    if record["traceback"]:
        return "traceback"
    outcome = CODES.get(record["code"], "other")
    if outcome == "done" and out is not None and (Path(out) / "results.json").is_file():
        metrics = json.loads((Path(out) / "results.json").read_text()).get("metrics", {})
        if not all(_finite(v) for v in metrics.values()):
            return "non-finite"
    return outcome


def _finite(value: object) -> bool:
    """A metric's value is a finite number (a list: each of its items)."""
    if isinstance(value, list):
        return all(_finite(v) for v in value)
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value)) or isinstance(value, (bool, str))


def _out_of(args: Sequence[str]) -> str | None:
    return args[args.index("--out") + 1] if "--out" in args else None


def run_in_one_process(tries: Sequence[Try], limit: float = LIMIT, entry: str = ENTRY) -> None:
    """Run ``tries`` (of one parameter, no environment of their own) with :func:`drive` on
    the command line's ``entry`` ("module:function"), each try's outcome set; a try that
    hangs or crashes the process is recorded, and the process started again after it."""
    pending = list(tries)
    while pending:
        process = subprocess.Popen(
            [sys.executable, "-c", "from ngincompat.studies.corpus import drive; drive()"],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            text=True, start_new_session=True)
        # stdin: a pipe (stdin=PIPE)
        process.stdin.write(  # type: ignore[union-attr]
            json.dumps({"entry": entry, "tries": [t.args for t in pending]}))
        process.stdin.close()  # type: ignore[union-attr]
        done = _follow(process, pending, limit)
        if not done:        # the driver itself did not start: no try can run
            _set(pending[0], "other", process.returncode, 0.0, "the driver ended at its start")
            done = 1
        pending = pending[done:]


def _follow(process: subprocess.Popen, tries: Sequence[Try], limit: float) -> int:
    """Read the driver's lines, setting each try's outcome; returns how many tries it ended
    (a try it did not end, having hung or crashed, counted with its outcome)."""
    lines: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: [*map(lines.put, process.stdout),  # type: ignore[arg-type]
                                     lines.put("")],  # type: ignore[func-returns-value]
                     daemon=True).start()
    current, started, ended = None, time.perf_counter(), 0
    alive = started
    while True:
        try:
            line = lines.get(timeout=None if current is None
                             else max(limit - (time.perf_counter() - started), 0.0))
        except queue.Empty:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            quiet = time.perf_counter() - alive
            if quiet < min(QUIET, limit / 2):
                # current: a try's index (the wait has a timeout only while one runs)
                _set(tries[current],  # type: ignore[call-overload, index]
                     "time limit", None, limit,
                     f"still reporting progress at {limit:g} s (last {quiet:.0f} s before)")
            else:
                _set(tries[current], "hang", None, limit,  # type: ignore[call-overload, index]
                     f"no end within {limit:g} s, no progress for {quiet:.0f} s")
            return current + 1  # type: ignore[operator]
        if not line:
            code = process.wait()
            if current is None:
                return ended
            what = "signal" if code < 0 else "other"
            why = (f"killed by {signal.Signals(-code).name}" if code < 0
                   else f"the process ended with exit code {code}")
            _set(tries[current], what, code, time.perf_counter() - started, why)
            return current + 1
        record = json.loads(line)
        if record.get("alive"):
            alive = time.perf_counter()
            continue
        if "code" not in record:
            current, started = record["k"], time.perf_counter()
            alive = started
            continue
        attempt = tries[record["k"]]
        _set(attempt, _classify(record, _out_of(attempt.args)), record["code"],
             record["seconds"], record["message"])
        current, ended = None, record["k"] + 1


def _set(attempt: Try, outcome: str, code: int | None, seconds: float, message: str) -> None:
    attempt.outcome, attempt.code, attempt.seconds, attempt.message = (
        outcome, code, round(seconds, 2), message)


def run_alone(attempt: Try, limit: float = LIMIT, interrupt: Interrupt | None = None) -> Try:
    """Run one try in a process of its own (the command line, :data:`ALONE`, its ``env`` on
    top of this process's), with ``interrupt`` (an :class:`Interrupt`) sent to its process
    group; sets its outcome."""
    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as err:
        process = subprocess.Popen([sys.executable, "-c", ALONE, *attempt.args],
                                   env={**os.environ, **attempt.env}, text=True,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                   start_new_session=True)
        try:
            _signal_when(process, interrupt, err)
            remaining = limit - (time.perf_counter() - start)
            err.write(process.communicate(timeout=max(remaining, 1.0))[1])
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            _set(attempt, "hang", None, limit, f"no end within {limit:g} s")
            return attempt
        err.seek(0)
        text = err.read()
    code = process.returncode
    out = _out_of(attempt.args)
    record = {"code": code, "traceback": "Traceback (most recent call last)" in text}
    outcome = "signal" if code < 0 else _classify(record, out)
    if outcome == "interrupted" and out is not None and any(Path(out).rglob(".ngincompat.lock")):
        outcome = "lock left"
    _set(attempt, outcome, code, time.perf_counter() - start,
         (text.strip().splitlines() or [""])[-1][:300])
    return attempt


def _signal_when(process: subprocess.Popen, interrupt: Interrupt | None, err: IO[str]) -> None:
    """Copy the process's standard error into ``err`` until a line contains
    ``interrupt.when``, then send its signal to the process group ``interrupt.delay``
    seconds later (nothing without ``interrupt``)."""
    if interrupt is None:
        return
    for line in process.stderr:  # type: ignore[union-attr]  # stderr=PIPE
        err.write(line)
        if interrupt.when in line:
            time.sleep(interrupt.delay)
            os.killpg(process.pid, interrupt.signum)
            return


def interrupt_tries(folder: str | os.PathLike) -> list[tuple[Try, Interrupt]]:
    """A try per :data:`INTERRUPTS` entry, with the interrupt it receives."""
    return [(Try("paper", "interrupt", i.name,
                 [*i.args, "--out", str(Path(folder) / f"interrupt-{k}")]), i)
            for k, i in enumerate(INTERRUPTS)]


def run_corpus(folder: str | os.PathLike, quick: bool = False, limit: float = LIMIT, jobs: int = 1,
               progress: Progress = SILENT) -> list[Try]:
    """Every try of the corpus (``quick``: :data:`QUICK_TRIES` and the environment's first
    variable), their runs in ``folder``, the parameters' tries ``jobs`` processes side by
    side; returns the tries with their outcomes."""
    from ngincompat.scenes import SCENES

    folder = Path(folder)
    groups = (QUICK_TRIES if quick else
              [(scene, key) for scene, cls in SCENES.items() for key in numeric_parameters(cls)])

    def one(group: tuple[str, str]) -> list[Try]:
        scene, key = group
        batch = parameter_tries(scene, key, folder / scene)
        run_in_one_process(batch, limit)
        progress.line(f"{scene} {key}: {_counts_text(batch)}")
        return batch

    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        tries = [t for batch in pool.map(one, groups) for t in batch]
    alone = environment_tries(folder / "environment")
    if quick:
        alone = [t for t in alone if t.key == next(iter(ENVIRONMENT))]
    else:
        alone += paper_tries(folder / "paper")
    for attempt in alone:
        tries.append(run_alone(attempt, limit))
    progress.line(f"environment and paper options: {_counts_text(alone)}")
    if not quick:
        for attempt, interrupt in interrupt_tries(folder / "paper"):
            tries.append(run_alone(attempt, limit, interrupt))
            progress.line(f"paper {interrupt.name}: {attempt.outcome}")
    return tries


def _counts_text(tries: Iterable[Try]) -> str:
    counts = Counter(t.outcome for t in tries)
    return ", ".join(f"{counts[o]} {o}" for o in OUTCOMES if counts[o])


def count_rows(tries: Sequence[Try]) -> list[dict[str, Any]]:
    """One row per group (scene, "environment", "paper") and a total: the tries and how
    many ended in each outcome."""
    groups = list(dict.fromkeys(t.group for t in tries))
    rows = []
    for group in [*groups, "total"]:
        chosen = [t for t in tries if group in ("total", t.group)]
        counts = Counter(t.outcome for t in chosen)
        rows.append({"group": group,
                     "inputs": len({t.key for t in chosen}) if group != "total" else None,
                     "tries": len(chosen), **{o: counts[o] for o in OUTCOMES}})
    return rows


#: The columns of the tables :func:`main` writes.
COUNT_COLUMNS = ("group", "inputs", "tries", *OUTCOMES)
TRY_COLUMNS = ("group", "key", "value", "outcome", "code", "seconds", "message")


def main(quick: bool = False, out: str | os.PathLike | None = None, jobs: int = 1,
         progress: Progress | None = None) -> list[str]:
    """``ngincompat bench inputs``: :func:`run_corpus` (its runs in ``out``/runs, emptied
    first, or in a scratch folder; ``jobs`` processes side by side); returns the lines to
    print. With ``out`` the counts are written as ``corpus``, every try as ``tries`` and the
    defects as ``defects`` (.md, .csv, .json)."""
    progress = progress or Progress()
    with contextlib.ExitStack() as stack:
        runs = (Path(out) / "runs" if out is not None
                else Path(stack.enter_context(tempfile.TemporaryDirectory())))
        # the runs of an earlier corpus there would refuse this one's as other runs
        shutil.rmtree(runs, ignore_errors=True)
        tries = run_corpus(runs, quick=quick, jobs=jobs, progress=progress)
    rows = count_rows(tries)
    records = [{c: getattr(t, c) for c in TRY_COLUMNS} for t in tries]
    defects = [r for r in records if r["outcome"] in DEFECTS]
    if out is not None:
        tables.write(out, "corpus", rows, list(COUNT_COLUMNS))
        tables.write(out, "tries", records, list(TRY_COLUMNS), {"seconds": "s"})
        tables.write(out, "defects", defects, list(TRY_COLUMNS), {"seconds": "s"})
    return [tables.markdown(rows, list(COUNT_COLUMNS)), "",
            f"defects: {len(defects)}" + (":" if defects else ""),
            *(f"  {r['group']} {r['key']}={r['value']!r}: {r['outcome']} ({r['message']})"
              for r in defects)]
