"""``ngincompat paper``: every idealized scene of sections 3.1-3.4 with one summary table.

Runs the cube; the hemisphere with the linear, concave and convex profiles (and the linear one
in symmetry mode, checked against the 1-D radial solution); the disc with radial and
circumferential GOH fibers; the cylinder. Each run writes its own folder; the summary is
written as ``summary.md``, ``summary.csv`` and ``summary.json``, and the comparison figures of
Fig. 2g-h (hemisphere profiles) and Fig. 3e (disc fiber families) as PNG.
"""

import time

from ngincompat.errors import ConvergenceError
from ngincompat.progress import SILENT
from ngincompat.scenes import CubeScene, CylinderScene, DiscScene, HemisphereScene
from ngincompat.workflow import output, plots, tables
from ngincompat.workflow.results import DONE

#: Verification metrics reported in the summary, by scene (closed forms and references).
CHECKS = ("G_error_L2_rel", "radial_sigma_rr_error", "radial_sigma_thetatheta_error",
          "b_radial_rel", "b_eq22_error", "sigma_r_rim_rel", "b_eq27_error",
          "Fe_rotation_deviation")


#: The hemispheres are solved as quarters (their mirror planes X1 = 0, X2 = 0 held): the same
#: solution at a third of the unknowns. With the centre refined to 0.04 the quarter's stresses
#: are closer to the radial solution than the full hemisphere's at 0.05 (largest relative
#: deviation 1.7e-4 at 7638 dofs against 2.1e-4 at 30228), and its growth solve is 2-3 s
#: instead of 10-24 s.
HEMISPHERE = dict(model="quarter", centre_maxh=0.04)


def cases(quick=False):
    """(label, scene) of every run; ``quick``: on each scene's ``preview`` preset (every case
    runs in seconds; the numbers are a smoke test of the whole job, not the paper's)."""
    def coarse(cls, **variant):
        paper = HEMISPHERE if cls is HemisphereScene else {}
        preview = cls.preset_settings("preview") if quick else {}
        return cls.from_settings({**paper, **preview, **variant})
    return [
        ("cube", coarse(CubeScene)),
        ("hemisphere-linear", coarse(HemisphereScene, profile="linear")),
        ("hemisphere-concave", coarse(HemisphereScene, profile="concave")),
        ("hemisphere-convex", coarse(HemisphereScene, profile="convex")),
        ("hemisphere-linear-symmetry", coarse(HemisphereScene, profile="linear",
                                              flat_face="symmetry")),
        ("disc-radial", coarse(DiscScene, fibers="radial")),
        ("disc-circumferential", coarse(DiscScene, fibers="circumferential")),
        ("cylinder", coarse(CylinderScene)),
    ]


#: Phases of a run whose wall time the summary shows (results.json has them all).
PHASES = ("mesh", "growth", "incompatibility", "postprocess", "output")

#: Columns of the summary table and their units.
COLUMNS = ("case", "status", "warnings", "ndof", "newton", "load_steps", "newton_per_step",
           "seconds", "strain_energy", "burgers_max", "max_principal_stress", *CHECKS,
           *(f"t_{p}" for p in PHASES))
UNITS = {"seconds": "s",
         **{k: CubeScene.metric_unit(k)
            for k in COLUMNS[COLUMNS.index("strain_energy"):-len(PHASES)]},
         **{f"t_{p}": "s" for p in PHASES}}


def row(label, results, seconds):
    """The summary row of one run."""
    m = results.metrics
    history = results.solver.get("growth")
    converged = [s for s in history.steps if s.converged] if history else []
    return {
        "case": label, "status": results.status, "warnings": len(results.warnings),
        "ndof": results.mesh.ndof,
        "newton": results.newton_iterations, "load_steps": len(converged),
        "newton_per_step": max((s.iterations for s in converged), default=0),
        "seconds": round(seconds, 2), "strain_energy": m.get("strain_energy"),
        "burgers_max": m.get("burgers_max"),
        "max_principal_stress": m.get("max_principal_stress"),
        **{k: m[k] for k in CHECKS if k in m},
        **{f"t_{p}": round(results.timings[p], 2) for p in PHASES if p in results.timings},
    }


def run_all(out=None, progress=SILENT, overwrite=False, quick=False):
    """Run every case (into ``out/<label>`` when ``out`` is given); returns the summary rows.

    A case that does not converge is a row with its status; the others still run.
    ``quick`` runs every case on its scene's ``preview`` preset."""
    if out is None:
        return _run_all(None, progress, overwrite, quick)
    with output.folder(out, overwrite=overwrite) as out:
        return _run_all(out, progress, overwrite, quick)


def _run_all(out, progress, overwrite, quick):
    """:func:`run_all` in a folder already prepared (or none)."""
    rows, results = [], {}
    runs = cases(quick)
    for label, scene in runs:
        start = time.perf_counter()
        try:
            r = scene.run(None if out is None else out / label, overwrite=overwrite,
                          progress=progress, label=label)
        except ConvergenceError as err:
            r = err.results
        results[label] = r
        rows.append(row(label, r, time.perf_counter() - start))
    if out is not None:
        files = [label for label, _ in runs]
        if all(results[k].status == DONE for k in FIGURE_CASES if k in results):
            files += _comparison_figures(out, results)
        files += ["summary.md", "summary.csv", "summary.json"]
        tables.write(out, "summary", rows, list(COLUMNS), UNITS, files=files)
    return rows


def summary_markdown(rows):
    """The summary table in markdown, with units."""
    return tables.markdown(rows, list(COLUMNS), UNITS)


#: The runs the comparison figures are drawn from.
FIGURE_CASES = ("hemisphere-linear", "hemisphere-concave", "hemisphere-convex", "disc-radial",
                "disc-circumferential")


def _comparison_figures(out, results):
    """Fig. 2g, 2h (hemisphere profiles) and 3e (disc fiber families); returns the files."""
    hemi = {k.split("-")[1]: results[k].profile("line")
            for k in ("hemisphere-linear", "hemisphere-concave", "hemisphere-convex")}
    R = hemi["linear"]["R"]
    plots.profiles(out / "fig2g_burgers.png", R,
                   {k: p["|b_meridional|"] for k, p in hemi.items()}, xlabel="R [mm]",
                   ylabel="|b| on the meridional plane [1/mm]",
                   title="Fig. 2g: hemisphere, growth profiles")
    plots.profiles(out / "fig2h_curl.png", R, {k: p["curlFg_sq"] for k, p in hemi.items()},
                   xlabel="R [mm]", ylabel="Curl Fg : Curl Fg [1/mm$^2$]",
                   title="Fig. 2h: hemisphere, growth profiles")
    disc = {k.split("-")[1]: results[k].profile("line")
            for k in ("disc-radial", "disc-circumferential")}
    curves = {}
    for family, p in disc.items():
        curves[f"sigma_r ({family} fibers)"] = p["sigma_r"]
        curves[f"sigma_theta ({family} fibers)"] = p["sigma_theta"]
    plots.profiles(out / "fig3e_disc_stress.png", disc["radial"]["R"], curves,
                   xlabel="R [mm]", ylabel="Cauchy stress [MPa]",
                   title="Fig. 3e: disc, GOH fiber families")
    return ["fig2g_burgers.png", "fig2h_curl.png", "fig3e_disc_stress.png"]
