"""``ngincompat expansion``: the skin-expansion scene (section 3.6) for every expander, with
one summary table.

Each expander runs into its own folder ``out/<footprint>``; the summary (``summary.md``,
``.csv``, ``.json``) has one row per expander with the volume after inflation and what holds
it (the contact model, the default: the expander's height, the contact area, the largest
penetration, the largest and mean contact pressure; with ``--set expander=pressure``: the
pressure), growth (largest, mean over the footprint, at the apex), incompatibility (largest
|b|, at the apex, the distance of the largest from the centre) and the largest residual
stress after deflation (clamped, then released). An expander whose run fails is a row with
its status; the others still run.
"""

import os
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from geometries import FOOTPRINTS
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes.skin import SkinExpansionScene
from ngincompat.studies.variants import COMMON, run_variants, write_summary
from ngincompat.workflow import tables

#: The metrics of the summary, after the footprint and the columns every driver has.
METRICS = ("volume_inflated", "pressure_inflated",
           "expander_height_inflated", "contact_area_inflated", "penetration_max_inflated",
           "contact_pressure_max_inflated", "contact_pressure_mean_inflated", "theta_max",
           "theta_mean_footprint", "theta_apex", "burgers_max", "burgers_apex",
           "burgers_max_radius", "max_principal_stress_clamped",
           "max_principal_stress_released")
COLUMNS = ("footprint", *COMMON, *METRICS)
#: The columns that one expander model does not fill.
UNUSED = {"pressure": METRICS[2:7], "contact": METRICS[1:2]}
UNITS = {"seconds": "s", **{k: SkinExpansionScene.metric_unit(k) for k in METRICS}}


def run_all(out: str | os.PathLike | None = None, footprints: Iterable[str] = FOOTPRINTS,
            progress: Progress = SILENT, overwrite: bool = False,
            **settings: Any) -> list[dict[str, Any]]:
    """Run every expander (into ``out/<footprint>`` when ``out`` is given); returns the rows.

    ``settings`` are skin-scene parameters by name (strings are converted as on the command
    line); they are checked for every expander before anything runs.
    """
    scenes = {f: SkinExpansionScene.from_settings({**settings, "footprint": f})
              for f in footprints}
    model = next(iter(scenes.values())).expander if scenes else SkinExpansionScene.expander
    columns = [c for c in COLUMNS if c not in UNUSED[model]]
    rows, _ = run_variants(scenes, out, key="footprint",
                           metrics=[m for m in METRICS if m not in UNUSED[model]],
                           progress=progress, overwrite=overwrite, label="skin")
    if out is not None:
        write_summary(out, rows, columns, UNITS)
    return rows


def summary_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """The summary table in markdown, with units (the columns of the rows' model)."""
    return tables.markdown(rows, [c for c in COLUMNS if rows and c in rows[0]], UNITS)
