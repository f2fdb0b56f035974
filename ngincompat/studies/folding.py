"""``ngincompat folding``: the cortical-folding scene (section 3.7) for every axon field, with
one summary table and the figure of Fig. 7 a-c, one row per axon field.

Each axon field runs into its own folder ``out/<axons>`` (:mod:`ngincompat.studies.variants`); the
summary (``summary.md``, ``.csv``, ``.json``) has one row per axon field with the onset
(growth and wavelength), how far the growth went (time and cortex growth), the smallest
elastic Jacobian, the self-contact of the top surface (length in contact, largest
penetration), the fold amplitude at the end, the largest axon growth, the largest |b| on the
plane normal to the paper's e3 and its depth below the top, the mean |b| in the band of one
cortex thickness around the interface, and, for runs that were released, the largest
principal stress and the curvature of the top after the release: side by side, the three
axon fields' measures of the paper's finding. An axon field whose
run fails is a row with its status; the others still run. ``fields.png`` has one row per
axon field and one column per field of :data:`ngincompat.scenes.folding.PANELS` that every
row has, on one colour scale per column.
"""

import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from ngincompat.mechanics import fields
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes.folding import FoldingScene, panels
from ngincompat.studies.variants import COMMON, run_variants, write_summary
from ngincompat.workflow import plots, tables
from ngincompat.workflow.results import Results

#: The axon fields of Fig. 7, left to right.
AXON_FIELDS = fields.AXONS

#: The metrics of the summary, after the axon field and the columns every driver has.
METRICS = ("onset_growth", "onset_wavelength", "t_reached", "theta_c_reached", "Je_min",
           "self_contact_area", "self_contact_penetration_max", "fold_amplitude",
           "sulci", "sulcus_depth", "theta_a_max", "burgers_max", "burgers_max_depth",
           "burgers_interface_mean",
           "max_principal_stress_released", "top_curvature_released")
#: Columns of the summary: the axon field, the columns every driver has, the metrics.
COLUMNS = ("axons", *COMMON, *METRICS)
#: The columns that only a released run fills: in the summary when a row has them.
RELEASED = METRICS[-2:]
UNITS = {"seconds": "s", **{k: FoldingScene.metric_unit(k) for k in METRICS}}


def run_all(out: str | os.PathLike | None = None, axons: Iterable[str] = AXON_FIELDS,
            progress: Progress = SILENT, overwrite: bool = False,
            **settings: Any) -> tuple[list[dict[str, Any]], dict[str, Results]]:
    """Run the folding scene for every axon field of ``axons`` (into ``out/<axons>`` when
    ``out`` is given, with the summary and ``fields.png``); returns the rows and the results
    by axon field.

    ``settings`` are folding-scene parameters by name (strings are converted as on the
    command line); they are checked for every axon field before anything runs.
    """
    scenes = {a: FoldingScene.from_settings({**settings, "axons": a}) for a in axons}
    rows, results = run_variants(scenes, out, key="axons", metrics=METRICS,
                                 progress=progress, overwrite=overwrite, label="folding")
    if out is not None:
        files: list[str] = []
        figure = fields_figure(results, next(iter(scenes.values())))
        if figure is not None:
            plots.save(figure, Path(out) / "fields.png")
            files.append("fields.png")
        write_summary(out, rows, columns(rows), UNITS, files=files)
    return rows, results


def columns(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """The summary's columns: those of :data:`COLUMNS`, the release's when a row has them."""
    return [c for c in COLUMNS
            if c not in RELEASED or any(row.get(c) is not None for row in rows)]


def fields_figure(results: Mapping[str, Results], scene: FoldingScene) -> Figure | None:
    """Fig. 7 a-c: one row per axon field whose run has sampled fields, or None if none
    (units and the stress floor from ``scene``)."""
    rows = {axons: r.profiles["section"] for axons, r in results.items()
            if "section" in r.profiles}
    if not rows:
        return None
    L = scene.units["length"]
    return plots.deformed_figure(rows, panels(scene), ("X1", "X2"), f"X1 [{L}]", f"X2 [{L}]",
                                 "cortical folding: the deformed bilayer per axon field",
                                 floor=1e-3 * scene.mu_white)


def summary_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The summary table in markdown, with units."""
    return tables.markdown(rows, columns(rows), UNITS)
