"""``report.html`` of ``ngincompat paper``: one static page, every image inlined, a section per
paper section with the paper's findings, the measured values and verdicts
(:mod:`ngincompat.studies.findings`), the figures laid out as the paper's Figs. 1-7, the
interactive 3-D views (:mod:`ngincompat.studies.views`) in frames beside them, the runs'
warnings, and the table of deviations from the paper's parameters
(:mod:`ngincompat.studies.deviations`).

The page needs no server, no network and no script of its own: it can be opened from the
folder, mailed or archived (the static figures inlined; the views are the pages
``view_<case>.html`` beside it, each self-contained, framed when scrolled to and linked to be
opened alone). It is written from the folders of the runs (results.json, the PNGs and the
views), so a job that resumed writes the same page as one that ran through.
"""

from __future__ import annotations

import base64
import html
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ngincompat.atomic import atomic_path
from ngincompat.studies import deviations, figures, findings, views
from ngincompat.studies.sections import SECTIONS, Section
from ngincompat.workflow import io, output
from ngincompat.workflow.results import Results

#: Per section: figures of the case folders shown beside the field figures (file in the
#: case's folder, caption), as the paper's panels that are profiles or sections.
SCENE_FIGURES = {
    "cube": (("profile.png", "Fig. 1g: strain energy and Curl Fg : Curl Fg along X1"),
             ("burgers.png", "Fig. 1e: |b| along X1"),
             ("stress.png", "Fig. 1f: S11, S22, S33 along X1")),
    "cylinder": (("burgers.png", "Fig. 4b: |b| across the cylinder"),
                 ("profile.png", "Fig. 4d-e: strain energy and Curl Fg : Curl Fg")),
    "atrophy": (("brain.png", "Fig. 5a-b: the brain's surface, reference and atrophied"),
                ("sections.png", "Fig. 5c-e: sections through the brain"),
                ("volume_loss.png", "volume loss against time"),
                ("stress.png", "stresses along X1")),
    "skin": (("fields.png", "Fig. 6a-c: mid-thickness maps"),
             ("stress.png", "Fig. 6c: residual stress along X1")),
}

#: Figures of several panels side by side, shown at the page's width.
WIDE = {"fields.png", "sections.png", "brain.png", "fig7_folding.png"}

#: The field figures' captions by the paper's figure number.
CAPTIONS = {"1": "Fig. 1a-f", "2": "Fig. 2a-e", "3": "Fig. 3a-d", "4": "Fig. 4a-e",
            "6": "Fig. 6a-c"}

STYLE = """
body{font-family:system-ui,sans-serif;max-width:1400px;margin:auto;padding:1em;color:#222}
h1{font-size:1.6em} h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}
td,th{border:1px solid #bbb;padding:.3em .5em;vertical-align:top;text-align:left}
th{background:#eee} .agrees{background:#d8f0d8} .partly{background:#fbeec0}
.differs{background:#f6d0d0} .imposed{background:#dce6f4} .not-run{background:#e4e4e4}
figure{margin:.5em 0} figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:.9em;color:#444} .grid{display:flex;flex-wrap:wrap;gap:1em}
.grid figure{flex:1 1 420px;max-width:680px} .grid figure.wide{flex:1 1 100%;max-width:100%}
.warn{color:#8a4b00} code{background:#f3f3f3;padding:0 .2em}
.grid figure.view{flex:1 1 100%;max-width:100%}
.view iframe{width:100%;height:560px;border:1px solid #ddd}
"""


def _image(path: str | os.PathLike, caption: str, wide: bool = False) -> str:
    """A figure with the PNG inlined (nothing if the file is missing); ``wide``: the page's
    whole width (the field figures)."""
    path = Path(path)
    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    cls = ' class="wide"' if wide else ""
    return (f'<figure{cls}><img alt="{html.escape(caption)}" '
            f'src="data:image/png;base64,{data}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")


def _view(out: str | os.PathLike, label: str, results: Mapping[str, Results]) -> str:
    """The interactive view of the case ``label``: its page framed (loaded when scrolled to)
    and linked (nothing if the page is missing)."""
    name = next(iter(views.case_files(label)), None)
    if name is None or label not in results or not (Path(out) / name).is_file():
        return ""
    unit = results[label].units["length"]
    title = html.escape(f"{label}: {views.VIEWS[label].title.format(L=unit)}")
    return (f'<figure class="view"><iframe src="{name}" loading="lazy" title="{title}">'
            f'</iframe><figcaption>Interactive 3-D view, {title} (drag to turn, wheel to '
            f'zoom; Open Controls: clipping plane, colour range). <a href="{name}">Open it '
            "alone</a>.</figcaption></figure>")


def _table(header: Iterable[str], rows: Iterable[Sequence[object]],
           classes: Sequence[str] | None = None) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = []
    for i, r in enumerate(rows):
        cls = f' class="{classes[i]}"' if classes and classes[i] else ""
        body.append(f"<tr{cls}>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r)
                    + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def _results(out: str | os.PathLike, labels: Iterable[str]) -> dict[str, Results]:
    """label -> Results of the case folders that hold a readable run."""
    found = {}
    for label in labels:
        if (Path(out) / label / "results.json").is_file():
            found[label] = output.read(Path(out) / label)
    return found


def _settings(results: Results | None, section: Section) -> str:
    """The run's settings that differ from its scene's defaults."""
    if results is None:
        return ""
    cls = next(c for _, c, _ in section.cases)
    typed = cls.typed_settings({k: v[0] for k, v in cls.parameters().items()})
    changed = {k: v for k, v in results.params.items() if typed.get(k) != v}
    return ", ".join(f"{k}={v}" for k, v in changed.items()) or "none"


def _section(out: str | os.PathLike, section: Section, rows: Sequence[Mapping[str, Any]],
             results: Mapping[str, Results]) -> str:
    """The HTML of one paper section."""
    labels = [label for label, _, _ in section.cases]
    mine = [r for r in rows if r["case"] in labels]
    parts = [f'<section id="s{section.number}"><h2>{section.number} '
             f"{html.escape(section.title)}</h2>"]
    if not mine:
        parts.append("<p>Not run in this folder (<code>--only</code>).</p></section>")
        return "".join(parts)
    parts.append(_table(
        ("case", "status", "warnings", "unknowns", "Newton iterations", "seconds",
         "settings other than the defaults"),
        [(r["case"], r["status"], r["warnings"], r["ndof"], r["newton"], r["seconds"],
          _settings(results.get(r["case"]), section)) for r in mine]))
    judged = findings.judged(section.number, results)
    parts.append('<h3>Findings of the paper, measured</h3><table class="verdicts">'
                 "<tr><th>the paper states</th><th>Fig.</th><th>measured</th>"
                 "<th>verdict</th><th>why</th></tr>")
    for f, measured, verdict, reason in judged:
        cls = verdict.replace(" ", "-")
        parts.append(f'<tr class="{cls}"><td>{html.escape(f.states)}</td>'
                     f"<td>{html.escape(f.figure)}</td><td>{html.escape(measured)}</td>"
                     f"<td><b>{verdict}</b></td><td>{html.escape(reason)}</td></tr>")
    parts.append("</table>")
    images = []
    for label in labels:
        for name in figures.case_files(label):
            number = name[3]
            images.append(_image(Path(out) / name, f"{CAPTIONS[number]}: {label}, colour "
                                 "maps on the deformed body", wide=True))
        images.append(_view(out, label, results))
    for name in figures.section_files(section.number):
        images.append(_image(Path(out) / name, name[:-4].replace("_", " "), name in WIDE))
    for label in labels:
        for name, caption in SCENE_FIGURES.get(label.split("-")[0], ()):
            images.append(_image(Path(out) / label / name, f"{caption} ({label})",
                                 name in WIDE))
    parts.append('<div class="grid">' + "".join(i for i in images if i) + "</div>")
    warnings = [(label, w) for label in labels if label in results
                for w in results[label].warnings]
    if warnings:
        parts.append("<h3>Warnings of the runs</h3><ul>" + "".join(
            f'<li class="warn">{html.escape(label)}: {html.escape(w)}</li>'
            for label, w in warnings) + "</ul>")
    parts.append("</section>")
    return "".join(parts)


def write(out: str | os.PathLike, rows: Sequence[Mapping[str, Any]], resolution: str) -> Path:
    """Write ``out/report.html`` for the summary ``rows`` (the cases in the folder)."""
    out = Path(out)
    results = _results(out, [r["case"] for r in rows])
    counts: dict[str, int] = {}
    body = []
    ran = {r["section"] for r in rows}
    for section in SECTIONS:
        body.append(_section(out, section, rows, results))
        if section.number not in ran:
            continue
        for _, _, verdict, _ in findings.judged(section.number, results):
            counts[verdict] = counts.get(verdict, 0) + 1
    record = io.provenance()["provenance"]
    total = sum(r["seconds"] or 0 for r in rows)
    head = (f"<h1>Lee et al. 2021, <i>The geometry of incompatibility in growing soft "
            f"tissues</i>, reproduced with ngincompat</h1><p>Resolution <b>{resolution}</b>; "
            f"{len(rows)} runs, {total:.0f} s of run time; findings "
            + ", ".join(f"{v}: {counts[v]}" for v in findings.VERDICTS if v in counts)
            + " (imposed: the measured value is one the model is given, an input or a cap, "
            "counted apart from the agreements; each verdict follows a rule fixed from the "
            "paper's words, listed with its thresholds and their sources on the "
            "documentation's validation page). "
            f"Written {html.escape(str(record.get('date', '')))} on "
            f"{html.escape(str(record.get('host', '')))}.</p>"
            + ("<p>The preview resolution is a first look on coarse meshes: a finding that "
               "differs there because of a discretisation error (a stress that should vanish "
               "on a face, a deviation from a reference) is measured again with "
               "<code>ngincompat paper --resolution paper</code>.</p>"
               if resolution == "preview" else "")
            + "<p>Sections: " + " ".join(f'<a href="#s{s.number}">{s.number}</a>'
                                        for s in SECTIONS)
            + ' <a href="#deviations">deviations</a></p>')
    runs: dict[str, list[dict[str, Any]]] = {}
    for r in results.values():
        runs.setdefault(r.scene, []).append(r.params)
    table = deviations.rows(runs)
    dev = ('<section id="deviations"><h2>Where the settings differ from the paper, or choose '
           "what it does not state</h2><p>The values are those of the runs of this report "
           f"(resolution {resolution}), each with the default it replaces; a scene not run "
           "here shows its defaults.</p>"
           + _table(("section", "scene", "parameter", "paper", "ours (as run)", "reason",
                     "effect"), [tuple(d.values()) for d in table]) + "</section>")
    page = ("<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<title>ngincompat: the paper's sections 3.1-3.7</title>"
            f"<style>{STYLE}</style></head><body>{head}{''.join(body)}{dev}</body></html>")
    with atomic_path(out / "report.html") as tmp:
        tmp.write_text(page, encoding="utf-8")
    return out / "report.html"
