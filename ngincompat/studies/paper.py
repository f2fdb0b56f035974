"""``ngincompat paper``: the paper's seven result sections, 3.1 to 3.7, one summary and one
report.

Section 3.1 runs the cube; 3.2 the hemisphere with the linear, concave and convex profiles
(and the linear one in symmetry mode, checked against the 1-D radial solution); 3.3 the disc
with radial and circumferential GOH fibers; 3.4 the cylinder; 3.5 brain atrophy; 3.6 skin
expansion under the four expanders; 3.7 cortical folding for the three axon fields. Each run
writes its own folder ``DIR/<case>``; the job writes the field figures of the paper's Figs.
1-7 (``fig*.png``), the profile figures of Figs. 2g-h and 3e, the interactive 3-D views
(``view_<case>.html``, :mod:`ngincompat.studies.views`), the summary (``summary.md``,
``.csv``, ``.json``, one row per case) and ``report.html`` (:mod:`ngincompat.studies.report`).

``resolution`` chooses the settings: ``preview`` (the default; each scene's ``preview``
preset) or ``paper`` (each scene's ``paper`` preset: the resolution of the paper's figures,
with the scene's defaults, which are the paper's parameters where the paper gives them).
The job resumes: a case whose folder holds a finished run of the same settings (and whose
field figure and view exist) is read back, not recomputed, unless ``overwrite``; so an interrupted
job continues where it stopped, and ``only`` runs some sections into a folder that holds the
others. The cases run side by side in worker processes (``jobs``, :mod:`.workers`), the
longest sections first; each draws its field figure and view where its fields live, and the
job draws a section's figures once all its cases have ended.
"""

from __future__ import annotations

import functools
import os
from collections import deque
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ngincompat.errors import ConvergenceError, ParameterError
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes import HemisphereScene
from ngincompat.scenes.base import Scene
from ngincompat.studies import figures, report, views, workers
from ngincompat.studies.sections import NUMBERS, SECTIONS, Section
from ngincompat.workflow import io, output, tables
from ngincompat.workflow.results import DONE, Results

#: The resolutions of :func:`run_all`.
RESOLUTIONS = ("preview", "paper")

#: The hemispheres are solved as quarters (their mirror planes X1 = 0, X2 = 0 held): the same
#: solution at a quarter of the unknowns, with the centre refined to 0.04 closer
#: to the radial solution than the full hemisphere (``docs/measurements/solver-costs.md``,
#: "The prescribed scenes: levers behind the defaults").
HEMISPHERE = dict(model="quarter", centre_maxh=0.04)


def resolution_settings(cls: type[Scene], resolution: str) -> dict[str, Any]:
    """The settings of ``cls`` at ``resolution`` (see the module docstring)."""
    if resolution not in RESOLUTIONS:
        raise ParameterError(f"--resolution {resolution!r}: allowed "
                             + " or ".join(RESOLUTIONS))
    return cls.preset_settings(resolution)


def sections(only: Collection[str] | None = None) -> list[Section]:
    """The sections to run: all, or those whose numbers ``only`` lists."""
    if not only:
        return list(SECTIONS)
    unknown = [n for n in only if n not in NUMBERS]
    if unknown:
        raise ParameterError(f"--only {','.join(unknown)}: allowed sections "
                             + ", ".join(NUMBERS))
    return [s for s in SECTIONS if s.number in only]


def cases(resolution: str = "preview",
          only: Collection[str] | None = None) -> list[tuple[Section, str, Scene]]:
    """(section, label, scene) of every run of the chosen sections."""
    out = []
    for section in sections(only):
        for label, cls, variant in section.cases:
            paper = HEMISPHERE if cls is HemisphereScene else {}
            settings = {**paper, **resolution_settings(cls, resolution), **variant}
            out.append((section, label, cls.from_settings(settings)))
    return out


#: Phases of a run whose wall time the summary shows (results.json has them all).
PHASES = ("mesh", "growth", "incompatibility", "postprocess", "output")

#: Verification metrics reported in the summary, by scene (closed forms and references).
CHECKS = ("G_error_L2_rel", "radial_sigma_rr_error", "radial_sigma_thetatheta_error",
          "b_radial_rel", "b_eq22_error", "sigma_r_rim_rel", "b_eq27_error",
          "Fe_rotation_deviation")

#: Columns of the summary table and their units.
COLUMNS = ("section", "case", "units", "status", "warnings", "ndof", "newton", "load_steps",
           "newton_per_step", "seconds", "strain_energy", "burgers_max",
           "max_principal_stress", *CHECKS, *(f"t_{p}" for p in PHASES))
UNITS = {"seconds": "s", **{f"t_{p}": "s" for p in PHASES}}


def row(section: str, label: str, results: Results) -> dict[str, Any]:
    """The summary row of one run; ``units``: its length and stress units (the sections
    differ: mm and MPa, cm and kPa); ``seconds``: the sum of its phases' times."""
    m = results.metrics
    steps = [s for h in results.solver.values() for s in h.steps if s.converged]
    units = results.units
    return {
        "section": section, "case": label,
        "units": f"{units.get('length', '')}, {units.get('stress', '')}",
        "status": results.status,
        "warnings": len(results.warnings), "ndof": results.mesh.ndof,
        "newton": results.newton_iterations, "load_steps": len(steps),
        "newton_per_step": max((s.iterations for s in steps), default=0),
        "seconds": round(sum(results.timings.values()), 2),
        "strain_energy": m.get("strain_energy"), "burgers_max": m.get("burgers_max"),
        "max_principal_stress": m.get("max_principal_stress",
                                      m.get("max_principal_stress_released")),
        **{k: m[k] for k in CHECKS if k in m},
        **{f"t_{p}": round(results.timings[p], 2) for p in PHASES if p in results.timings},
    }


def default_jobs(resolution: str, cores: int | None = None) -> int:
    """How many runs :func:`run_all` runs side by side by default: one per core (at most
    :data:`MAX_JOBS`) at the preview resolution, one at the paper's, whose largest runs
    take many times a preview's memory (docs/measurements/paper-job.md)."""
    cores = cores or os.cpu_count() or 1
    return 1 if resolution == "paper" else max(1, min(cores, MAX_JOBS))


#: The most runs side by side by default: each preview run holds its own mesh and solver.
MAX_JOBS = 4


def run_all(out: str | os.PathLike | None = None, progress: Progress = SILENT,
            overwrite: bool = False, resolution: str = "preview",
            only: Collection[str] | None = None, jobs: int | None = None) -> list[dict[str, Any]]:
    """Run the sections (``only``: their numbers; default all) at ``resolution``; with
    ``out``, into ``out/<case>`` with the figures, the summary and report.html, resuming
    finished cases unless ``overwrite``, ``jobs`` runs side by side in worker processes
    (default :func:`default_jobs`; 1: one after the other in this process). Returns the
    summary rows of the cases run now and before. A case that does not converge is a row with
    its status; the others still run."""
    runs = cases(resolution, only)
    if jobs is None:
        jobs = default_jobs(resolution)
    elif not (isinstance(jobs, int) and jobs >= 1):
        raise ParameterError(f"--jobs {jobs!r}: allowed an integer >= 1")
    if out is None:
        return [row(s.number, label, _run_case(label, scene, None, progress, False))
                for s, label, scene in runs]
    with output.folder(out, overwrite=overwrite, resume=not overwrite) as out:
        reuse = {label: _finished(out, label, scene) for _, label, scene in runs}
        _refuse_other_settings(out, runs, reuse, overwrite)
        done = _read_summary(out) if not overwrite else {}
        results, drawn = {}, set()

        def finish(section: Section, label: str, r: Results) -> None:
            """Record a case that ended; draw each section whose cases have all ended."""
            results[label], done[label] = r, row(section.number, label, r)
            for s in sections(only):
                labels = [lab for t, lab, _ in runs if t is s]
                if s.number not in drawn and all(lab in results for lab in labels):
                    figures.section_figures(out, s, results)
                    _write(out, done, resolution)
                    drawn.add(s.number)

        todo: list[tuple[Section, str, Scene]] = []
        for s, label, scene in runs:
            if reuse[label] is None:
                todo.append((s, label, scene))
                continue
            progress.line(f"{label}: finished before, read from {out / label}")
            finish(s, label, reuse[label])  # type: ignore[arg-type]  # not None: above
        try:
            if jobs == 1 or len(todo) <= 1:
                for s, label, scene in todo:
                    r = _run_case(label, scene, out, progress, overwrite=True)
                    _draw(out, label, resolution, r)
                    finish(s, label, r)
            else:
                _side_by_side(todo, out, resolution, min(jobs, len(todo)), progress, finish)
        except KeyboardInterrupt:       # Ctrl-C, SIGTERM: the summary of what has ended
            if done:
                _write(out, done, resolution)
            raise
        return [done[label] for _, label, _ in runs if label in done]


def _side_by_side(todo: Sequence[tuple[Section, str, Scene]], out: Path, resolution: str, jobs: int,
                  progress: Progress, finish: Callable[[Section, str, Results], None]) -> None:
    """Run the cases ``todo`` in ``jobs`` worker processes, the last sections first (they take
    longest), each drawing its figure and view where it ran; ``finish`` as each ends."""
    section_of = {label: s for s, label, _ in todo}
    tasks = deque((label, {"scene": scene, "folder": str(out / label), "threads": None,
                           "quiet": progress.quiet,
                           "after": functools.partial(_draw, out, label, resolution)})
                  for _, label, scene in reversed(todo))

    def ended(label: str, outcome: dict[str, Any]) -> None:
        if outcome["status"] == workers.FAILED:
            error_file = out / label / workers.ERROR_FILE
            raise RuntimeError(f"{label} failed: {outcome['error']}" + (
                f" (its traceback: {error_file})" if error_file.is_file() else ""))
        if not (out / label / "results.json").is_file():   # interrupted before it began
            return
        finish(section_of[label], label, output.read(out / label))

    workers.run_side_by_side(tasks, workers.LocalPool(jobs, None, progress), ended)


def _run_case(label: str, scene: Scene, out: Path | None, progress: Progress,
              overwrite: bool) -> Results:
    """Run one case; returns its results (those of the last converged state for a case that
    did not converge)."""
    try:
        return scene.run(None if out is None else out / label, overwrite=overwrite,
                         progress=progress, label=label)
    except ConvergenceError as err:
        return err.results


def _draw(out: Path, label: str, resolution: str, results: Results) -> None:
    """The field figure and the interactive view of one case, from its live fields."""
    figures.case_figure(out, label, results, resolution)
    views.case_view(out, label, results, resolution)


def _finished(out: Path, label: str, scene: Scene) -> Results | None:
    """The results of ``out/label`` if it holds a finished run of ``scene``'s settings whose
    field figure and interactive view exist, else None."""
    path = Path(out) / label
    if not (path / "results.json").is_file():
        return None
    try:
        r = output.read(path)
    except ParameterError:
        return None
    if r.status != DONE or r.params != scene.settings():
        return None
    drawn = [*figures.case_files(label), *views.case_files(label)]
    return r if all((Path(out) / f).is_file() for f in drawn) else None


def _refuse_other_settings(out: Path, runs: Iterable[tuple[Section, str, Scene]],
                           reuse: Mapping[str, Results | None], overwrite: bool) -> None:
    """Before anything runs: a case folder holding a run of other settings is replaced only
    with ``overwrite`` (a finished run of the same settings is reused, an unfinished one
    of them continued)."""
    if overwrite:
        return
    for _, label, scene in runs:
        path = out / label / "results.json"
        if reuse[label] is None and path.is_file():
            try:
                params = output.read(path.parent).params
            except ParameterError:
                params = None
            if params != scene.settings():
                raise ParameterError(
                    f"--out {out}: {label} holds a run of other settings (another "
                    "--resolution?): choose another folder, or pass --overwrite to replace "
                    "it")


def _read_summary(out: Path) -> dict[str, dict[str, Any]]:
    """The rows of an earlier summary in ``out`` by case (none if there is none)."""
    path = Path(out) / "summary.json"
    if not path.is_file():
        return {}
    return {r["case"]: r for r in io.read_json(path).get("rows", [])}


def _write(out: Path, rows: Mapping[str, Mapping[str, Any]], resolution: str) -> None:
    """The summary and the report of every case the folder holds."""
    order = [label for s in SECTIONS for label, _, _ in s.cases]
    ordered = [rows[k] for k in order if k in rows]
    names = [r["case"] for r in ordered]
    drawn = [*figures.all_files(names), *(f for n in names for f in views.case_files(n))]
    pictures = [f for f in drawn if (Path(out) / f).is_file()]
    files = [*names, *pictures, "report.html", "summary.md", "summary.csv", "summary.json"]
    tables.write(out, "summary", ordered, list(COLUMNS), UNITS, files=files,
                 resolution=resolution)
    report.write(out, ordered, resolution)


def summary_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The summary table in markdown, with units."""
    return tables.markdown(rows, list(COLUMNS), UNITS)
