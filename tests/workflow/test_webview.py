"""The interactive 3-D views (:mod:`ngincompat.workflow.webview`): the scene carries the field
and the deformation it was given (checked against their closed forms), a field defined per
material region is drawn on the boundary, and the page, opened in headless Chromium (WebGL on
SwiftShader) with every host name unresolvable, loads without console output, requests
nothing but itself, and draws the colour map on its WebGL canvas (seen on a screenshot);
NGSolve's own export of the same scene, which loads its viewer from a CDN, fails there."""

import base64
import html
import json
import re
import subprocess

import ngsolve as ngs
import numpy as np
import pytest
from matplotlib.image import imread
from netgen.csg import CSGeometry, OrthoBrick, Pnt
from netgen.webgui import GenerateHTML
from studies.test_report import CHROMIUM, needs_chromium

from ngincompat.workflow import webview

#: Put first in the page's head: records error events and console.error calls; 1.5 s after
#: the load, writes into <pre id="check"> the errors, every resource the page requested and
#: whether it holds a WebGL canvas.
PROBE = """<script>
window.__errors = [];
window.addEventListener('error', e => window.__errors.push(String(e.message ||
    ('failed to load ' + ((e.target && (e.target.src || e.target.href || '')) + '')))), true);
const __error = console.error;
console.error = (...a) => { window.__errors.push(a.join(' ')); __error(...a); };
window.addEventListener('load', () => setTimeout(() => {
  const canvases = [...document.querySelectorAll('canvas')];
  const pre = document.createElement('pre'); pre.id = 'check';
  const labels = [...document.querySelectorAll('#view div')].filter(d =>
    d.children.length == 0 && /^-?[0-9][0-9.e+-]*$/.test(d.textContent.trim())).map(d => {
      const r = d.getBoundingClientRect(); return [r.left, r.right, d.textContent]; });
  pre.textContent = JSON.stringify({errors: window.__errors, canvases: canvases.length,
    webgl: canvases.some(c => !!(c.getContext('webgl2') || c.getContext('webgl'))),
    resources: performance.getEntriesByType('resource').map(r => r.name), labels});
  document.body.appendChild(pre);
}, 1500));
</script>"""

#: Chromium without a GPU: WebGL on SwiftShader; every host name resolves to nothing, so a
#: request that would leave the machine fails (and shows as an error) instead of loading.
FLAGS = ["--headless", "--no-sandbox", "--hide-scrollbars", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--enable-logging=stderr", "--v=0",
         "--host-resolver-rules=MAP * ~NOTFOUND", "--virtual-time-budget=10000",
         "--allow-file-access-from-files"]

#: Rows of a screenshot above the body: the page's header and the viewer's colour bar.
TOP = 110


def look(page, folder, screenshot=None, size=(1000, 640)):
    """Open ``page`` (HTML text) with :data:`PROBE` in headless Chromium from ``folder``;
    returns the probe's record and the console lines Chromium logged (and writes a
    ``screenshot`` of the page without the probe, if given)."""
    probed = folder / "probed_view.html"
    probed.write_text(page.replace("<head>", "<head>" + PROBE, 1), encoding="utf-8")
    window = f"--window-size={size[0]},{size[1]}"
    done = subprocess.run([CHROMIUM, *FLAGS, window, "--dump-dom", probed.as_uri()],
                          capture_output=True, text=True, timeout=180)
    if screenshot is not None:
        plain = folder / "plain_view.html"
        plain.write_text(page, encoding="utf-8")
        subprocess.run([CHROMIUM, *FLAGS, window, f"--screenshot={screenshot}",
                        plain.as_uri()], capture_output=True, timeout=180)
    found = re.search(r'<pre id="check">(.*?)</pre>', done.stdout, re.S)
    assert found, done.stderr[-2000:]
    console = [line for line in done.stderr.splitlines() if ":CONSOLE" in line]
    return json.loads(html.unescape(found.group(1))), console


def colour_map(screenshot):
    """Of the screenshot below :data:`TOP`: the fraction of coloured pixels (not white, grey
    or black: the body under its colour map) and the number of distinct colours among them
    (16 levels a channel)."""
    rgb = (imread(screenshot)[TOP:, :, :3] * 255).astype(int)
    coloured = rgb.max(axis=2) - rgb.min(axis=2) > 60
    return coloured.mean(), len({tuple(c) for c in rgb[coloured] // 16})


def assert_offline_view(record, console, folder, screenshot):
    """The page loaded cleanly, requested only files of ``folder`` or data, and drew a
    colour map on a WebGL canvas (seen on its ``screenshot``)."""
    assert record["errors"] == [] and console == []
    assert all(r.startswith(("data:", folder.as_uri())) for r in record["resources"]), \
        record["resources"]
    assert record["canvases"] >= 1 and record["webgl"]
    covered, colours = colour_map(screenshot)
    assert covered > 0.05                 # the body covers part of the window
    assert colours >= 6                   # under a colour map, not one flat colour


@pytest.fixture(scope="module")
def bricks():
    """Two bricks side by side, [0, 1] x [0, 1] x [0, 1] in two materials (x < 0.5: 'left')
    on a coarse mesh."""
    geo = CSGeometry()
    left = OrthoBrick(Pnt(0, 0, 0), Pnt(0.5, 1, 1)).mat("left")
    right = OrthoBrick(Pnt(0.5, 0, 0), Pnt(1, 1, 1)).mat("right")
    geo.Add(left)
    geo.Add(right)
    return ngs.Mesh(geo.GenerateMesh(maxh=0.5))


def patches(data):
    """The drawn surface's control points (x, y, z, value) of an order-1 scene: its
    triangles' corners."""
    return np.concatenate([np.frombuffer(base64.b64decode(p), np.float32).reshape(-1, 4)
                           for p in data["Bezier_trig_points"]])


def test_the_scene_carries_the_field_on_the_deformed_body(bricks):
    """x drawn on the body moved by (0.1 x, 0, 0): the corners lie in [0, 1.1] x [0, 1]^2
    and carry the value x of their reference point (x is its own projection)."""
    u = ngs.GridFunction(ngs.VectorH1(bricks, order=1))
    u.Set(ngs.CF((0.1 * ngs.x, 0, 0)))
    data = webview.scene(bricks, ngs.x, u, order=1)
    p = patches(data)
    assert p[:, 0].min() == pytest.approx(0, abs=1e-6)
    assert p[:, 0].max() == pytest.approx(1.1, abs=1e-6)
    assert np.allclose(p[:, 3], p[:, 0] / 1.1, atol=1e-6)      # x = (x + 0.1 x) / 1.1
    assert (data["funcmin"], data["funcmax"]) == pytest.approx((0, 1), abs=1e-12)
    assert "points3d" not in data                     # no clipping plane: the surface only


def test_a_peak_at_a_point_does_not_set_the_colour_bar_a_smooth_field_does():
    """On the unit cube (maxh 0.1), x + 1000 exp(-|X - c|^2 / 1e-3) with c a corner (a crease
    tip's stress) gets the colour bar [0, 1] (the viewer's autoscale off), x alone the
    viewer's autoscale over its range."""
    geo = CSGeometry()
    geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(1, 1, 1)))
    mesh = ngs.Mesh(geo.GenerateMesh(maxh=0.1))
    peak = ngs.exp(-((ngs.x - 1)**2 + (ngs.y - 1)**2 + (ngs.z - 1)**2) / 1e-3)
    data = webview.scene(mesh, ngs.x + 1000 * peak, order=1)
    assert patches(data)[:, 3].max() > 100                  # the peak is drawn
    assert not data["autoscale"]
    assert (data["funcmin"], data["funcmax"]) == pytest.approx((0, 1), abs=1e-6)
    assert webview.scene(mesh, ngs.x, order=1)["autoscale"]


def test_a_field_without_a_value_at_a_vertex_is_drawn_whole(bricks):
    """x / x is 1 but 0/0 on the face x = 0, as the hemisphere's meridional |b| on its axis:
    drawn from its projection, every corner carries 1 and none is NaN (a hole in the view)."""
    p = patches(webview.scene(bricks, ngs.x / ngs.x, order=1))
    assert np.isfinite(p).all() and np.allclose(p[:, 3], 1, atol=1e-6)


def test_a_field_per_material_is_drawn_with_a_clipping_plane(bricks):
    """A field defined per material region (1 in 'left', 2 in 'right') has no value on the
    boundary of its own: it is taken from the adjacent element; with a clipping plane the
    volume is drawn too, and the field on the cut; zoom 2 halves the radius the camera
    fits."""
    field = bricks.MaterialCF({"left": 1.0, "right": 2.0})
    data = webview.scene(bricks, field, clipping=(1, 0, 0, 0), camera=(-60, 0, 30), order=1,
                         zoom=2)
    p = patches(data)
    assert set(np.unique(p[:, 3])) == {1.0, 2.0}
    assert np.all(p[p[:, 0] < 0.5 - 1e-6, 3] == 1) and np.all(p[p[:, 0] > 0.5 + 1e-6, 3] == 2)
    assert data["draw_vol"] and data["points3d"] and data["clipping"]
    assert data["clipping_function"] and data["clipping_x"] == 1
    assert data["gui_settings"]["camera"]["euler_angles"] == [-60.0, 0.0, 30.0]
    assert data["mesh_radius"] == pytest.approx(webview.scene(bricks, field)["mesh_radius"] / 2)


def test_the_page_inlines_the_viewer_and_names_no_host(bricks):
    page = webview.page(webview.scene(bricks, ngs.x, order=1), "x [mm]", "a </script> test")
    assert webview.viewer_script() in page
    assert page.count("</script>") == 3               # the caption's was escaped
    # the viewer names the XHTML namespace, which is an identifier, never fetched
    hosts = set(re.findall(r"https?://[^\s\"'<>)]+", page)) - {"http://www.w3.org/1999/xhtml"}
    assert hosts == set()
    assert not re.search(r"""(src|href)\s*=\s*["']?https?:""", page)


@needs_chromium
def test_the_view_draws_offline_and_the_cdn_export_does_not(bricks, tmp_path):
    """Our page draws the colour map (on the surface and on a cut through the middle) with
    every host unresolvable; ngsolve's export of the same scene, whose viewer comes from a
    CDN, does not load (the check can fail)."""
    u = ngs.GridFunction(ngs.VectorH1(bricks, order=1))
    u.Set(ngs.CF((0.1 * ngs.x, 0, 0.05 * ngs.x * ngs.y)))
    data = webview.scene(bricks, ngs.x, u, camera=(-65, 0, 30), clipping=(0, 1, 0, 0),
                         order=1)
    shot = tmp_path / "view.png"
    record, console = look(webview.page(data, "x [mm]", "two bricks"), tmp_path, shot)
    assert_offline_view(record, console, tmp_path, shot)
    blank = tmp_path / "cdn.png"
    cdn, _ = look(GenerateHTML(data), tmp_path, blank)
    assert any("webgui is not defined" in e for e in cdn["errors"])
    assert cdn["canvases"] == 0 and colour_map(blank)[0] < 0.01


@needs_chromium
def test_the_colour_bars_labels_do_not_run_into_each_other_in_the_reports_frame(bricks,
                                                                               tmp_path):
    """Five labels of four significant digits (0.06189 ... 0.08333, the cube's |b|) at the
    size of the report's frame: each ends before the next begins, and all are in the
    window."""
    data = webview.scene(bricks, 0.06189 + 0.02144 * ngs.x)
    record, _ = look(webview.page(data, "|b| [1/mm]"), tmp_path, size=(1370, 560))
    labels = sorted(record["labels"])
    assert [text for _, _, text in labels] == ["0.06189", "0.06725", "0.07261", "0.07797",
                                               "0.08333"]
    assert labels[0][0] >= 0
    for (_, right, _), (left, _, _) in zip(labels[:-1], labels[1:], strict=True):
        assert right < left
