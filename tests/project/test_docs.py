"""The documentation site: ``make docs`` builds it with warnings as errors, the API reference
holds every public module, class and function, the parameters page every parameter of every
scene, the gallery the executed notebooks' figures, and the index and a gallery page load in
a real browser (headless Chromium) with their images and math and without console errors.

Building the site is a tier of its own, marked ``docs`` (``pytest -m docs``): the fixture
runs the build command of the Makefile's ``docs`` target (the notebooks are executed only
when they changed since the last build of docs/_build, so after ``make docs`` it takes
seconds).
"""

import html
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from studies.test_report import CHROMIUM, browse, needs_chromium

from ngincompat.scenes import SCENES

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))
from api_pages import defined, public_modules  # noqa: E402  (docs/_ext on the path first)

GALLERY = ("getting_started", "cube", "hemisphere", "disc", "cylinder", "atrophy", "skin",
           "folding")


def build_command():
    """The Sphinx command of the Makefile's ``docs`` target, as arguments after ``python``."""
    recipe = re.search(r"^docs:\n\t(.+)$", (ROOT / "Makefile").read_text(), re.M).group(1)
    sphinx = recipe.split("&&")[-1]
    return shlex.split(sphinx.split(".venv/bin/python", 1)[1])


#: A test module named in prose: ``tests/<folders>/test_<name>.py``.
CITED_TEST = re.compile(r"tests/[\w/]*test_\w+\.py")


def test_every_test_module_the_docs_and_the_code_cite_exists():
    """The pages, the README, the package's docstrings, the tests and the examples
    send readers to test modules as evidence: each named one exists (the tests mirror the
    package, and a move must carry its citations along)."""
    texts = [ROOT / "README.md", *sorted(DOCS.glob("*.md")), *sorted(DOCS.glob("*/*.md")),
             *sorted((ROOT / "ngincompat").rglob("*.py")), *sorted((ROOT / "tests").rglob("*.py")),
             *sorted((ROOT / "examples").rglob("*.py"))]
    cited = {(m, p.relative_to(ROOT).as_posix()) for p in texts
             for m in CITED_TEST.findall(p.read_text(encoding="utf-8"))}
    assert len(cited) > 20
    assert sorted((m, where) for m, where in cited if not (ROOT / m).is_file()) == []


def test_make_docs_builds_offline_with_warnings_as_errors():
    command = build_command()
    assert command[:2] == ["-m", "sphinx"]
    assert {"-W", "-n"} <= set(command) and command[-2:] == ["docs", "docs/_build/html"]


@pytest.fixture(scope="module")
def site():
    """The built site (docs/_build/html), brought up to date by the Makefile's command."""
    done = subprocess.run([sys.executable, *build_command()], cwd=ROOT, capture_output=True,
                          text=True, timeout=3600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return DOCS / "_build" / "html"


def inventory(site):
    """The documented Python objects of the site: (role, full name) pairs from objects.inv."""
    from sphinx.util.inventory import InventoryFile
    with open(site / "objects.inv", "rb") as stream:
        data = InventoryFile.load(stream, "", lambda base, uri: uri)
    entries = data.data if hasattr(data, "data") else data
    return {(role, name) for role, items in entries.items() for name in items}


@pytest.mark.docs
def test_api_reference_has_every_public_module_class_and_function(site):
    documented = inventory(site)
    missing = []
    for package in ("ngincompat", "geometries"):
        for name in public_modules(package):
            module = __import__(name, fromlist=["_"])
            if ("py:module", name) not in documented:
                missing.append(name)
            for member in defined(module):
                kind = ("py:function" if callable(getattr(module, member))
                        and not isinstance(getattr(module, member), type) else None)
                roles = [kind] if kind else ["py:class", "py:exception"]
                if not any((role, f"{name}.{member}") in documented for role in roles):
                    missing.append(f"{name}.{member}")
    assert not missing
    # the package's own names, among them the scenes and Results
    assert ("py:class", "ngincompat.scenes.cube.CubeScene") in documented
    assert ("py:class", "ngincompat.workflow.results.Results") in documented
    assert ("py:module", "geometries.cube") in documented     # a module, not the function


def page_sections(page, kind):
    """Scene name -> the HTML of a generated page between its ``<kind>-<scene>`` anchor and
    the next scene's."""
    starts = sorted((page.index(f'id="{kind}-{name}"'), name) for name in SCENES)
    ends = [s for s, _ in starts[1:]] + [len(page)]
    return {name: page[start:end] for (start, name), end in zip(starts, ends, strict=True)}


@pytest.mark.docs
def test_parameters_page_lists_every_parameter_of_every_scene(site):
    page = (site / "guide" / "parameters.html").read_text(encoding="utf-8")
    for name, section in page_sections(page, "parameters").items():
        cls, section = SCENES[name], html.unescape(section)
        cells = re.findall(r'<span class="pre">([^<]*)</span>', section)
        for parameter, decl in cls.declarations().items():
            assert parameter in cells, (name, parameter)
            assert decl.help.split()[0] in section, (name, parameter)
        for preset, values in cls.presets.items():        # what each preset sets, shown
            for key in values:
                assert key in cells, (name, preset, key)


@pytest.mark.docs
def test_metrics_page_lists_every_metric_of_every_scene_with_unit_and_meaning(site):
    page = (site / "guide" / "metrics.html").read_text(encoding="utf-8")
    for name, section in page_sections(page, "metrics").items():
        cls = SCENES[name]
        rows = re.findall(r'<tr[^>]*>(.*?)</tr>', section, flags=re.S)
        listed = {}
        for row in rows[1:]:
            cells = [html.unescape(re.sub(r"<[^>]+>", "", c)).strip()
                     for c in re.findall(r"<td[^>]*>(.*?)</td>", row, flags=re.S)]
            listed[cells[0]] = cells[1:]
        assert list(listed) == list(cls.metrics), name
        for metric, (unit, meaning) in listed.items():
            assert unit == cls.metric_unit(metric), (name, metric)
            assert " ".join(meaning.split()) == " ".join(cls.metrics[metric].meaning.split())


@pytest.mark.docs
@pytest.mark.parametrize("notebook", GALLERY)
def test_gallery_page_holds_the_executed_notebook_with_its_figures(site, notebook):
    page = (site / "gallery" / f"{notebook}.html").read_text(encoding="utf-8")
    images = re.findall(r'<img[^>]*src="([^"]+)"', page)
    assert images, f"{notebook}: no figure"
    for src in images:
        path = (site / "gallery" / src).resolve()
        assert path.is_file() and path.stat().st_size > 1000, src
    assert "Traceback" not in page and "WebGuiWidget" not in page
    assert "|---" not in page              # the notebooks' Markdown tables are tables


@pytest.fixture
def probe(site):
    """Open a page of the site in headless Chromium (a probed copy beside it, so that its
    relative links hold); returns the probe's record and Chromium's console lines."""
    made = []

    def open_page(relative, screenshot=None):
        page = site / relative
        made.append(page.parent / "probed.html")
        return browse(page.read_text(encoding="utf-8"), page.parent, screenshot=screenshot)

    yield open_page
    for path in made:
        path.unlink(missing_ok=True)


@pytest.mark.docs
@needs_chromium
@pytest.mark.parametrize("relative", ["index.html", "gallery/cube.html"])
def test_page_loads_in_a_browser_with_images_and_math(site, probe, relative, tmp_path):
    shot = tmp_path / "page.png"
    record, console = probe(relative, screenshot=shot)
    assert record["errors"] == [] and console == []
    for image in record["images"]:
        assert image["width"] > 0, image["alt"]
        assert image["variance"] > 20, image["alt"]              # not blank
    if relative.startswith("gallery"):
        assert len(record["images"]) >= 3
    # the math is typeset by the site's own MathJax (nothing from the network)
    dom = subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                          "--virtual-time-budget=10000", "--dump-dom",
                          (site / relative).as_uri()], capture_output=True, text=True,
                         timeout=180).stdout
    assert 'jax="SVG"' in dom
    assert not re.search(r'<script[^>]+src="https?://', dom)
    assert shot.stat().st_size > 0

