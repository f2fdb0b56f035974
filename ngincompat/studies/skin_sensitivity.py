"""Section 3.6's findings under the choices the paper leaves open: ``ngincompat bench skin``.

The paper finds that "the square expander results in the largest area growth and the
circular expander yields the smallest growth" and a residual stress of "about 40 kPa" at
the base, with 40 kPa compression where the expander touched (section 3.6, Fig. 6). It does
not give the expanders' sizes (only their volume, 50 cc), the dome's shape, the skin's
modulus (it cites ref. [77]) or the Hill law's constants (eq. 46). Each choice of
:data:`CHOICES` changes one of them from the scene's defaults; for each, the four expanders
run (:func:`ngincompat.studies.expansion.run_all`'s scenes, one after the other) and the
report's own rules judge them (:mod:`ngincompat.studies.findings`: ``skin-order`` and
``skin-stress``, unchanged). The table says which choices, if any, give the paper's order
and its 40 kPa.

Not varied, for want of a parameter: the skin's thickness (0.3 cm, the paper's) and its
edge conditions (the periphery clamped; :mod:`ngincompat.studies.deviations`).
"""

from __future__ import annotations

import os
from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from geometries import FOOTPRINTS, footprint_area
from ngincompat.errors import ParameterError
from ngincompat.progress import SILENT, Progress
from ngincompat.scenes.skin import SkinExpansionScene
from ngincompat.studies import findings
from ngincompat.studies.findings import Finding
from ngincompat.studies.variants import run_variants
from ngincompat.workflow import tables
from ngincompat.workflow.results import Results

#: The width of every footprint in the "equal base size" choice (cm): the default rectangle's
#: length (7 x 3.5 cm).
WIDTH = 7.0


@dataclass(frozen=True)
class Choice:
    """One reading of what the paper leaves open, by ``name`` (a word for the command line)
    and ``what`` it is: ``settings`` for every expander, and per footprint ``each``
    (footprint -> settings) on top of them."""

    name: str
    what: str
    settings: dict = field(default_factory=dict)
    each: dict = field(default_factory=dict)

    def scene(self, footprint: str, base: Mapping[str, Any]) -> SkinExpansionScene:
        """The skin scene of ``footprint`` under this choice and the ``base`` settings."""
        return SkinExpansionScene.from_settings({"outputs": "none", **base, **self.settings,
                                                 **self.each.get(footprint, {}),
                                                 "footprint": footprint})


#: The readings studied: the defaults, then one change each.
CHOICES = (
    Choice("defaults", "the scene's: equal base areas ({footprint_area:g} cm^2), a rigid dome "
           "in contact, mu = {mu:g} MPa, k = {k:g} per day, theta_crit = {theta_crit:g}".format(
               **{k: v[0] for k, v in SkinExpansionScene.parameters().items()})),
    Choice("equal-size", f"every footprint {WIDTH:g} cm wide (the rectangle "
           f"{WIDTH:g} x {WIDTH / 2:g} cm, the square {WIDTH:g} x {WIDTH:g} cm, the circle and "
           f"the crescent's disc {WIDTH:g} cm across)",
           each={f: {"footprint_area": round(footprint_area(f, WIDTH), 6)}
                 for f in FOOTPRINTS}),
    Choice("pressure", "no dome: a uniform pressure on the footprint",
           {"expander": "pressure"}),
    Choice("mu-low", "mu = 0.1786 MPa: E = 0.5 MPa, nu = 0.4 (Buganza Tepole et al. 2011), "
           "a third of the default", {"mu": 0.1786}),
    Choice("k-half", "the Hill law's rate k = 0.05 per day", {"k": 0.05}),
    Choice("k-double", "the Hill law's rate k = 0.2 per day", {"k": 0.2}),
    Choice("theta-crit-1", "growth wherever the skin is stretched at all",
           {"theta_crit": 1.0}),
)

#: What ``--quick`` runs: two choices on a coarse patch, inflated to 3 cc in one step and
#: grown for half a day (seconds per expander).
QUICK = ("defaults", "equal-size")
#: The coarse patch of ``--quick``.
QUICK_SETTINGS = {"maxh": 3.0, "order": 1, "growth_order": 0, "g_order": 2, "volume": 3.0,
                  "inflation_steps": 1, "theta_crit": 1.0, "hold_days": 0.5, "dt": 0.5}

#: The columns of the table: the choice, the runs' status, the order and the stresses with
#: the verdicts of the findings :data:`JUDGED`.
COLUMNS = ("choice", "what", "status", "order", "order_verdict", "tension_released",
           "compression_contact", "stress_verdict")
UNITS = {"tension_released": "kPa", "compression_contact": "kPa"}
#: The findings judged, by key.
JUDGED = ("skin-order", "skin-stress")


def _finding(key: str) -> Finding:
    return next(f for f in findings.FINDINGS if f.key == key)


def judge(results: Mapping[str, Results]) -> dict[str, Any]:
    """The row's measures and verdicts from ``results`` (footprint -> Results): the order of
    the mean growth over the footprints (least to most), the largest released tension and
    the largest compression in the former contact zone (kPa; None without a contact zone),
    and the verdicts of the findings :data:`JUDGED`."""
    by_label = {f"skin-{f}": r for f, r in results.items()}
    _, order_verdict, _ = _finding("skin-order").judge(by_label)
    _, stress_verdict, _ = _finding("skin-stress").judge(by_label)
    done = [r for r in results.values() if r.converged]
    mean = {f: r.metrics["theta_mean_footprint"] for f, r in results.items() if r.converged}
    kpa = 1000 if SkinExpansionScene.units["stress"] == "MPa" else 1
    tension = max((r.metrics["max_principal_stress_released"] for r in done), default=None)
    contact = [r.metrics.get("min_principal_stress_contact_zone") for r in done]
    contact = [c for c in contact if c is not None]
    return {"status": ", ".join(sorted({r.status for r in results.values()})),
            "order": " < ".join(f"{f} {mean[f]:.3g}"
                                for f in sorted(mean, key=mean.get)),  # type: ignore[arg-type]
            "order_verdict": order_verdict,
            "tension_released": None if tension is None else round(kpa * tension, 1),
            # contact: its Nones filtered out above
            "compression_contact": (
                round(-kpa * min(contact), 1)  # type: ignore[operator, type-var]
                if contact else None),
            "stress_verdict": stress_verdict}


def table(choices: Collection[str] | None = None, settings: Mapping[str, Any] | None = None,
          out: str | os.PathLike | None = None,
          progress: Progress = SILENT) -> list[dict[str, Any]]:
    """Run the four expanders under each choice named in ``choices`` (default: all of
    :data:`CHOICES`) with the base ``settings``; returns the rows (:data:`COLUMNS`). With
    ``out`` every run's results.json is kept in ``out/runs/<choice>/<footprint>`` (no other
    files: ``outputs`` "none" unless ``settings`` say otherwise).

    Raises
    ------
    ParameterError
        An unknown choice, or settings a scene refuses (before anything runs).
    """
    known = {c.name: c for c in CHOICES}
    for name in choices or ():
        if name not in known:
            raise ParameterError(f"unknown choice {name!r}: allowed {', '.join(known)}")
    chosen = [known[n] for n in choices] if choices else list(CHOICES)
    scenes = {c.name: {f: c.scene(f, settings or {}) for f in FOOTPRINTS} for c in chosen}
    rows = []
    for choice in chosen:
        folder = None if out is None else Path(out) / "runs" / choice.name
        _, results = run_variants(scenes[choice.name], folder, key="footprint",
                                  progress=progress, overwrite=True,
                                  label=f"skin {choice.name}")
        rows.append({"choice": choice.name, "what": choice.what, **judge(results)})
        progress.line(f"skin {choice.name}: {rows[-1]['order']}; {rows[-1]['order_verdict']}, "
                      f"{rows[-1]['stress_verdict']}")
    return rows


def main(choices: Collection[str] | None = None, quick: bool = False,
         out: str | os.PathLike | None = None) -> list[str]:
    """``ngincompat bench skin``: :func:`table` (``quick``: :data:`QUICK` on
    :data:`QUICK_SETTINGS`); returns the lines to print. With ``out`` the table is written as
    ``sensitivity`` (.md, .csv, .json)."""
    rows = table(choices or (QUICK if quick else None), QUICK_SETTINGS if quick else None,
                 out=out, progress=Progress())
    if out is not None:
        tables.write(out, "sensitivity", rows, list(COLUMNS), UNITS)
    paper = [r["choice"] for r in rows
             if r["order_verdict"] == findings.AGREES and r["stress_verdict"] == findings.AGREES]
    return [tables.markdown(rows, list(COLUMNS), UNITS), "",
            "choices that give the paper's order and its 40 kPa: "
            + (", ".join(paper) if paper else "none")]
