"""Every notebook in notebooks/ runs headless, top to bottom, on a coarse mesh.

The notebooks are jupytext percent scripts; each is converted to a notebook and executed in a
fresh python3 kernel with NGINCOMPAT_COARSE=1, from the repository root. A cell that raises
(including the notebook's final assert) fails the test. ``ngsolve.webgui.Draw`` only
produces widget output there.
"""

import ast
import os
from pathlib import Path

import pytest

jupytext = pytest.importorskip("jupytext")
nbclient = pytest.importorskip("nbclient")

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.py"))
TIMEOUT = 300  # seconds, per notebook (and so per cell)


def test_notebooks_found():
    assert {p.name for p in NOTEBOOKS} >= {"cube.py", "getting_started.py"}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_ends_with_an_assert(path):
    """The convention: the last statement of every notebook checks a number."""
    code = [c for c in jupytext.read(path).cells if c.cell_type == "code"]
    assert code and isinstance(ast.parse(code[-1].source).body[-1], ast.Assert)


@pytest.mark.timeout(TIMEOUT)
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path):
    notebook = jupytext.read(path)
    pythonpath = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
    env = {**os.environ, "NGINCOMPAT_COARSE": "1", "PYTHONPATH": pythonpath}
    client = nbclient.NotebookClient(notebook, timeout=TIMEOUT, kernel_name="python3",
                                     resources={"metadata": {"path": str(ROOT)}})
    client.execute(env=env)  # raises CellExecutionError, with the cell and traceback
