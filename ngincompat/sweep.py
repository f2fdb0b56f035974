"""Parameter sweeps: ``ngincompat sweep run FILE.toml --out DIR`` and ``ngincompat sweep plot``.

A sweep file (TOML) names a scene, the parameters that stay fixed, those that vary and the
metrics to collect::

    scene = "cube"
    metrics = ["strain_energy", "G_error_L2_rel"]   # optional; default: every metric

    [fixed]                                         # scene parameters of every case
    maxh = 0.5
    outputs = "none"

    [vary]                                          # full product across the keys
    order = {start = 1, stop = 3, step = 1}         # ints, stop included: 1, 2, 3
    nu = [0.3, 0.4, 0.45]

    [zip]                                           # varied together (equal lengths),
    a = [0.1, 0.25]                                 # then producted with [vary]
    side = [1.0, 2.0]

A value of ``[vary]`` or ``[zip]`` is a list or a range: ``{start, stop, num}`` is
``numpy.linspace(start, stop, num)``, ``{start, stop, step}`` the integers from ``start`` to
``stop`` (included when a step lands on it) by ``step``. The cases are the product of the rows
of ``[zip]`` (outermost) with the values of ``[vary]`` in the file's order, the last key
varying fastest. The file itself is checked when it is read (unknown keys or parameter names,
empty lists, unequal ``[zip]`` lengths, an unknown scene); the parameter *values* are checked
by the scene, case by case, so that a bad value makes only its case fail.

Case ``i`` runs ``scene.run(DIR/case_<i>_<hash>, quiet=True)``: its folder name holds the case
index (three digits or more) and a short hash of the scene and all its parameters. A case is
done when its folder holds a results.json of the same scene and parameters without an error;
done cases are never run again (a second run of a sweep, with or without ``--resume``, runs
the cases that are missing or failed). A folder that holds a *different* sweep is refused
unless ``--resume`` is given, which then reuses the finished cases they share.

Cases run in local processes ("spawn"; ``--workers``, NGSolve threads per worker so that
workers x threads <= cores) or, with ``--scheduler ADDRESS``, on an existing Dask cluster whose
workers see the same file system and can import ngincompat (give the workers one thread each:
a case uses NGSolve's task manager, ``--threads`` NGSolve threads, default 1).

The table of the sweep, ``DIR/sweep.csv`` (and ``DIR/sweep.parquet`` when pyarrow is
installed), has the columns ``case, status, <varied parameters>, <metrics>, seconds, error``,
one row per finished case in case order; it is rewritten atomically whenever a case finishes,
so an interrupted sweep keeps every finished case. A case that raises becomes a row with
status ``failed`` and the error; its traceback is in ``DIR/case_.../error.txt``.
``DIR/sweep.json`` records the sweep and its cases.
"""

import concurrent.futures
import csv
import dataclasses
import hashlib
import itertools
import json
import logging
import math
import multiprocessing
import os
import sys
import time
import traceback
import uuid
from collections import deque
from pathlib import Path

from . import io
from .errors import ParameterError

log = logging.getLogger(__name__)

SWEEP_KEYS = ("scene", "fixed", "vary", "zip", "metrics")
RANGE_KEYS = ("start", "stop", "num", "step")
TABLE = "sweep.csv"
PARQUET = "sweep.parquet"
RECORD = "sweep.json"
FIXED_COLUMNS = ("case", "status", "seconds", "error")


# --------------------------------------------------------------------------- the sweep file

@dataclasses.dataclass(frozen=True)
class Case:
    """One run of a sweep.

    Attributes
    ----------
    index : int
        Position in the sweep (row order of the table).
    scene : str
        Name of the scene.
    params : dict
        Every parameter handed to the scene's ``from_settings`` (fixed and varied).
    varied : dict
        The varied parameters alone (the table's parameter columns).
    """

    index: int
    scene: str
    params: dict
    varied: dict

    @property
    def key(self):
        """Short hash of the scene and the parameters."""
        text = json.dumps({"scene": self.scene, "params": self.params}, sort_keys=True)
        return hashlib.sha1(text.encode()).hexdigest()[:8]

    @property
    def name(self):
        """Folder name of the case, ``case_<index>_<hash>``."""
        return f"case_{self.index:03d}_{self.key}"


@dataclasses.dataclass(frozen=True)
class Sweep:
    """A validated sweep file.

    Attributes
    ----------
    scene : str
        Name of the scene.
    fixed : dict
        Parameters shared by every case.
    vary : dict
        Parameter -> list of values; the cases take the full product across the keys.
    zipped : dict
        Parameter -> list of values, all of the same length, varied together.
    metrics : tuple of str or None
        Metrics to collect (None: every metric of the results).
    """

    scene: str
    fixed: dict
    vary: dict
    zipped: dict
    metrics: tuple | None = None

    @property
    def varied(self):
        """Names of the varied parameters, in the table's order."""
        return [*self.zipped, *self.vary]

    def cases(self):
        """The cases: rows of ``zipped`` (outer) times the product of ``vary``.

        Returns
        -------
        list of Case
        """
        zip_rows = [dict(zip(self.zipped, values, strict=True))
                    for values in zip(*self.zipped.values(), strict=True)]
        vary_rows = [dict(zip(self.vary, values, strict=True))
                     for values in itertools.product(*self.vary.values())]
        cases = []
        for index, (z, v) in enumerate(itertools.product(zip_rows or [{}], vary_rows)):
            varied = {**z, **v}
            cases.append(Case(index, self.scene, {**self.fixed, **varied}, varied))
        return cases


def load_sweep(path):
    """Read and validate a sweep file.

    Parameters
    ----------
    path : path-like
        The TOML file.

    Returns
    -------
    Sweep

    Raises
    ------
    ParameterError
        The file cannot be read, is not TOML, or breaks a rule of the format; the message
        names the key.
    """
    try:
        import tomllib
    except ImportError:  # Python 3.10
        try:
            import tomli as tomllib
        except ImportError:
            raise ParameterError("reading a sweep file needs Python >= 3.11 (tomllib) or "
                                 "the tomli package") from None
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as err:
        raise ParameterError(f"sweep file {path} cannot be read: {err}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ParameterError(f"sweep file {path} is not valid TOML: {err}") from None
    return parse_sweep(data, source=str(path))


def parse_sweep(data, source="sweep"):
    """Validate the contents of a sweep file (a dict as ``tomllib`` returns it).

    Parameters
    ----------
    data : dict
        Keys ``scene``, ``fixed``, ``vary``, ``zip``, ``metrics``.
    source : str
        Name of the file, for the error messages.

    Returns
    -------
    Sweep
    """
    def fail(message):
        raise ParameterError(f"{source}: {message}")

    for key in data:
        if key not in SWEEP_KEYS:
            fail(f"unknown key {key!r}: allowed {', '.join(SWEEP_KEYS)}")
    if "scene" not in data:
        fail("missing key 'scene' (the name of the scene, e.g. scene = \"cube\")")
    scene = data["scene"]
    from .scenes import SCENES
    if not isinstance(scene, str) or scene not in SCENES:
        fail(f"scene = {scene!r} is unknown: allowed {', '.join(sorted(SCENES))}")
    allowed = SCENES[scene].parameters()

    tables = {}
    for section in ("fixed", "vary", "zip"):
        table = data.get(section, {})
        if not isinstance(table, dict):
            fail(f"{section} must be a table ([{section}]), not {table!r}")
        for key in table:
            if key not in allowed:
                fail(f"{section}.{key}: unknown parameter of scene {scene!r}: allowed "
                     f"{', '.join(sorted(allowed))}")
            for other, seen in tables.items():
                if key in seen:
                    fail(f"{section}.{key}: {key!r} is also set in [{other}]")
        tables[section] = table

    fixed = {}
    for key, value in tables["fixed"].items():
        if not _is_scalar(value):
            fail(f"fixed.{key} = {value!r} must be a single value (vary it in [vary])")
        fixed[key] = value
    vary = {key: _values(f"vary.{key}", raw, fail) for key, raw in tables["vary"].items()}
    zipped = {key: _values(f"zip.{key}", raw, fail) for key, raw in tables["zip"].items()}
    lengths = {key: len(values) for key, values in zipped.items()}
    if len(set(lengths.values())) > 1:
        fail("the lists of [zip] must have equal lengths: "
             + ", ".join(f"zip.{key} has {n}" for key, n in lengths.items()))

    metrics = data.get("metrics")
    if metrics is not None:
        if not isinstance(metrics, list) or not metrics:
            fail(f"metrics = {metrics!r} must be a non-empty list of metric names")
        for name in metrics:
            if not isinstance(name, str) or not name:
                fail(f"metrics: {name!r} is not a metric name")
            if name in FIXED_COLUMNS or name in vary or name in zipped:
                fail(f"metrics: {name!r} is also the name of a column of the table")
        if len(set(metrics)) < len(metrics):
            fail(f"metrics = {metrics!r} names a metric twice")
        metrics = tuple(metrics)
    return Sweep(scene, fixed, vary, zipped, metrics)


def _is_scalar(value):
    return isinstance(value, (str, int, float, bool))


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _values(name, raw, fail):
    """The list of values of one varied parameter: a list or a range table."""
    if isinstance(raw, dict):
        values = _range(name, raw, fail)
    elif isinstance(raw, list):
        values = raw
        for i, value in enumerate(values):
            if not _is_scalar(value):
                fail(f"{name}[{i}] = {value!r} must be a single value")
    else:
        fail(f"{name} = {raw!r} must be a list of values or a range {{start=, stop=, num=}} "
             "or {start=, stop=, step=}")
    if not values:
        fail(f"{name} is an empty list")
    return list(values)


def _range(name, spec, fail):
    for key in spec:
        if key not in RANGE_KEYS:
            fail(f"{name}.{key}: unknown key of a range: allowed start, stop and num or step")
    for key in ("start", "stop"):
        if key not in spec:
            fail(f"{name}: a range needs {key}")
    if ("num" in spec) == ("step" in spec):
        fail(f"{name}: a range needs either num (evenly spaced numbers) or step (integers)")
    start, stop = spec["start"], spec["stop"]
    if "num" in spec:
        import numpy as np
        num = spec["num"]
        if not (isinstance(num, int) and not isinstance(num, bool) and num >= 1):
            fail(f"{name}.num = {num!r} must be an integer >= 1")
        for key in ("start", "stop"):
            if not _is_number(spec[key]):
                fail(f"{name}.{key} = {spec[key]!r} must be a number")
        return [float(v) for v in np.linspace(start, stop, num)]
    step = spec["step"]
    for key in ("start", "stop", "step"):
        value = spec[key]
        if not (isinstance(value, int) and not isinstance(value, bool)):
            fail(f"{name}.{key} = {value!r} must be an integer (use num for evenly spaced "
                 "numbers)")
    if step == 0:
        fail(f"{name}.step = 0 must not be zero")
    values = list(range(start, stop + (1 if step > 0 else -1), step))
    if not values:
        fail(f"{name}: the range from {start} to {stop} by {step} is empty")
    return values


# --------------------------------------------------------------------------- one case

def _run_case(task):
    """Run one case (in a worker); returns its outcome and never raises.

    Parameters
    ----------
    task : dict
        ``scene``, ``params``, ``folder`` and ``threads`` (NGSolve threads, or None to keep the
        worker's setting).

    Returns
    -------
    dict
        ``status`` ("ok" or "failed"), ``metrics`` (as written to results.json), ``seconds``
        (the sum of the run's timings in results.json; for a failed case the wall time until
        the failure), ``error`` (message, or None).
    """
    start = time.perf_counter()
    folder = Path(task["folder"])
    try:
        if task.get("threads"):
            import ngsolve
            ngsolve.SetNumThreads(task["threads"])
        from .scenes import get_scene
        scene = get_scene(task["scene"]).from_settings(task["params"])
        scene.run(folder, quiet=True)
        results = io.read_json(folder / "results.json")
    except Exception as err:
        seconds = time.perf_counter() - start
        try:
            with io.atomic_path(folder / "error.txt") as tmp:
                tmp.write_text(traceback.format_exc())
        except OSError:
            pass
        return {"status": "failed", "metrics": {}, "seconds": seconds,
                "error": _message(err)}
    (folder / "error.txt").unlink(missing_ok=True)
    return {"status": "ok", "metrics": results["metrics"], "seconds": _seconds(results),
            "error": None}


def _init_worker(threads):
    """Initializer of a local worker process: its number of NGSolve threads."""
    import ngsolve
    ngsolve.SetNumThreads(threads)


def _seconds(results):
    """Run time of a case from its results.json: the sum of its timings."""
    return sum(v for v in results.get("timings", {}).values() if v is not None)


def _message(err):
    text = " ".join(str(err).split())
    return f"{type(err).__name__}: {text}" if text else type(err).__name__


def _settings(case):
    """The parameters the case's results.json must hold (None if the scene rejects them)."""
    from .scenes import get_scene
    try:
        settings = get_scene(case.scene).from_settings(case.params).settings()
    except Exception:
        return None
    return json.loads(json.dumps(settings))


def _finished(case, folder):
    """The results of ``case`` if ``folder`` holds them complete, else None."""
    path = folder / "results.json"
    if not path.is_file():
        return None
    try:
        results = io.read_json(path)
    except (OSError, ValueError):
        return None
    if (results.get("scene") != case.scene or "error" in results
            or not results.get("solver", {}).get("converged", False)):
        return None
    expected = _settings(case)
    if expected is None or results.get("params") != expected:
        return None
    return results


# --------------------------------------------------------------------------- executors

class _Local:
    """Local worker processes ("spawn") with a fixed number of NGSolve threads each."""

    def __init__(self, workers, threads):
        cores = os.cpu_count() or 1
        self.window = workers
        threads = threads or max(1, cores // workers)
        if workers * threads > cores:
            log.warning("%d workers x %d NGSolve threads exceed the %d cores", workers,
                        threads, cores)
        log.info("local pool: %d workers x %d NGSolve threads", workers, threads)
        self.executor = concurrent.futures.ProcessPoolExecutor(
            max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
            initializer=_init_worker, initargs=(threads,))

    def submit(self, task):
        return self.executor.submit(_run_case, task)

    def wait(self, futures):
        done, _ = concurrent.futures.wait(futures, return_when=concurrent.futures.FIRST_COMPLETED)
        return done

    def close(self, cancel):
        self.executor.shutdown(wait=not cancel, cancel_futures=cancel)


class _Dask:
    """An existing Dask cluster, by the address of its scheduler (or a Client)."""

    def __init__(self, scheduler, workers, threads):
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
        log.info("Dask cluster %s: up to %d cases at a time, %d NGSolve threads each",
                 self.client.scheduler.address, self.window, self.threads)
        self.futures = set()

    def submit(self, task):
        key = f"ngincompat-{Path(task['folder']).name}-{uuid.uuid4().hex[:8]}"
        future = self.client.submit(_run_case, {**task, "threads": self.threads}, key=key,
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
    columns : list of str
        Columns of the table.
    rows : list of dict
        The table: one row per finished case, in case order.
    computed : int
        Cases run by this call.
    reused : int
        Cases taken over from an earlier run (their results.json).
    pending : int
        Cases left to run (``max_cases``).
    """

    out: Path
    columns: list
    rows: list
    computed: int
    reused: int
    pending: int

    @property
    def ok(self):
        """Number of finished cases."""
        return sum(row["status"] == "ok" for row in self.rows)

    @property
    def failed(self):
        """Number of failed cases."""
        return sum(row["status"] == "failed" for row in self.rows)


def run_sweep(sweep, out, workers=None, scheduler=None, resume=False, quiet=False,
              threads=None, max_cases=None):
    """Run the cases of a sweep that are not done yet and write the table.

    Parameters
    ----------
    sweep : Sweep
        From :func:`load_sweep` or :func:`parse_sweep`.
    out : path-like
        The sweep folder: one folder per case, the table, sweep.json.
    workers : int, optional
        Local worker processes (default min(2, cases to run)); with ``scheduler``: cases
        submitted at a time (default: the cluster's threads).
    scheduler : str or dask.distributed.Client, optional
        Run on this Dask cluster instead of local processes.
    resume : bool
        Accept a folder that holds a different sweep, reusing the finished cases they share.
        (An unchanged sweep always resumes: done cases are skipped, failed ones retried.)
    quiet : bool
        No progress bar (it is also off when stderr is not a terminal).
    threads : int, optional
        NGSolve threads per case (default: cores // workers locally, 1 on Dask).
    max_cases : int, optional
        Run at most this many cases now; the rest stay for the next run.

    Returns
    -------
    SweepReport
    """
    for name, value, low in (("workers", workers, 1), ("threads", threads, 1),
                             ("max_cases", max_cases, 0)):
        if value is not None and not (isinstance(value, int) and value >= low):
            raise ParameterError(f"{name} = {value!r} is out of range: allowed an integer "
                                 f">= {low}")
    out = Path(out).resolve()
    cases = sweep.cases()
    _check_record(out, sweep, cases, resume)
    out.mkdir(parents=True, exist_ok=True)
    io.write_json(out / RECORD, _record(sweep, cases))

    rows = {}
    todo = []
    for case in cases:
        results = _finished(case, out / case.name)
        if results is None:
            todo.append(case)
        else:
            rows[case.index] = _row(case, "ok", results.get("metrics", {}), _seconds(results),
                                    None)
    reused = len(rows)
    if max_cases is not None:
        todo = todo[:max_cases]
    log.info("sweep %s: %d cases, %d done, %d to run", out, len(cases), reused, len(todo))
    _write_table(out, sweep, rows)

    computed = 0
    if todo:
        if scheduler is not None:
            backend = _Dask(scheduler, workers, threads)
        else:
            backend = _Local(workers or min(2, len(todo)), threads)
        bar = _progress(len(cases), reused, quiet)
        counts = {"done": reused, "failed": 0}
        tasks = deque(todo)
        running = {}
        finished = False
        try:
            while tasks or running:
                while tasks and len(running) < backend.window:
                    case = tasks.popleft()
                    task = {"scene": case.scene, "params": case.params,
                            "folder": str(out / case.name), "threads": None}
                    running[backend.submit(task)] = case
                bar.set_postfix(**counts, running=len(running))
                for future in backend.wait(set(running)):
                    case = running.pop(future)
                    outcome = _outcome(future)
                    rows[case.index] = _row(case, outcome["status"], outcome["metrics"],
                                            outcome["seconds"], outcome["error"])
                    computed += 1
                    _log_case(case, outcome)
                    _write_table(out, sweep, rows)
                    counts["done" if outcome["status"] == "ok" else "failed"] += 1
                    bar.set_postfix(**counts, running=len(running), refresh=False)
                    bar.update(1)
            finished = True
        finally:
            backend.close(cancel=not finished)
            bar.close()
            if not finished:
                log.warning("sweep interrupted with %d of %d cases finished; the table %s "
                            "holds them; run the sweep again to go on", len(rows), len(cases),
                            out / TABLE)
    columns, table = _table(sweep, rows)
    return SweepReport(out, columns, table, computed, reused,
                       len(cases) - reused - computed)


def _outcome(future):
    try:
        return future.result()
    except Exception as err:  # the worker died (or the cluster lost it)
        return {"status": "failed", "metrics": {}, "seconds": None, "error": _message(err)}


def _log_case(case, outcome):
    if outcome["status"] == "ok":
        log.info("%s done in %.2f s", case.name, outcome["seconds"])
    else:
        log.warning("%s (%s) failed: %s", case.name,
                    ", ".join(f"{k}={v!r}" for k, v in case.varied.items()), outcome["error"])


def _progress(total, initial, quiet):
    from tqdm import tqdm
    return tqdm(total=total, initial=initial, desc="sweep", unit="case",
                disable=quiet or not sys.stderr.isatty())


def _row(case, status, metrics, seconds, error):
    return {"case": case.index, "status": status, "params": case.varied,
            "metrics": metrics if status == "ok" else {}, "seconds": seconds, "error": error}


def _record(sweep, cases):
    return {"scene": sweep.scene, "fixed": sweep.fixed, "vary": sweep.vary,
            "zip": sweep.zipped, "metrics": list(sweep.metrics) if sweep.metrics else None,
            "varied": sweep.varied,
            "cases": [{"case": c.index, "folder": c.name, "params": c.params} for c in cases],
            **io.provenance()}


def _check_record(out, sweep, cases, resume):
    """Refuse a folder that holds another sweep, unless resuming."""
    path = out / RECORD
    if resume or not path.is_file():
        return
    try:
        old = io.read_json(path)
    except (OSError, ValueError):
        return
    mine = json.loads(json.dumps(_record(sweep, cases)["cases"]))
    if old.get("cases") != mine:
        raise ParameterError(
            f"--out {out} holds a different sweep ({len(old.get('cases', []))} cases of scene "
            f"{old.get('scene')!r}): pass --resume to reuse its finished cases, or choose "
            "another folder")


# --------------------------------------------------------------------------- the table

def _table(sweep, rows):
    """Columns and flat rows (case order) of the table."""
    ordered = [rows[i] for i in sorted(rows)]
    if sweep.metrics is not None:
        metrics = list(sweep.metrics)
        missing = [m for m in metrics
                   if any(r["status"] == "ok" and m not in r["metrics"] for r in ordered)]
        if missing:
            log.warning("metrics %s are not in the results of every finished case (available: "
                        "%s)", ", ".join(missing),
                        ", ".join(next(r["metrics"] for r in ordered if r["status"] == "ok")))
    else:
        metrics = list(dict.fromkeys(m for r in ordered for m in r["metrics"]))
    columns = ["case", "status", *sweep.varied, *metrics, "seconds", "error"]
    table = []
    for r in ordered:
        table.append({"case": r["case"], "status": r["status"], **r["params"],
                      **{m: r["metrics"].get(m) for m in metrics},
                      "seconds": r["seconds"], "error": r["error"]})
    return columns, table


def _write_table(out, sweep, rows):
    """Write sweep.csv (and sweep.parquet if pyarrow is importable) atomically."""
    columns, table = _table(sweep, rows)
    with io.atomic_path(out / TABLE) as tmp:
        with open(tmp, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            writer.writeheader()
            for row in table:
                writer.writerow({k: "" if v is None else v for k, v in row.items()})
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return
    arrays = {}
    for column in columns:
        values = [row[column] for row in table]
        try:
            arrays[column] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types: as text
            arrays[column] = pa.array([None if v is None else str(v) for v in values])
    with io.atomic_path(out / PARQUET) as tmp:
        pq.write_table(pa.table(arrays), str(tmp))


def read_table(sweep_dir):
    """The table of a sweep folder (sweep.csv), numbers parsed.

    Parameters
    ----------
    sweep_dir : path-like

    Returns
    -------
    columns : list of str
    rows : list of dict
        Empty cells are None; cells that parse as int or float are numbers.
    """
    path = Path(sweep_dir) / TABLE
    if not path.is_file():
        raise ParameterError(f"{sweep_dir}: no {TABLE} (is it the --out of a sweep run?)")
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = [{k: _parse(v) for k, v in row.items()} for row in reader]
        return list(reader.fieldnames or []), rows


def _parse(text):
    if text == "":
        return None
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


# --------------------------------------------------------------------------- the plot

def plot_sweep(sweep_dir, metric, x, out, hue=None, where=(), logx=False, logy=False):
    """Draw a metric against a varied parameter, one curve per value of another.

    Parameters
    ----------
    sweep_dir : path-like
        The folder of a sweep (holds sweep.csv).
    metric : str
        Column on the y axis.
    x : str
        Parameter on the x axis.
    out : path-like
        PNG file to write (atomically).
    hue : str, optional
        Parameter with one curve per value.
    where : sequence of str
        ``KEY=VALUE`` filters on the rows.
    logx, logy : bool
        Logarithmic axes.

    Returns
    -------
    Path
        ``out``.
    """
    columns, rows = read_table(sweep_dir)
    for option, name in (("--metric", metric), ("--x", x), ("--hue", hue)):
        if name is not None and name not in columns:
            raise ParameterError(f"{option} {name!r} is not a column of the sweep: allowed "
                                 f"{', '.join(c for c in columns if c not in FIXED_COLUMNS)}")
    for pair in where:
        key, sep, value = pair.partition("=")
        key = key.strip()
        if not sep or key not in columns:
            raise ParameterError(f"--where {pair!r} must be KEY=VALUE with KEY a column: "
                                 f"{', '.join(columns)}")
        wanted = _parse(value.strip())
        rows = [r for r in rows if r[key] == wanted]
    rows = [r for r in rows if r["status"] == "ok" and r[metric] is not None]
    if not rows:
        raise ParameterError(f"--metric {metric!r}: no finished case has a value")

    record = Path(sweep_dir) / RECORD
    varied = io.read_json(record).get("varied", []) if record.is_file() else []
    groups = {}
    for r in rows:
        groups.setdefault(r[hue] if hue else None, []).append(r)
    for label, group in groups.items():
        xs = [r[x] for r in group]
        if len(set(xs)) < len(xs):
            others = [v for v in varied if v not in (x, hue)]
            raise ParameterError(
                f"several cases share {x} = {xs[0]!r}"
                + (f" and {hue} = {label!r}" if hue else "")
                + f": fix the other varied parameters ({', '.join(others) or 'none'}) with "
                  "--where KEY=VALUE or choose one as --hue")

    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 3.6), dpi=120)
    ax = fig.subplots()
    for label in sorted(groups, key=_sort_key):
        group = sorted(groups[label], key=lambda r: _sort_key(r[x]))
        ax.plot([r[x] for r in group], [r[metric] for r in group], lw=2, marker="o",
                label=f"{hue} = {_fmt(label)}" if hue else None)
    ax.set_xlabel(x)
    ax.set_ylabel(metric)
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    if hue:
        ax.legend()
    scene = io.read_json(record).get("scene") if record.is_file() else None
    ax.set_title(f"{scene + ': ' if scene else ''}{metric} against {x}")
    fig.tight_layout()
    with io.atomic_path(out) as tmp:
        fig.savefig(tmp, format="png")
    return Path(out)


def _sort_key(value):
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return (0, value, "")
    return (1, 0, str(value))


def _fmt(value):
    return f"{value:g}" if isinstance(value, float) else str(value)


# --------------------------------------------------------------------------- command line

def add_arguments(parser):
    """The ``sweep run`` and ``sweep plot`` subcommands."""
    sub = parser.add_subparsers(dest="sweep_command", required=True)
    p = sub.add_parser("run", help="run the cases of a sweep file (TOML)")
    p.add_argument("file", help="the sweep file")
    p.add_argument("--out", required=True, help="sweep folder: cases, sweep.csv, sweep.json")
    p.add_argument("--workers", type=int,
                   help="local worker processes (default: min(2, cases)); with --scheduler: "
                        "cases submitted at a time (default: the cluster's threads)")
    p.add_argument("--threads", type=int,
                   help="NGSolve threads per case (default: cores / workers; 1 with "
                        "--scheduler)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on this Dask scheduler (e.g. tcp://host:8786) instead of locally")
    p.add_argument("--resume", action="store_true",
                   help="reuse the finished cases of a folder that holds a different sweep "
                        "(an unchanged sweep always resumes)")
    p.add_argument("--max-cases", type=int, metavar="N",
                   help="run at most N cases now, the rest on the next run")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")

    p = sub.add_parser("plot", help="a metric against a parameter, one curve per hue")
    p.add_argument("sweep_dir", help="the --out folder of a sweep run")
    p.add_argument("--metric", required=True, help="column on the y axis")
    p.add_argument("--x", required=True, help="parameter on the x axis")
    p.add_argument("--hue", help="parameter with one curve per value")
    p.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                   help="keep the rows with KEY = VALUE (repeatable)")
    p.add_argument("--logx", action="store_true", help="logarithmic x axis")
    p.add_argument("--logy", action="store_true", help="logarithmic y axis")
    p.add_argument("--out", required=True, help="PNG file")


def format_table(report):
    """The table of a report as aligned text (errors listed below it)."""
    columns = [c for c in report.columns if c != "error"]
    cells = [[_cell(row[c]) for c in columns] for row in report.rows]
    widths = [max([len(c)] + [len(line[i]) for line in cells]) for i, c in enumerate(columns)]
    lines = ["  ".join(f"{c:>{w}s}" for c, w in zip(columns, widths, strict=True))]
    lines += ["  ".join(f"{v:>{w}s}" for v, w in zip(line, widths, strict=True)) for line in cells]
    for row in report.rows:
        if row["error"]:
            lines.append(f"case {row['case']}: {row['error']}")
    return "\n".join(lines)


def _cell(value):
    if value is None:
        return "-"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else f"{value:.4g}"
    return str(value)


def main(args):
    """Entry of ``ngincompat sweep``: run a sweep or plot one; returns the summary lines for
    the command line to print."""
    if args.sweep_command == "plot":
        path = plot_sweep(args.sweep_dir, args.metric, args.x, args.out, hue=args.hue,
                          where=args.where, logx=args.logx, logy=args.logy)
        return [f"plot written to {path}"]
    sweep = load_sweep(args.file)
    report = run_sweep(sweep, args.out, workers=args.workers, scheduler=args.scheduler,
                       resume=args.resume, quiet=args.quiet, threads=args.threads,
                       max_cases=args.max_cases)
    tables = [TABLE] + ([PARQUET] if (report.out / PARQUET).is_file() else [])
    return [format_table(report),
            f"{len(report.rows)} cases: {report.ok} ok, {report.failed} failed; run now "
            f"{report.computed}, taken over {report.reused}"
            + (f", left for the next run {report.pending}" if report.pending else ""),
            f"table written to {', '.join(str(report.out / t) for t in tables)}"]
