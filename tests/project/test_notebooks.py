"""Every notebook in notebooks/ runs headless, top to bottom, on a coarse mesh.

The notebooks are jupytext percent scripts; each is converted to a notebook and executed in a
fresh python3 kernel with NGINCOMPAT_COARSE=1, from the repository root. A cell that raises
(including the notebook's final assert) fails the test. ``ngsolve.webgui.Draw`` only
produces widget output there.

Executing the notebooks is a tier of its own, marked ``notebooks`` (``pytest -m notebooks``);
the structural checks below are fast and run with the rest of the tests: every notebook ends
with an assert, and none re-implements the scene pipeline (it runs a scene and draws its
results).
"""

import ast
import os
from pathlib import Path

import pytest

jupytext = pytest.importorskip("jupytext")
nbclient = pytest.importorskip("nbclient")

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.py"))
TIMEOUT = 600  # seconds, per notebook (and so per cell)


#: What the scene pipeline does for a notebook: building and solving the mechanics, and the
#: projected Curl Fg. A notebook that uses these re-implements a scene.
PIPELINE = {"GrowthMechanics", "CoupledProblem", "solve_growth", "solve_coupled",
            "curl_projected"}


def code_cells(path):
    """The code cells of a notebook as Python modules (IPython magics blanked)."""
    for cell in jupytext.read(path).cells:
        if cell.cell_type == "code":
            lines = ["" if line.lstrip().startswith(("%", "!")) else line
                     for line in cell.source.splitlines()]
            yield ast.parse("\n".join(lines))


def pipeline_names(tree):
    """Names of the pipeline's internals that a module imports or uses."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom | ast.Import):
            found |= {part for alias in node.names for part in alias.name.split(".")}
        elif isinstance(node, ast.Attribute):
            found.add(node.attr)
        elif isinstance(node, ast.Name):
            found.add(node.id)
    return found & PIPELINE


def test_notebooks_found():
    assert {p.name for p in NOTEBOOKS} >= {"cube.py", "getting_started.py"}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_ends_with_an_assert(path):
    """The convention: the last statement of every notebook checks a number."""
    code = [c for c in jupytext.read(path).cells if c.cell_type == "code"]
    assert code and isinstance(ast.parse(code[-1].source).body[-1], ast.Assert)


def test_pipeline_names_are_found():
    """The check below sees an import, a module attribute and a bare name."""
    tree = ast.parse("from ngincompat.fem.problem import GrowthMechanics\n"
                     "import ngincompat.incompatibility.operators as inc\n"
                     "inc.curl_projected(Fg, mesh, 6)\n"
                     "solve_coupled(problem, 1.0, 0.1)\n")
    assert pipeline_names(tree) == {"GrowthMechanics", "curl_projected", "solve_coupled"}
    assert not pipeline_names(ast.parse("results = CubeScene().run()"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_does_not_reimplement_the_pipeline(path):
    """A notebook runs a scene and draws its results; building and solving the mechanics or
    projecting Curl Fg by hand duplicates what the scenes do."""
    used = set().union(*(pipeline_names(tree) for tree in code_cells(path)))
    assert not used, f"{path.name} uses {sorted(used)}: run a scene instead"


@pytest.mark.notebooks
@pytest.mark.timeout(TIMEOUT)
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path):
    notebook = jupytext.read(path)
    pythonpath = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
    env = {**os.environ, "NGINCOMPAT_COARSE": "1", "PYTHONPATH": pythonpath}
    client = nbclient.NotebookClient(notebook, timeout=TIMEOUT, kernel_name="python3",
                                     resources={"metadata": {"path": str(ROOT)}})
    client.execute(env=env)  # raises CellExecutionError, with the cell and traceback
