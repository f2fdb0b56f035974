"""Benchmarks: ``ngincompat bench cube`` measures run time against error;
``ngincompat bench stability`` runs the numerical stress-test matrix; ``ngincompat bench
scaling`` the cost of one Newton step against size and linear solver (:mod:`.scaling`).

For every (maxh, order) the cube scene is solved and the table reports ndof, Newton iterations,
solve time, the strain energy and its relative error against the finest run of the table, and
the relative L2 error of G (projected path) against eq. (16). Files are not written for the
runs (only results.json), so the times are those of the computation.
"""

import itertools
import tempfile
from pathlib import Path

from . import io, scaling


def add_arguments(parser):
    parser.add_argument("case", choices=["cube", "accuracy", "stability", "scaling"],
                        help="cube: run time against error of the cube; accuracy: the same "
                             "for cube, hemisphere (symmetry mode) and cylinder, with a plot "
                             "and the cheapest setting per target; stability: the numerical "
                             "stress-test matrix (see ngincompat.stability); scaling: one "
                             "Newton step of the cube against ndof and linear solver (see "
                             "ngincompat.scaling)")
    parser.add_argument("--quick", action="store_true",
                        help="stability, scaling: only a small corner of the matrix or grid")
    parser.add_argument("--threads", type=int, default=1,
                        help="stability: NGSolve threads (default 1)")
    parser.add_argument("--maxh", type=float, nargs="+", default=None,
                        help="mesh sizes (cube default: 0.5 0.25; scaling: see "
                             "ngincompat.scaling.GRID)")
    parser.add_argument("--orders", type=int, nargs="+", default=None,
                        help="polynomial orders (cube default: 2 3 4 5; scaling: see "
                             "ngincompat.scaling.GRID)")
    parser.add_argument("--solvers", nargs="+", default=None,
                        help="scaling: linear solvers among sparsecholesky, umfpack, bddc, "
                             "pardiso (default: all)")
    parser.add_argument("--timeout", type=float, default=scaling.TIMEOUT,
                        help="scaling: wall-time limit of one case's process [s] "
                             f"(default {scaling.TIMEOUT:g})")
    parser.add_argument("--memory-limit", type=float, default=scaling.MEMORY_LIMIT,
                        help="scaling: resident-set limit of one case's process [GiB] "
                             f"(default {scaling.MEMORY_LIMIT:g})")
    parser.add_argument("--out", default=None,
                        help="folder for the table (bench.json, scaling.json) and the runs' "
                             "results")


def cube_table(maxhs, orders, out):
    """Run the cube for every (maxh, order); returns the rows, finest run last."""
    from .scenes import CubeScene
    rows = []
    for maxh, order in itertools.product(sorted(maxhs, reverse=True), sorted(orders)):
        scene = CubeScene(maxh=maxh, order=order, outputs="none")
        r = scene.run(Path(out) / f"cube_h{maxh:g}_p{order}")
        rows.append({
            "maxh": maxh, "order": order, "ndof": r["mesh"]["ndof"],
            "newton": r["solver"]["newton_iterations"],
            "solve_s": r["timings"]["solve"],
            "strain_energy": r["metrics"]["strain_energy"],
            "G_error": r["metrics"]["G_error_L2_rel"],
        })
    finest = max(rows, key=lambda row: row["ndof"])
    for row in rows:
        row["energy_error"] = abs(row["strain_energy"] - finest["strain_energy"]) / \
            abs(finest["strain_energy"])
    return rows


def format_table(rows):
    head = "| maxh | order | ndof | Newton | solve [s] | strain energy [N mm] | " \
           "energy rel. error | G rel. L2 error |"
    lines = [head, "|" + "---|" * 8]
    for r in rows:
        lines.append(f"| {r['maxh']:g} | {r['order']} | {r['ndof']} | {r['newton']} | "
                     f"{r['solve_s']:.2f} | {r['strain_energy']:.6e} | "
                     f"{r['energy_error']:.1e} | {r['G_error']:.1e} |")
    return "\n".join(lines)


def main(args):
    """Entry of ``ngincompat bench``; returns the lines for the command line to print."""
    if args.case == "stability":
        from . import stability
        return stability.main(args)
    if args.case == "scaling":
        return scaling.main(args)
    if args.case == "accuracy":
        return accuracy_main(args)
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(args.out) if args.out else Path(scratch)
        rows = cube_table(args.maxh or [0.5, 0.25], args.orders or [2, 3, 4, 5], out)
        if args.out:
            io.write_json(out / "bench.json", {"case": args.case, "rows": rows,
                                               **io.provenance()})
    return [format_table(rows), "(energy error against the finest run of the table)"]


#: Converged strain energy of the cube (N mm): order 6 on 4^3 hexahedra, 2.195334e-7, which
#: agrees with the independent reference 2.19533e-7.
CUBE_ENERGY = 2.195334e-7

#: (scene, settings grid) of the accuracy study; errors as documented in :func:`_error`.
#: "cube-fast" is the cube with every lever for speed: a quarter model (two mirror planes)
#: and the factorised tangent reused while Newton contracts tenfold per iteration.
ACCURACY = {
    "cube": ("cube", [dict(maxh=h, order=p) for h in (1.0, 0.5, 0.25) for p in (2, 3, 4, 5)]),
    "cube-fast": ("cube", [dict(maxh=h, order=p, model="quarter", reuse_tangent=True)
                           for h in (1.0, 0.5, 0.25) for p in (3, 4, 5)]),
    "hemisphere": ("hemisphere", [dict(maxh=h, centre_maxh=c, order=p, flat_face="symmetry")
                                  for h, c in ((0.4, 0.1), (0.3, 0.02)) for p in (2, 3, 4)]),
    "cylinder": ("cylinder", [dict(maxh=h, order=p) for h in (0.5, 0.25) for p in (2, 3, 4)]),
}
TARGETS = (1e-2, 1e-4, 1e-6)


def _error(scene, results):
    """The error measure of a scene: relative energy error (cube), largest Cauchy-stress error
    against the 1-D radial solution relative to the largest stress (hemisphere), strain energy
    over mu |B| (a L)^2, which must vanish (cylinder)."""
    m = results["metrics"]
    if scene == "cube":
        return abs(m["strain_energy"] - CUBE_ENERGY) / CUBE_ENERGY
    if scene == "hemisphere":
        return max(m["radial_sigma_rr_error"], m["radial_sigma_thetatheta_error"])
    p = results["params"]
    return m["strain_energy"] / (p["mu"] * p["area"] * p["length"] * (p["a"] * p["length"]) ** 2)


def accuracy_table(out, cases=None):
    """Run every setting of the accuracy study; returns rows with error and solve time."""
    from .scenes import get_scene
    rows = []
    for case in ACCURACY if cases is None else cases:
        name, grid = ACCURACY[case]
        for settings in grid:
            scene = get_scene(name)(outputs="none", **settings)
            label = "_".join(f"{k}{v}" for k, v in settings.items()
                             if k in ("maxh", "centre_maxh", "order"))
            r = scene.run(Path(out) / f"{case}_{label}")
            rows.append({"case": case, "maxh": settings["maxh"], "order": settings["order"],
                         "ndof": r["mesh"]["ndof"], "newton": r["solver"]["newton_iterations"],
                         "tangents": r["solver"]["tangent_assemblies"],
                         "solve_s": r["timings"]["solve"], "error": _error(name, r)})
    return rows


def cheapest(rows, case, target):
    """The fastest row of ``case`` whose error is at most ``target``, or None."""
    ok = [r for r in rows if r["case"] == case and r["error"] <= target]
    return min(ok, key=lambda r: r["solve_s"]) if ok else None


def accuracy_main(args):
    from . import plots
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(args.out) if args.out else Path(scratch)
        rows = accuracy_table(out)
        lines = ["| case | maxh | order | ndof | Newton | tangents | solve [s] | error |",
                 "|---|---|---|---|---|---|---|---|"]
        lines += [f"| {r['case']} | {r['maxh']:g} | {r['order']} | {r['ndof']} | "
                  f"{r['newton']} | {r['tangents']} | {r['solve_s']:.2f} | {r['error']:.1e} |"
                  for r in rows]
        lines += ["", "| case | target | cheapest setting | solve [s] |", "|---|---|---|---|"]
        for case in ACCURACY:
            for target in TARGETS:
                best = cheapest(rows, case, target)
                setting = (f"maxh {best['maxh']:g}, order {best['order']}" if best
                           else "none in the grid")
                seconds = f"{best['solve_s']:.2f}" if best else "-"
                lines.append(f"| {case} | {target:g} | {setting} | {seconds} |")
        if args.out:
            for case in ACCURACY:
                curves = {}
                for order in sorted({r["order"] for r in rows if r["case"] == case}):
                    pts = sorted((r["solve_s"], r["error"]) for r in rows
                                 if r["case"] == case and r["order"] == order)
                    curves[f"order {order}"] = pts
                plots.error_against_time(out / f"accuracy_{case}.png", curves,
                                         title=f"{case}: error against solve time")
            io.write_json(out / "accuracy.json", {"rows": rows, **io.provenance()})
            lines.append(f"plots and table written to {out}")
    return lines
