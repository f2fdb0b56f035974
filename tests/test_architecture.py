"""The package's shape: the layers' contracts hold, and no module grows past about 600 lines
without saying why at its top."""

import ast
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: Lines above which a module states, in its docstring, why it is one module.
LONG = 600
#: The phrase that opens that statement.
REASON = "Why one module:"


def _modules():
    return sorted(p for d in ("ngincompat", "geometries") for p in (ROOT / d).rglob("*.py"))


def test_the_import_contracts_hold():
    """lint-imports (import-linter on grimp's graph, which reads the imports inside functions
    too) keeps the layers of pyproject.toml, geometries on ngincompat.errors, and no cycles."""
    exe = shutil.which("lint-imports", path=str(pathlib.Path(sys.executable).parent))
    if exe is None:
        pytest.skip("import-linter is not installed (the test extra has it)")
    out = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout[-3000:]
    assert "BROKEN" not in out.stdout and "KEPT" in out.stdout


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_a_long_module_says_why_it_is_one(path):
    source = path.read_text()
    if source.count("\n") <= LONG:
        return
    doc = ast.get_docstring(ast.parse(source)) or ""
    assert REASON in doc, (f"{path.relative_to(ROOT)} has {source.count(chr(10))} lines: "
                           f"split it, or say at its top ('{REASON} ...') why it is one")
