"""``ngincompat paper``'s report.html, opened in a real browser (headless Chromium): it loads
without console errors, every image is there and not blank, every section that ran has its
table of verdicts (the rules behind the verdicts: tests/studies/findings/)."""

import base64
import html
import io
import json
import re
import shutil
import subprocess

import numpy as np
import pytest
from matplotlib.image import imsave

from ngincompat.cli import main
from ngincompat.studies import deviations, findings, paper

CHROMIUM = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")
                 if shutil.which(n)), None)
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="no Chromium on PATH (Debian: apt-get install chromium; .ci/run "
    "installs it where apt-get is available)")

#: Put first in the page's head: records error events (scripts, images that fail to load) and
#: console.error calls; after the load, writes what it found into <pre id="check">: the
#: errors, every image's size and pixel variance (grey levels, on a canvas), the frames' pages,
#: and per section its tables of verdicts.
PROBE = """<script>
window.__errors = [];
window.addEventListener('error', e => window.__errors.push(String(e.message ||
    ('failed to load ' + ((e.target && (e.target.src || '')) + '').slice(-60)))), true);
const __error = console.error;
console.error = (...a) => { window.__errors.push(a.join(' ')); __error(...a); };
window.addEventListener('load', () => {
  const images = [...document.images].map(img => {
    let variance = null;
    if (img.complete && img.naturalWidth > 0) {
      const w = Math.min(img.naturalWidth, 600), h = Math.min(img.naturalHeight, 600);
      const c = document.createElement('canvas'); c.width = w; c.height = h;
      const g = c.getContext('2d'); g.drawImage(img, 0, 0, w, h);
      const d = g.getImageData(0, 0, w, h).data;
      let s = 0, s2 = 0, n = 0;
      for (let i = 0; i < d.length; i += 4) {
        const v = (d[i] + d[i + 1] + d[i + 2]) / 3; s += v; s2 += v * v; n++; }
      variance = s2 / n - (s / n) ** 2;
    }
    return {alt: img.alt, width: img.naturalWidth, variance: variance};
  });
  const frames = [...document.querySelectorAll('iframe')].map(f => f.getAttribute('src'));
  const sections = [...document.querySelectorAll('section')].map(s => ({id: s.id,
    tables: s.querySelectorAll('table.verdicts').length,
    rows: s.querySelectorAll('table.verdicts tr').length}));
  const pre = document.createElement('pre'); pre.id = 'check';
  pre.textContent = JSON.stringify({errors: window.__errors, images, frames, sections});
  document.body.appendChild(pre);
});
</script>"""


def browse(page, tmp_path, screenshot=None):
    """Open ``page`` (HTML text) with :data:`PROBE` in headless Chromium, from the folder
    ``tmp_path`` (its relative links resolve there); returns the probe's record and the
    console lines Chromium logged."""
    probed = tmp_path / "probed.html"
    probed.write_text(page.replace("<head>", "<head>" + PROBE, 1), encoding="utf-8")
    # files beside the page are of its origin (the documentation site's images; without
    # this, Chromium would not let the probe read their pixels from a file:// page); WebGL
    # (the report's interactive views) on SwiftShader, there being no GPU
    flags = [CHROMIUM, "--headless", "--no-sandbox", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--hide-scrollbars",
             "--enable-logging=stderr", "--v=0", "--virtual-time-budget=10000",
             "--window-size=1400,3000", "--allow-file-access-from-files"]
    done = subprocess.run([*flags, "--dump-dom", probed.as_uri()], capture_output=True,
                          text=True, timeout=180)
    if screenshot is not None:
        subprocess.run([*flags, f"--screenshot={screenshot}", (tmp_path / "probed.html")
                        .as_uri()], capture_output=True, timeout=180)
    found = re.search(r'<pre id="check">(.*?)</pre>', done.stdout, re.S)
    assert found, done.stderr[-2000:]
    console = [line for line in done.stderr.splitlines() if ":CONSOLE" in line]
    return json.loads(html.unescape(found.group(1))), console


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """The report of sections 3.1 and 3.4 on their preview settings."""
    out = tmp_path_factory.mktemp("paper")
    assert main(["paper", "--out", str(out), "--only", "3.1,3.4", "-q"]) == 0
    return out


@needs_chromium
def test_the_probe_sees_a_broken_image_and_a_console_error(tmp_path):
    """The browser check can fail: a missing image and console.error are caught, a blank
    image has no variance."""
    png = io.BytesIO()
    imsave(png, np.ones((8, 8, 3)), format="png")            # one colour
    blank = base64.b64encode(png.getvalue()).decode("ascii")
    page = ("<!DOCTYPE html><html><head></head><body><img alt='gone' src='missing.png'>"
            f"<img alt='blank' src='data:image/png;base64,{blank}'>"
            "<script>console.error('broken')</script></body></html>")
    record, console = browse(page, tmp_path)
    assert any("broken" in e for e in record["errors"])
    assert any("missing.png" in e for e in record["errors"])
    images = {i["alt"]: i for i in record["images"]}
    assert images["gone"]["width"] == 0
    assert images["blank"]["variance"] == pytest.approx(0.0)
    assert console


@needs_chromium
def test_report_loads_with_its_images_and_verdicts(report, tmp_path):
    page = (report / "report.html").read_text(encoding="utf-8")
    assert "http://" not in page and "https://" not in page       # nothing from the network
    shot = report / "screenshot.png"
    for view in report.glob("view_*.html"):                   # the frames' pages beside it
        shutil.copy(view, tmp_path)
    record, console = browse(page, tmp_path, screenshot=shot)
    assert record["errors"] == [] and console == []           # the framed views' too
    assert record["frames"] == ["view_cube.html"]             # 3.4's cylinder has none
    assert len(record["images"]) >= 6
    for image in record["images"]:
        assert image["width"] > 0, image["alt"]
        assert image["variance"] > 20, image["alt"]          # not blank
    sections = {s["id"]: s for s in record["sections"]}
    assert set(sections) == {f"s{n}" for n in paper.NUMBERS} | {"deviations"}
    for number in ("3.1", "3.4"):
        tables = sections[f"s{number}"]
        expected = sum(f.section == number for f in findings.FINDINGS)
        assert tables["tables"] == 1 and tables["rows"] == expected + 1
    assert sections["s3.5"]["tables"] == 0                    # not run here: no verdicts
    assert shot.stat().st_size > 0


@needs_chromium
def test_the_cubes_interactive_view_draws_offline(report, tmp_path):
    """The paper job's view of 3.1 (Fig. 1e, |b| on the deformed cube) opens on its own
    without the network and draws its colour map; the summary lists it."""
    from workflow.test_webview import assert_offline_view, look
    page = (report / "view_cube.html").read_text(encoding="utf-8")
    assert "|b| on the planes normal to n2 [1/mm]" in page
    shot = report / "view_cube.png"
    record, console = look(page, tmp_path, shot)
    assert_offline_view(record, console, tmp_path, shot)
    summary = json.loads((report / "summary.json").read_text())
    assert "view_cube.html" in summary["files"]
    assert not (report / "view_cylinder.html").exists()


def test_report_lists_every_deviation_with_the_settings_it_was_run_at(report):
    """The deviation table gives the values of the report's runs (the preview's, each with
    the default it replaces), the defaults of the scenes not run, and the modelling choices
    no parameter sets."""
    page = (report / "report.html").read_text(encoding="utf-8")
    runs = {}
    for name in ("cube", "cylinder"):
        record = json.loads((report / name / "results.json").read_text())
        runs.setdefault(record["scene"], []).append(record["params"])
    for row in deviations.rows(runs):
        assert html.escape(row["ours"]) in page
    # the cube and the cylinder as run at the preview, not their defaults
    assert "elements = tet, order = 3 (default 6), maxh = 0.5 mm" in page
    assert "order = 2 (default 3), maxh = 0.5 mm (default 0.25)" in page
    assert "mu = 0.55 MPa" in page              # the skin's default, read from ref. [77] via 3.1
    assert "periphery clamped" in page          # a choice without a parameter


def test_a_second_run_resumes_and_overwrite_recomputes(report, capsys):
    """Finished cases of the same settings are read back; other settings need --overwrite."""
    before = (report / "cube" / "results.json").stat().st_mtime_ns
    assert main(["paper", "--out", str(report), "--only", "3.1", "-q"]) == 0
    assert (report / "cube" / "results.json").stat().st_mtime_ns == before
    summary = json.loads((report / "summary.json").read_text())
    assert [r["case"] for r in summary["rows"]] == ["cube", "cylinder"]
    assert main(["paper", "--out", str(report), "--only", "3.1", "--resolution", "paper",
                 "-q"]) == 2
    assert "other settings" in capsys.readouterr().err
