"""Command line: ``ngincompat list | run | paper | expansion | folding | sweep | bench``.

Exit codes (the ``EXIT_*`` constants; what each means in full: the table of
``docs/guide/outputs.md``): 0 done, 2 bad input, 3 not converged (the last converged state
written), 4 a sweep with failed cases, 5 a file not written, 130 interrupted.

This is the only module that parses arguments; everything it calls takes plain values.
"""

import argparse
import contextlib
import errno
import importlib
import logging
import os
import resource
import shlex
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from types import FrameType, ModuleType
from typing import TYPE_CHECKING, Any, NoReturn

from ngincompat import config, names, parallel
from ngincompat.errors import (
    ConvergenceError,
    Interrupted,
    InterruptedBeforeComputing,
    ParameterError,
)
from ngincompat.parameters import OUTPUTS, PRESETS, Outputs
from ngincompat.progress import Progress

if TYPE_CHECKING:     # imported where a command needs it (it imports NGSolve)
    from ngincompat.workflow.results import Results

EXIT_OK, EXIT_INPUT, EXIT_NOT_CONVERGED, EXIT_FAILED_CASES, EXIT_NOT_WRITTEN = 0, 2, 3, 4, 5
EXIT_INTERRUPTED = 130
#: The errors of a write that the machine refused (exit 5): a full disk or quota, a file too
#: large, a read-only file system, or permissions taken away while the run computed (the
#: folder's are checked before); any other OSError is a bug.
NOT_WRITTEN = (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG, errno.EACCES, errno.EPERM)


def _settings(pairs: Iterable[str] | None, option: str = "--set") -> dict[str, str]:
    out = {}
    for pair in pairs or ():
        key, sep, value = pair.partition("=")
        if not sep or not key.strip():
            raise ParameterError(f"{option} {pair!r} must have the form KEY=VALUE")
        out[key.strip()] = value.strip()
    return out


#: --outputs: what to compute (incompatibility always, mechanics optionally), then the
#: optional outputs of a scene, :data:`ngincompat.parameters.OUTPUTS`.
OUTPUT_NAMES = ("incompatibility", "mechanics", *OUTPUTS)


def _outputs(text: str) -> dict[str, Any]:
    """--outputs LIST -> the scene settings ``mechanics`` and ``outputs``.

    incompatibility (G, b, Curl Fg) is always computed; mechanics adds the solve, stresses and
    energy; the scene's optional outputs (:data:`ngincompat.parameters.OUTPUTS`) are passed
    on as :class:`~ngincompat.parameters.Outputs`. ``none``: no files besides results.json,
    what is computed left to ``--set mechanics`` (as ``--set outputs=none``)."""
    if text.strip() == "none":
        return {"outputs": "none"}
    items = {item.strip() for item in text.split(",") if item.strip()}
    unknown = items - set(OUTPUT_NAMES)
    if unknown or not items:
        raise ParameterError(f"--outputs {text!r}: allowed a comma list of "
                             f"{', '.join(OUTPUT_NAMES)}, or none")
    return {"mechanics": "mechanics" in items, "outputs": str(Outputs(items & set(OUTPUTS)))}


def _cmd_list(args: argparse.Namespace) -> int:
    from ngincompat.scenes import SCENES
    for name, cls in SCENES.items():
        print(f"{name:10s} {cls.summary}")
        if args.verbose:
            for key, p in cls.declarations().items():
                print("    " + cls.parameter_line(key))
                print(f"        {p.help}")
            for preset in cls.preset_names():
                print(f"    --preset {preset}: {cls.preset_line(preset)}")
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    from ngincompat.scenes import get_scene
    cls = get_scene(args.scene)
    settings = _settings(args.set)
    if args.order is not None:
        settings["order"] = args.order
    if args.maxh is not None:
        settings["maxh"] = args.maxh
    if args.outputs is not None:
        settings.update(_outputs(args.outputs))
    scene = cls.from_settings(settings, preset=args.preset)
    root = parallel.is_root()       # with MPI, rank 0 alone reports
    try:
        results = scene.run(args.out, overwrite=args.overwrite,
                            progress=Progress(quiet=args.quiet or not root))
    except ConvergenceError as err:
        if root:
            _print_run(err.results, args.out)
        raise
    if root:
        _print_run(results, args.out)
    return EXIT_OK


def _print_run(results: "Results", out: str) -> None:
    """The summary lines of a run: size, solver, time, metrics with the scene's units."""
    print(results.summary())
    print("\n".join(results.metric_lines()))
    print(f"results written to {out}/results.json (units: "
          + ", ".join(f"{q} {u}" for q, u in results.units.items()) + ")")


def _status_code(rows: Iterable[Mapping[str, Any]]) -> int:
    """3 if a row did not converge, 130 if one was interrupted, else 0."""
    statuses = {row["status"] for row in rows}
    if "interrupted" in statuses:
        return EXIT_INTERRUPTED
    return EXIT_NOT_CONVERGED if statuses - {"done"} else EXIT_OK


def _cmd_paper(args: argparse.Namespace) -> int:
    from ngincompat.studies import paper
    only = None if args.only is None else [n.strip() for n in args.only.split(",") if n.strip()]
    if only == []:          # an empty list is a mistake, not "every section"
        raise ParameterError(f"--only {args.only!r} names no section: allowed a comma list of "
                             "section numbers, e.g. 3.5,3.6 (leave it out for every section)")
    rows = paper.run_all(args.out, progress=Progress(quiet=args.quiet),
                         overwrite=args.overwrite, resolution=args.resolution, only=only,
                         jobs=args.jobs)
    print(paper.summary_markdown(rows))
    print(f"report written to {args.out}/report.html; summary to {args.out}/summary.md "
          "(.csv, .json), figures beside them")
    return _status_code(rows)


def _cmd_expansion(args: argparse.Namespace) -> int:
    from ngincompat.studies import expansion
    rows = expansion.run_all(args.out, footprints=args.footprints,
                             progress=Progress(quiet=args.quiet), overwrite=args.overwrite,
                             **_settings(args.set))
    print(expansion.summary_markdown(rows))
    print(f"summary written to {args.out}/summary.md (.csv, .json)")
    return _status_code(rows)


def _cmd_folding(args: argparse.Namespace) -> int:
    from ngincompat.studies import folding
    rows, _ = folding.run_all(args.out, axons=args.axons, progress=Progress(quiet=args.quiet),
                              overwrite=args.overwrite, **_settings(args.set))
    print(folding.summary_markdown(rows))
    print(f"summary written to {args.out}/summary.md (.csv, .json), figure "
          f"{args.out}/fields.png")
    return _status_code(rows)


def _cmd_bench(args: argparse.Namespace) -> int:
    """Runs the benchmark ``args.case`` (its runner, ``args.run``, registered with its
    parser by :func:`_add_bench`) and records how the tables were made."""
    start, load = time.perf_counter(), os.getloadavg()[0]
    from ngincompat.workflow import io, tables
    # the checkout's state before the benchmark rewrites its own (possibly committed) tables:
    # asked once per process, so the records of every file it writes say the same
    io.git_state()
    lines = args.run(args)
    print("\n".join(lines))
    if args.out is not None:
        usage = [resource.getrusage(who) for who in (resource.RUSAGE_SELF,
                                                     resource.RUSAGE_CHILDREN)]
        tables.write_made_by(args.out, shlex.join(["ngincompat", *args.argv]),
                             time.perf_counter() - start,
                             sum(u.ru_utime + u.ru_stime for u in usage),
                             (load, os.getloadavg()[0]))
    return EXIT_OK


def _cmd_sweep_run(args: argparse.Namespace) -> int:
    from ngincompat.studies import sweep
    spec = sweep.load_sweep(args.file).with_settings(_settings(args.set))
    report = sweep.run_sweep(spec, args.out, workers=args.workers,
                             threads=args.threads, scheduler=args.scheduler,
                             resume=args.resume, max_cases=args.max_cases,
                             progress=Progress(quiet=args.quiet))
    print("\n".join(report.summary()))
    return EXIT_FAILED_CASES if report.failed else EXIT_OK


def _cmd_sweep_plot(args: argparse.Namespace) -> int:
    from ngincompat.studies import sweep
    path = sweep.plot_sweep(args.sweep_dir, args.metric, args.x, args.out, hue=args.hue,
                            where=_settings(args.where, "--where"), logx=args.logx,
                            logy=args.logy)
    print(f"plot written to {path}")
    return EXIT_OK


def _add_bench(sub: argparse._SubParsersAction) -> None:
    """``bench scenes | folding | cube | accuracy | curvature | validation | skin | inputs |
    peer | stability | mpi | scaling`` and their options."""
    from ngincompat.studies.scaling import MEMORY_LIMIT, SOLVERS, TIMEOUT
    bench = sub.add_parser("bench", help="benchmarks: run time against error, the "
                                         "stress-test matrix, cost per Newton step")
    cases = bench.add_subparsers(dest="case", required=True)

    def case(name: str, help: str, study: str,
             run: Callable[[argparse.Namespace, ModuleType], list[str]],
             quick: str | None = None) -> argparse.ArgumentParser:
        """A benchmark's parser with --out, and --quick where ``quick`` says what it runs;
        ``run(args, module)`` runs it and returns its lines, ``module`` the study
        ``ngincompat.studies.<study>`` (imported only when the benchmark runs)."""
        p = cases.add_parser(name, help=help)
        p.add_argument("--out", help="folder for the tables and the runs' results")
        if quick:
            p.add_argument("--quick", action="store_true", help=quick)
        p.set_defaults(func=_cmd_bench, run=lambda args: run(
            args, importlib.import_module(f"ngincompat.studies.{study}")))
        return p

    p = case("scenes", "what each scene costs at each preset: dofs, Newton iterations, wall and "
                       "CPU time, peak memory, error against the finest", "costs",
             lambda a, m: m.main(a.scenes, a.presets, out=a.out, timeout=a.timeout))
    p.add_argument("--scenes", nargs="+", metavar="SCENE", help="default: every scene")
    p.add_argument("--presets", nargs="+", metavar="PRESET",
                   help="default: every preset of each scene (preview, default, paper)")
    p.add_argument("--timeout", type=float, default=3600.0,
                   help="seconds a run may take before it is stopped (default 3600)")
    p = case("folding", "what the folding scene costs per axon field, and where its time "
                        "goes (assembly, factorisation, contact search, ...)", "folding_costs",
             lambda a, m: m.main(a.axons, a.preset, threads=a.threads, out=a.out,
                                 timeout=a.timeout, settings=_settings(a.set),
                                 baseline=a.baseline))
    p.add_argument("--axons", nargs="+", choices=names.AXONS, default=list(names.AXONS),
                   help="axon fields (default: all three)")
    p.add_argument("--preset", choices=PRESETS, default="default",
                   help="the scene's preset (default: default)")
    p.add_argument("--threads", type=int, default=1,
                   help="NGSolve threads per run (default 1; 2 on an otherwise idle "
                        "2-core machine)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="a folding parameter for every run (repeatable)")
    p.add_argument("--baseline", metavar="CHECKOUT", help="also run each field on this "
                   "checkout of another version, after this one (before and after)")
    p.add_argument("--timeout", type=float, default=3600.0,
                   help="seconds a run may take before it is stopped (default 3600)")
    p = case("cube", "run time against error of the cube (energy against the converged "
                     "energy)", "bench",
             lambda a, m: m.cube_main(a.maxh, a.orders, out=a.out, elements=a.elements))
    p.add_argument("--maxh", type=float, nargs="+", default=[0.5, 0.25],
                   help="mesh sizes (default: 0.5 0.25)")
    p.add_argument("--orders", type=int, nargs="+", default=[2, 3, 4, 5],
                   help="polynomial orders (default: 2 3 4 5)")
    p.add_argument("--elements", choices=("hex", "tet"), default="hex",
                   help="element shape (default hex, the paper's layout; the scene's default "
                        "is tet)")
    case("accuracy", "run time against error of cube, hemisphere (symmetry mode) and "
                     "cylinder, with a plot and the cheapest setting per target", "bench",
         lambda a, m: m.accuracy_main(out=a.out, quick=a.quick),
         quick="only coarse cube and cylinder settings (seconds)")
    p = case("curvature", "the curvature of the growth metric on Regge elements against the "
                          "exact one: errors, cost and rates under h- and p-refinement",
             "curvature_rates",
             lambda a, m: m.main(out=a.out, quick=a.quick, names=a.bodies, orders=a.orders),
             quick="only the coarse hemisphere, k = 1, 2 (seconds)")
    p.add_argument("--bodies", nargs="+", metavar="BODY",
                   help="among hemisphere, disc (default: both)")
    p.add_argument("--orders", type=int, nargs="+", metavar="K",
                   help="Regge degrees k (default: 1 2 3)")
    case("validation", "closed forms and independent solutions no other benchmark "
                       "tabulates: G and b of sections 3.1-3.4, folding's onset against "
                       "the Stroh analysis, atrophy against the logistic closed form, "
                       "its volume bookkeeping (see ngincompat.studies.validation)",
         "validation", lambda a, m: m.main(out=a.out, quick=a.quick, progress=Progress()),
         quick="coarse settings (about a minute)")
    p = case("skin", "section 3.6's findings (the expanders' order, the 40 kPa) under the "
                     "choices the paper leaves open: sizes, dome, modulus, Hill constants "
                     "(see ngincompat.studies.skin_sensitivity)", "skin_sensitivity",
             lambda a, m: m.main(a.choices, quick=a.quick, out=a.out),
             quick="two choices on a coarse patch (under a minute)")
    p.add_argument("--choices", nargs="+", metavar="CHOICE", help="the study's choices by "
                   "name (default: all; an unknown name is refused with the list)")
    p = case("inputs", "the hostile-input corpus through the command line: every numeric "
                       "parameter's hostile and boundary values, the environment, the paper "
                       "job's options and interrupts; the outcomes counted (see "
                       "ngincompat.studies.corpus)", "corpus",
             lambda a, m: m.main(quick=a.quick, out=a.out, jobs=a.jobs),
             quick="two parameters of the cube and NGS_NUM_THREADS (under a minute)")
    p.add_argument("--jobs", type=int, default=1, metavar="N",
                   help="parameters tried side by side, each in a process (default 1)")
    p = case("peer", "the cube side by side with FEniCSx (the peer of issue 15): "
                     "alternate runs, the ratio of solve times and both energy errors", "peer",
             lambda a, m: m.main(a.peer, _settings(a.set), pairs=a.pairs, out=a.out))
    p.add_argument("--peer", metavar="DIR",
                   help="the peer's folder (env_dolfinx.sh, fenicsx_growth.py; default: "
                        "$NGINCOMPAT_PEER)")
    p.add_argument("--pairs", type=int, default=3,
                   help="alternating (peer, ours) runs (default 3)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="a parameter of our cube (repeatable; default: the scene's defaults)")
    p = case("stability", "the numerical stress-test matrix and the locking study (see "
                          "ngincompat.studies.stability)", "stability",
             lambda a, m: m.main(quick=a.quick, threads=a.threads, out=a.out),
             quick="only a small corner of the matrix and locking orders 1-3")
    p.add_argument("--threads", type=int, default=1,
                   help="NGSolve threads (default 1: the cells are small, and times on a "
                        "shared machine stay comparable)")
    p = case("mpi", "what a distributed run costs per rank (the atrophy scene on the "
                    "idealized brain on 2, 3, ... ranks: each rank's memory, the times) and "
                    "the cost model fitted to it (see ngincompat.studies.mpi_costs)",
             "mpi_costs", lambda a, m: m.main(a.maxh, a.ranks, _settings(a.set),
                                              timeout=a.timeout, out=a.out))
    p.add_argument("--maxh", type=float, nargs="+",
                   help="mesh sizes of the idealized brain (default: 1.4 1.0 0.8)")
    p.add_argument("--ranks", type=int, nargs="+",
                   help="MPI ranks of each run, >= 2 (default: 2 3)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="an atrophy parameter for every run (repeatable)")
    p.add_argument("--timeout", type=float,
                   help="seconds a run may take before it is stopped (default 3600)")
    p = case("scaling", "one Newton step of the cube against ndof and linear solver (see "
                        "ngincompat.studies.scaling)", "scaling",
             lambda a, m: m.main(a.maxh, a.orders, quick=a.quick, solvers=a.solvers,
                                 timeout=a.timeout, memory_limit=a.memory_limit, out=a.out),
             quick="only the two smallest sizes")
    p.add_argument("--maxh", type=float, nargs="+",
                   help="mesh sizes (default: the grid ngincompat.studies.scaling.GRID)")
    p.add_argument("--orders", type=int, nargs="+",
                   help="polynomial orders (default: those of the grid; with --maxh: 2)")
    p.add_argument("--solvers", nargs="+", choices=SOLVERS, metavar="SOLVER",
                   help=f"linear solvers among {', '.join(SOLVERS)} (default: all)")
    p.add_argument("--timeout", type=float, default=TIMEOUT,
                   help=f"wall-time limit of one case's process [s] (default {TIMEOUT:g})")
    p.add_argument("--memory-limit", type=float, default=MEMORY_LIMIT,
                   help="resident-set limit of one case's process [GiB] "
                        f"(default {MEMORY_LIMIT:g})")


def _add_sweep(sub: argparse._SubParsersAction) -> None:
    """``sweep run`` and ``sweep plot``."""
    sweep = sub.add_parser("sweep", help="parameter sweeps: run a sweep file, plot its table")
    commands = sweep.add_subparsers(dest="sweep_command", required=True)
    p = commands.add_parser("run", help="run the cases of a sweep file (TOML)")
    p.add_argument("file", help="the sweep file")
    p.add_argument("--out", required=True, help="sweep folder: cases, sweep.csv, sweep.json")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="a scene parameter for every case, over the file's [fixed] "
                        "(repeatable; not one the sweep varies); part of the sweep: a folder "
                        "run without it needs --resume and reruns every case")
    p.add_argument("--workers", type=int,
                   help="local worker processes (default: min(2, cases)); with --scheduler: "
                        "cases submitted at a time (default: the cluster's threads)")
    p.add_argument("--threads", type=int,
                   help="NGSolve threads per case (default: cores / workers; 1 with "
                        "--scheduler); 1 when other jobs share the cores: NGSolve's threads "
                        "wait actively for each other (one case on 2 threads beside one busy "
                        "process: 1.8 times the wall and CPU time of one thread)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on this Dask scheduler (e.g. tcp://host:8786) instead of locally")
    p.add_argument("--resume", action="store_true",
                   help="reuse the finished cases of a folder that holds a different sweep "
                        "(an unchanged sweep always resumes)")
    p.add_argument("--max-cases", type=int, metavar="N",
                   help="run at most N cases now, the rest on the next run")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress report")
    p.set_defaults(func=_cmd_sweep_run)

    p = commands.add_parser("plot", help="a metric against a parameter, one curve per hue")
    p.add_argument("sweep_dir", help="the --out folder of a sweep run")
    p.add_argument("--metric", required=True, help="column on the y axis")
    p.add_argument("--x", required=True, help="parameter on the x axis")
    p.add_argument("--hue", help="parameter with one curve per value")
    p.add_argument("--where", action="append", default=[], metavar="KEY=VALUE",
                   help="keep the rows with KEY = VALUE (repeatable)")
    p.add_argument("--logx", action="store_true", help="logarithmic x axis")
    p.add_argument("--logy", action="store_true", help="logarithmic y axis")
    p.add_argument("--out", required=True, help="PNG file")
    p.set_defaults(func=_cmd_sweep_plot)


def _add_variants(sub: argparse._SubParsersAction, command: str, help: str, scene: str,
                  option: str, what: str, choices: Sequence[str],
                  func: Callable[[argparse.Namespace], int]) -> None:
    """A driver that runs ``scene`` for every variant of ``option`` (``expansion``,
    ``folding``)."""
    p = sub.add_parser(command, help=help)
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help=f"a parameter of the {scene} scene for every variant (repeatable)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace a run already in --out (its files are removed first)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress report")
    p.add_argument(option, nargs="+", choices=choices, default=list(choices), metavar="NAME",
                   help=f"the {what} to run (default: all of " + ", ".join(choices) + ")")
    p.set_defaults(func=func)


#: The files every scene writes besides results.json when neither --outputs nor
#: ``--set outputs=...`` says otherwise (the scenes' default ``outputs``; a test keeps them
#: equal).
DEFAULT_FILES = "vtk,figures"


def version_text() -> str:
    """``ngincompat X.Y.Z`` and the NGSolve it runs on (``--version``)."""
    from ngincompat.config import VERSION
    try:
        import ngsolve
        ngsolve_version = ngsolve.__version__
    except ImportError:
        ngsolve_version = "not installed"
    return f"ngincompat {VERSION} (NGSolve {ngsolve_version}, Python {sys.version.split()[0]})"


class _Version(argparse.Action):
    """``--version``: prints :func:`version_text` and exits 0 (NGSolve imported only then)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS,
                 default: Any = argparse.SUPPRESS,
                 help: str = "print the versions of ngincompat and NGSolve and exit") -> None:
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: str | Sequence[Any] | None, option_string: str | None = None) -> None:
        print(version_text())
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ngincompat",
        description="Growth of soft tissue and the geometric incompatibility it leaves.")
    parser.add_argument("--version", action=_Version)
    parser.add_argument("-v", "--verbose", action="store_true", help="log solver progress")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("list", help="list the scenes (with -v: their parameters)")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="every parameter with its type, default, unit and allowed values")
    p.set_defaults(func=_cmd_list)

    p = sub.add_parser("run", help="run a scene and write its results to a folder")
    p.add_argument("scene", help="the scene: " + ", ".join(names.SCENES)
                   + " ('ngincompat list' describes them)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="set a scene parameter (repeatable); see 'ngincompat list -v'")
    p.add_argument("--preset", default="default", metavar="NAME",
                   help="named settings under the explicit ones: " + ", ".join(PRESETS)
                   + " (a first look in seconds, the defaults, the paper's resolution); "
                   "'ngincompat list -v' shows each scene's")
    p.add_argument("--order", type=int, help="polynomial order of the displacement")
    p.add_argument("--maxh", type=float, help="mesh size")
    p.add_argument("--outputs", metavar="LIST",
                   help="what to compute and write: comma list of " + ", ".join(OUTPUT_NAMES)
                   + f" (default: incompatibility,mechanics,{DEFAULT_FILES}, or what --set "
                   "mechanics=... and --set outputs=... say); 'incompatibility' alone builds "
                   "no mechanics problem; 'none': no files besides results.json")
    p.add_argument("--overwrite", action="store_true",
                   help="replace a run already in --out (its files are removed first)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress report")
    p.set_defaults(func=_cmd_run)

    p = sub.add_parser("paper", help="run the paper's sections 3.1-3.7: one summary, one "
                       "report.html")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--resolution", choices=("preview", "paper"), default="preview",
                   help="preview (default: a first look on coarse settings, each scene's "
                        "preview preset) or paper (the paper's resolution and settings)")
    p.add_argument("--only", metavar="LIST",
                   help="comma list of sections to run, e.g. 3.5,3.6 (default: all of "
                        "3.1-3.7); the report shows every section the folder holds")
    p.add_argument("--overwrite", action="store_true",
                   help="replace the runs already in --out (their files are removed first); "
                        "without it, finished runs of the same settings are kept and the "
                        "job continues")
    p.add_argument("--jobs", metavar="N", type=int,
                   help="runs side by side, each in a worker process of its own (default: "
                        "one per core, at most 4, at the preview resolution; 1 at the "
                        "paper's, whose largest runs take many GB); 1: one after the other")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress report")
    p.set_defaults(func=_cmd_paper)

    _add_variants(sub, "expansion", "the skin-expansion scene for all four expanders",
                  "skin", "--footprints", "expanders", names.FOOTPRINTS, _cmd_expansion)
    _add_variants(sub, "folding", "the cortical-folding scene for the three axon fields",
                  "folding", "--axons", "axon fields",
                  names.AXONS,
                  _cmd_folding)
    _add_bench(sub)
    _add_sweep(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (see the module docstring)."""
    try:        # before the parser, whose choices import NGSolve
        config.check_environment()
    except ParameterError as err:
        print(f"ngincompat: error: {err}", file=sys.stderr)
        return EXIT_INPUT
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit:
        return exit.code  # type: ignore[return-value]  # argparse's: 0 or 2
    # the arguments as given, for the records of what a command wrote
    args.argv = list(sys.argv[1:] if argv is None else argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    with _terminate_as_interrupt():
        return _dispatch(args)


@contextlib.contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM (``kill``, a batch system's stop) ends a run as Ctrl-C does: marked
    "interrupted", exit 130. A SIGINT the parent told the process to ignore (``command &`` in
    a script: POSIX has background jobs ignore it) stays ignored."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) != signal.SIG_DFL):
        yield
        return

    def interrupt(signum: int, frame: FrameType | None) -> None:
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _dispatch(args: argparse.Namespace) -> int:
    """Run the command of ``args``; every error the user can cause is an exit code."""
    try:
        return args.func(args)
    except ParameterError as err:
        _report(f"ngincompat: error: {err}")
        return EXIT_INPUT
    except ConvergenceError as err:
        _report(f"ngincompat: not converged: {err} (the last converged state is written)")
        return EXIT_NOT_CONVERGED
    except InterruptedBeforeComputing as err:
        _report(f"ngincompat: {err}")
        return EXIT_INTERRUPTED
    except (Interrupted, KeyboardInterrupt):
        _report("ngincompat: interrupted; finished results are kept, an unfinished run is "
                "marked \"interrupted\" in its results.json")
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # the reader of the output stopped (`ngincompat list -v | head`): what it read is all
        # it wanted; stdout goes to /dev/null so that Python's flush at exit stays quiet
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    except OSError as err:
        if err.errno not in NOT_WRITTEN:
            raise
        print(f"ngincompat: cannot write: {err.strerror or err}"
              f"{f' ({err.filename})' if err.filename else ''}", file=sys.stderr)
        return EXIT_NOT_WRITTEN


def _report(message: str) -> None:
    """``message`` on stderr, once: in a distributed run every rank raises the errors
    reported so (:data:`~ngincompat.workflow.pipeline.COLLECTIVE`), and rank 0 says it."""
    if parallel.is_root():
        print(message, file=sys.stderr)


def run() -> NoReturn:
    """The program ``ngincompat``: :func:`main` on the process's arguments."""
    sys.exit(main())


if __name__ == "__main__":
    run()
