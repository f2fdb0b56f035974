"""Sphinx configuration of ngincompat's documentation site (``make docs``).

The site builds offline with warnings as errors (``-W``) and every cross-reference checked
(``-n``):

- pages are MyST markdown (myst-parser); the gallery's pages are the jupytext notebooks of
  ``notebooks/`` (symbolic links in ``gallery/``), executed by myst-nb on their
  coarse settings (``NGINCOMPAT_COARSE=1``, as the notebooks' test tier runs them);
- the API reference is generated from the docstrings: one page per public module
  (``_ext/api_pages.py``: autodoc, with autosummary tables; numpy-style sections read by
  napoleon, ``_ext/numpy_sections.py``); the parameters and the metrics of every scene are
  generated from the scenes' own declarations (``_ext/scene_parameters.py``,
  ``_ext/scene_metrics.py``), and the rules that judge the
  paper's findings from the code that applies them (``_ext/finding_rules.py``);
- math is typeset by the MathJax 3 copy that the ``sphinx-mathjax-offline`` package ships,
  copied into the site, so no page loads anything from the network.
"""

import os
import shutil
import sys
from importlib.util import find_spec
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(HERE / "_ext"), str(ROOT)]

# The notebooks take their coarse settings (what the notebooks' test tier runs); the
# executing kernels inherit the environment, and find the package of this checkout first.
os.environ["NGINCOMPAT_COARSE"] = "1"
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT),
                                                         os.environ.get("PYTHONPATH")]))

from ngincompat import __version__  # noqa: E402  (after the path above)

project = "ngincompat"
author = "the ngincompat authors"
copyright = "the ngincompat authors, MIT license"
release = version = __version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "api_pages",
    "scene_parameters",
    "scene_metrics",
    "finding_rules",
    "short_references",
    "numpy_sections",
    "plain_math",
    "webgui_views",
]

# --------------------------------------------------------------------------- sources
# Not pages: the extensions' code; the files the benchmarks write under _generated/ (tables,
# figures, made_by.md), which the validation and performance pages include; the build itself.
exclude_patterns = ["_build", "_ext", "conf.py", "_generated", "**/.ipynb_checkpoints",
                    "**/__pycache__"]
root_doc = "index"
# quotes as written: the parameters' help texts and the notebooks' outputs are the program's
smartquotes = False

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# --------------------------------------------------------------------------- notebooks
# The gallery's notebooks are jupytext "percent" scripts (the .py files of notebooks/).
nb_custom_formats = {".py": ["jupytext.reads", {"fmt": "py:percent"}]}
nb_execution_mode = "cache"                  # re-run a notebook only when its source changed
nb_execution_cache_path = str(HERE / "_build" / ".jupyter_cache")
nb_execution_timeout = 900                   # seconds per cell (the folding study is the longest)
nb_execution_raise_on_error = True           # a notebook that fails fails the build
nb_execution_show_tb = True
# what the notebooks write to stderr is the environment's (tqdm without ipywidgets, kernel
# notices); their results are printed or displayed
nb_output_stderr = "remove"
# the notebooks' tables are Markdown outputs (display(Markdown(...))): read them as MyST,
# which has tables (CommonMark, the default, has none)
nb_render_markdown_format = "myst"
# ngsolve.webgui's 3D views are Jupyter widgets whose script comes from a CDN: offline they
# cannot show, so the gallery leaves them out (in Jupyter they are interactive; the pages
# keep the matplotlib figures); _ext/webgui_views.py puts a note in their place.
nb_mime_priority_overrides = [
    ("*", "application/vnd.jupyter.widget-view+json", None),
]

# --------------------------------------------------------------------------- API reference
# one page per public module (_ext/api_pages.py); autosummary makes the tables of contents
api_packages = ["ngincompat", "geometries"]
autosummary_generate = False
autodoc_default_options = {"members": True, "undoc-members": True, "show-inheritance": True,
                           "member-order": "bysource", "ignore-module-all": True}
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
autoclass_content = "both"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_param = False       # parameter types stay text ("3x3 CoefficientFunction")
napoleon_use_ivar = True         # "Attributes" sections as fields, not a second description

# --------------------------------------------------------------------------- cross-references
nitpicky = True
# Offline there are no inventories of other projects (intersphinx needs the network), so a
# reference to an outside name cannot resolve: the builtins, the standard library, and the
# packages ngincompat builds on are named here. Every reference into ngincompat and
# geometries must resolve.
_OUTSIDE = ("ngsolve", "ngs", "netgen", "numpy", "np", "scipy", "matplotlib", "mpi4py", "dask",
            "pyarrow", "meshio", "basix", "nilearn", "nibabel", "tqdm", "pathlib",
            "typing", "collections", "dataclasses", "argparse", "enum", "abc", "io",
            "fractions", "numbers", "concurrent", "subprocess", "os", "types", "datetime",
            "json", "threading", "contextlib", "tomllib", "csv", "signal", "pyngcore", "ast",
            "shutil", "tempfile", "re", "math", "functools", "itertools", "time")
_BUILTINS = ("str", "int", "float", "bool", "complex", "dict", "list", "tuple", "set",
             "frozenset", "bytes", "object", "type", "callable", "None", "Exception",
             "ValueError", "TypeError", "RuntimeError", "KeyError", "OSError", "IOError",
             "FileNotFoundError", "FileExistsError", "KeyboardInterrupt", "AttributeError",
             "NotImplementedError", "ArithmeticError", "ZeroDivisionError", "Ellipsis",
             "iterable", "sequence", "mapping", "optional", "array_like", "array",
             "function", "path", "Path", "ndarray", "ClassVar", "Literal", "Any",
             "Callable", "Iterable", "Iterator", "Sequence", "Mapping", "Collection",
             "Generator", "CF", "CoefficientFunction", "collection", "open", "eval", "print",
             "len", "range", "zip")
nitpick_ignore_regex = [
    # a type in words ("3x3 CoefficientFunction", '{"hex", "tet"}'), not a Python name
    ("py:.*", r"(?![A-Za-z_]\w*(\.[A-Za-z_]\w*)*$).*"),
    ("py:.*", rf"({'|'.join(_OUTSIDE)})(\..*)?"),
    ("py:.*", rf"({'|'.join(_BUILTINS)})"),
    # a private name (a leading underscore) that a docstring names for the reader of the
    # source: the reference documents public names only
    ("py:.*", r"(.*\.)?_[A-Za-z]\w*"),
]

# --------------------------------------------------------------------------- HTML
html_theme = "furo"
html_title = f"ngincompat {release}"
html_static_path = ["_static"]
html_css_files = ["site.css"]
html_last_updated_fmt = None
html_show_sourcelink = False
html_copy_source = False

# MathJax 3 from the sphinx-mathjax-offline package (its files, not its extension, which
# would take the CHTML output: web fonts, which a page opened from file:// may not load), with
# SVG output (the glyphs are in the script), copied into _static/mathjax when the build ends.
_MATHJAX = Path(find_spec("sphinx-mathjax-offline").submodule_search_locations[0],
                "static", "mathjax")
mathjax_path = "mathjax/tex-svg.js"
#: What tex-svg.js loads beside itself: TeX extensions on demand, the SVG output's parts, the
#: menu and the accessibility parts the menu offers.
_MATHJAX_PARTS = ("tex-svg.js", "input", "output/svg", "output/svg.js", "ui", "a11y",
                  "adaptors")


def copy_mathjax(app, exception):
    """Copy MathJax (:data:`_MATHJAX_PARTS`) into the site's _static/mathjax."""
    if exception is None and app.builder.format == "html":
        target = Path(app.outdir) / "_static" / "mathjax"
        for part in _MATHJAX_PARTS:
            source, copy = _MATHJAX / part, target / part
            copy.parent.mkdir(parents=True, exist_ok=True)
            if source.is_dir():
                shutil.copytree(source, copy, dirs_exist_ok=True)
            else:
                shutil.copy2(source, copy)


def setup(app):
    app.connect("build-finished", copy_mathjax)
