"""``ngincompat paper``: every idealized scene of sections 3.1-3.4 with one summary table.

Runs the cube; the hemisphere with the linear, concave and convex profiles (and the linear one
in symmetry mode, checked against the 1-D radial solution); the disc with radial and
circumferential GOH fibers; the cylinder. Each run writes its own folder; the summary is
written as ``summary.md``, ``summary.csv`` and ``summary.json``, and the comparison figures of
Fig. 2g-h (hemisphere profiles) and Fig. 3e (disc fiber families) as PNG.
"""

import csv
import io as _io
import logging
import time
from pathlib import Path

from . import io, plots
from .scenes import CubeScene, CylinderScene, DiscScene, HemisphereScene

log = logging.getLogger(__name__)

#: Verification metrics reported in the summary, by scene (closed forms and references).
CHECKS = ("G_error_L2_rel", "radial_sigma_rr_error", "radial_sigma_thetatheta_error",
          "b_radial_rel", "b_eq22_error", "sigma_r_rim_rel", "b_eq27_error",
          "Fe_rotation_deviation")


def cases():
    """(label, scene) of every run."""
    return [
        ("cube", CubeScene()),
        ("hemisphere-linear", HemisphereScene(profile="linear")),
        ("hemisphere-concave", HemisphereScene(profile="concave")),
        ("hemisphere-convex", HemisphereScene(profile="convex")),
        ("hemisphere-linear-symmetry", HemisphereScene(profile="linear", flat_face="symmetry")),
        ("disc-radial", DiscScene(fibers="radial")),
        ("disc-circumferential", DiscScene(fibers="circumferential")),
        ("cylinder", CylinderScene()),
    ]


def run_all(out, quiet=True):
    """Run every case into ``out/<label>``; returns the summary rows."""
    out = Path(out)
    rows, results = [], {}
    for label, scene in cases():
        log.info("running %s", label)
        start = time.perf_counter()
        r = scene.run(out / label, quiet=quiet)
        results[label] = r
        m = r["metrics"]
        converged = [s for s in r["solver"]["steps"] if s["converged"]]
        rows.append({
            "case": label, "ndof": r["mesh"]["ndof"], "newton": r["solver"]["newton_iterations"],
            "load_steps": len(converged),
            "newton_per_step": max(s["iterations"] for s in converged),
            "seconds": round(time.perf_counter() - start, 2),
            "strain_energy": m["strain_energy"], "burgers_max": m["burgers_max"],
            "max_principal_stress": m["max_principal_stress"],
            **{k: m[k] for k in CHECKS if k in m},
        })
    _comparison_figures(out, results)
    _write_summary(out, rows)
    return rows


def summary_markdown(rows):
    keys = ["case", "ndof", "newton", "load_steps", "newton_per_step", "seconds",
            "strain_energy", "burgers_max",
            "max_principal_stress", *CHECKS]
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for row in rows:
        cells = []
        for k in keys:
            v = row.get(k, "")
            cells.append(f"{v:.3g}" if isinstance(v, float) else str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _write_summary(out, rows):
    keys = sorted({k for row in rows for k in row}, key=lambda k: (k != "case", k))
    buffer = _io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=keys)
    writer.writeheader()
    writer.writerows(rows)
    with io.atomic_path(out / "summary.csv") as tmp:
        tmp.write_text(buffer.getvalue())
    with io.atomic_path(out / "summary.md") as tmp:
        tmp.write_text(summary_markdown(rows) + "\n")
    io.write_json(out / "summary.json", {"rows": rows, **io.provenance()})


def _comparison_figures(out, results):
    hemi = {k.split("-")[1]: results[k]["profiles"]["line"]
            for k in ("hemisphere-linear", "hemisphere-concave", "hemisphere-convex")}
    R = hemi["linear"]["R"]
    plots.profiles(out / "fig2g_burgers.png", R,
                   {k: p["|b_meridional|"] for k, p in hemi.items()}, xlabel="R [mm]",
                   ylabel="|b| on the meridional plane [1/mm]", title="Fig. 2g")
    plots.profiles(out / "fig2h_curl.png", R, {k: p["curlFg_sq"] for k, p in hemi.items()},
                   xlabel="R [mm]", ylabel="Curl Fg : Curl Fg [1/mm^2]", title="Fig. 2h")
    disc = {k.split("-")[1]: results[k]["profiles"]["line"]
            for k in ("disc-radial", "disc-circumferential")}
    curves = {}
    for family, p in disc.items():
        curves[f"sigma_r ({family})"] = p["sigma_r"]
        curves[f"sigma_theta ({family})"] = p["sigma_theta"]
    plots.profiles(out / "fig3e_disc_stress.png", disc["radial"]["R"], curves,
                   xlabel="R [mm]", ylabel="Cauchy stress [MPa]", title="Fig. 3e")
