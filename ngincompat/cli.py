"""Command line: ``ngincompat list | run | paper | expansion | sweep | bench``.

Errors a user can cause (unknown scene or key, a value out of range, a bad expression) end the
program with exit code 2 and one line on stderr; a run whose growth could not be applied to the
end exits with code 1 after writing the last converged state.
"""

import argparse
import logging
import sys

from .errors import ConvergenceError, ParameterError


def _settings(pairs):
    out = {}
    for pair in pairs or ():
        key, sep, value = pair.partition("=")
        if not sep or not key.strip():
            raise ParameterError(f"--set {pair!r} must have the form KEY=VALUE")
        out[key.strip()] = value.strip()
    return out


OUTPUT_NAMES = ("incompatibility", "mechanics", "vtk", "figures")


def _outputs(text):
    """--outputs LIST -> the scene settings ``mechanics`` and ``outputs``.

    incompatibility (G, b, Curl Fg) is always computed; mechanics adds the solve, stresses and
    energy; vtk and figures add files."""
    items = {item.strip() for item in text.split(",") if item.strip()}
    unknown = items - set(OUTPUT_NAMES)
    if unknown or not items:
        raise ParameterError(f"--outputs {text!r}: allowed a comma list of "
                             f"{', '.join(OUTPUT_NAMES)}")
    files = [name for name in ("vtk", "figures") if name in items]
    return {"mechanics": "mechanics" in items, "outputs": ",".join(files) or "none"}


def _cmd_list(args):
    from .scenes import SCENES
    for name, cls in SCENES.items():
        print(f"{name:10s} {cls.summary}")
        if args.verbose:
            for key, (default, help, unit) in cls.parameters().items():
                unit = f" [{cls.unit_of(unit)}]" if unit else ""
                print(f"    {key:10s} = {default!r:24s} {help}{unit}")
    return 0


def _cmd_run(args):
    from .scenes import get_scene
    cls = get_scene(args.scene)
    settings = _settings(args.set)
    if args.order is not None:
        settings["order"] = args.order
    if args.maxh is not None:
        settings["maxh"] = args.maxh
    if args.outputs is not None:
        settings.update(_outputs(args.outputs))
    scene = cls.from_settings(settings)
    results = scene.run(args.out, quiet=args.quiet)
    metrics = results["metrics"]
    if "solver" in results:
        print(f"{scene.name}: ndof {results['mesh']['ndof']}, "
              f"Newton iterations {results['solver']['newton_iterations']}, "
              f"solve {results['timings']['solve']:.2f} s")
    else:
        print(f"{scene.name}: incompatibility only (no mechanics), "
              f"{sum(results['timings'].values()):.2f} s")
    for key, value in metrics.items():
        print(f"  {key:28s} {value:.6g}")
    print(f"results written to {args.out}/results.json")
    return 0


def _cmd_paper(args):
    from . import paper
    rows = paper.run_all(args.out, quiet=args.quiet)
    print(paper.summary_markdown(rows))
    print(f"summary written to {args.out}/summary.md (.csv, .json) with figures")
    return 0


def _cmd_expansion(args):
    from .scenes import skin
    rows = skin.summary(args.out, quiet=args.quiet, **_settings(args.set))
    keys = list(rows[0])
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for row in rows:
        print("| " + " | ".join(f"{v:.4g}" if isinstance(v, float) else str(v)
                                for v in row.values()) + " |")
    print(f"summary written to {args.out}/summary.json")
    return 0


def _cmd_bench(args):
    from . import bench
    print("\n".join(bench.main(args)))
    return 0


def _cmd_sweep(args):
    from . import sweep
    print("\n".join(sweep.main(args)))
    return 0


def build_parser():
    parser = argparse.ArgumentParser(
        prog="ngincompat",
        description="Growth of soft tissue and the geometric incompatibility it leaves.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log solver progress")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("list", help="list the scenes (with -v: their parameters)")
    p.add_argument("-v", "--verbose", action="store_true")
    p.set_defaults(func=_cmd_list)

    p = sub.add_parser("run", help="run a scene and write its results to a folder")
    p.add_argument("scene")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="set a scene parameter (repeatable); see 'ngincompat list -v'")
    p.add_argument("--order", type=int, help="polynomial order of the displacement")
    p.add_argument("--maxh", type=float, help="mesh size")
    p.add_argument("--outputs", metavar="LIST",
                   help="what to compute and write: comma list of " + ", ".join(OUTPUT_NAMES)
                   + " (default: all); 'incompatibility' alone builds no mechanics problem")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_run)

    p = sub.add_parser("paper", help="run every idealized scene of the paper, one summary")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_paper)

    p = sub.add_parser("expansion", help="the skin-expansion scene for all four expanders")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="a parameter of the skin scene for every expander (repeatable)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_expansion)

    from . import bench
    p = sub.add_parser("bench", help="benchmarks: run time against error")
    bench.add_arguments(p)
    p.set_defaults(func=_cmd_bench)

    from . import sweep
    p = sub.add_parser("sweep", help="parameter sweeps: run a sweep file, plot its table")
    sweep.add_arguments(p)
    p.set_defaults(func=_cmd_sweep)
    return parser


def main(argv=None):
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit:
        return exit.code
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except ParameterError as err:
        print(f"ngincompat: error: {err}", file=sys.stderr)
        return 2
    except ConvergenceError as err:
        print(f"ngincompat: not converged: {err}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
