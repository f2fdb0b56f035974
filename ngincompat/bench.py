"""Benchmarks: ``ngincompat bench cube`` measures run time against error;
``ngincompat bench stability`` runs the numerical stress-test matrix.

For every (maxh, order) the cube scene is solved and the table reports ndof, Newton iterations,
solve time, the strain energy and its relative error against the finest run of the table, and
the relative L2 error of G (projected path) against eq. (16). Files are not written for the
runs (only results.json), so the times are those of the computation.
"""

import itertools
import tempfile
from pathlib import Path

from . import io


def add_arguments(parser):
    parser.add_argument("case", choices=["cube", "stability"],
                        help="cube: run time against error; stability: the numerical "
                             "stress-test matrix (see ngincompat.stability)")
    parser.add_argument("--quick", action="store_true",
                        help="stability: only a small corner of the matrix")
    parser.add_argument("--threads", type=int, default=1,
                        help="stability: NGSolve threads (default 1)")
    parser.add_argument("--maxh", type=float, nargs="+", default=[0.5, 0.25],
                        help="mesh sizes (default: 0.5 0.25)")
    parser.add_argument("--orders", type=int, nargs="+", default=[2, 3, 4, 5],
                        help="polynomial orders (default: 2 3 4 5)")
    parser.add_argument("--out", default=None,
                        help="folder for the table (bench.json) and the runs' results")


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
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(args.out) if args.out else Path(scratch)
        rows = cube_table(args.maxh, args.orders, out)
        if args.out:
            io.write_json(out / "bench.json", {"case": args.case, "rows": rows,
                                               **io.provenance()})
    return [format_table(rows), "(energy error against the finest run of the table)"]
