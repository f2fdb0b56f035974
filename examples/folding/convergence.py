"""The folding scene's measures under refinement, from runs already made: one folder per
level of refinement, each as ``ngincompat folding --out FOLDER`` writes it (one subfolder
per axon field with its ``results.json``). For each axon field and measure the value at
each level and its difference relative to the next finer level::

    python convergence.py --out docs/_generated/folding-convergence \\
        L0=runs/folding-L0 L1=runs/folding-L1

Writes ``convergence.md``/``.csv``/``.json`` (the library's tables) and ``made_by.md`` (the
runs' commits, unknowns and wall times). The crease day is the first record of the march
with a contact length > 0 (none: the top never touched itself)."""

import argparse
import itertools
import json
from pathlib import Path

from ngincompat.mechanics import fields
from ngincompat.scenes.folding import FoldingScene
from ngincompat.workflow import tables

#: The measures compared, in the table's order (the crease day is read from the records).
MEASURES = ("sulci", "sulcus_depth", "crease_day", "self_contact_area",
            "self_contact_penetration_max", "burgers_interface_mean",
            "max_principal_stress_released", "peak_tension_depth_released",
            "strain_energy_released")


def measures(results):
    """The :data:`MEASURES` of one run's ``results.json`` (a dict), None where missing."""
    metrics, records = results["metrics"], results["profiles"].get("buckling", {})
    contact = zip(records.get("t", []), records.get("contact_length", []), strict=True)
    values = {k: metrics.get(k) for k in MEASURES}
    values["crease_day"] = next((t for t, length in contact if length > 0), None)
    return values


def relative(coarse, fine):
    """(coarse - fine) / |fine| in percent, or "" where either is missing or fine is 0."""
    if coarse is None or fine is None or fine == 0:
        return ""
    return round(100 * (coarse - fine) / abs(fine), 1)


def rows_of(levels, units):
    """One row per axon field and measure: its unit (``units``), the value at each level
    (label -> results by axon field), then each level's difference to the next finer one
    [%]."""
    labels = list(levels)
    rows = []
    for axons in fields.AXONS:
        runs = {label: levels[label].get(axons) for label in labels}
        if not any(runs.values()):
            continue
        values = {label: (measures(run) if run else {}) for label, run in runs.items()}
        for name in MEASURES:
            row = {"axons": axons, "measure": name, "unit": units[name]}
            row.update({label: values[label].get(name) for label in labels})
            for coarse, fine in itertools.pairwise(labels):
                row[f"{coarse} vs {fine} [%]"] = relative(values[coarse].get(name),
                                                          values[fine].get(name))
            rows.append(row)
    return rows


def made_by(levels, command):
    """The paragraph naming the command and, per run, its commit, unknowns and wall time."""
    runs = []
    for label, by_axons in levels.items():
        for axons, r in by_axons.items():
            git = r["provenance"].get("git") or {}
            runs.append(f"{label} {axons}: {r['mesh'].get('ndof')} unknowns, "
                        f"{sum(r['timings'].values()):.0f} s, {r['status']}, commit "
                        f"{git.get('commit', '?')[:10]} of {r['provenance']['date'][:10]}")
    return (f"Made by `{command}` from the runs ({'; '.join(runs)}), each on one thread "
            f"beside other runs.")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="folder for the tables")
    parser.add_argument("levels", nargs="+", metavar="LABEL=FOLDER",
                        help="a level of refinement and its folder, coarsest first")
    args = parser.parse_args(argv)
    levels = {}
    for level in args.levels:
        label, _, folder = level.partition("=")
        levels[label] = {p.parent.name: json.loads(p.read_text())
                         for p in sorted(Path(folder).glob("*/results.json"))}
    units = {name: FoldingScene.metric_unit(name) if name in FoldingScene.metrics
             else FoldingScene.unit_of("time") for name in MEASURES}     # the crease day
    rows = rows_of(levels, units)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tables.write(out, "convergence", rows)
    command = " ".join(["python examples/folding/convergence.py", "--out", args.out,
                        *args.levels])
    tables.write_markdown(out / "made_by.md", made_by(levels, command))
    print(tables.markdown(rows))


if __name__ == "__main__":
    main()
