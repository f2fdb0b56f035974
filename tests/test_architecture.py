"""The package's shape: the layers' contracts hold, and no module grows past 600 lines (a
concern that outgrows them becomes a package of modules)."""

import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: The most lines a module has.
LONG = 600


def _modules():
    return sorted(p for d in ("ngincompat", "geometries") for p in (ROOT / d).rglob("*.py"))


def test_the_import_contracts_hold():
    """lint-imports (import-linter on grimp's graph, which reads the imports inside functions
    too) keeps the layers of pyproject.toml, geometries on ngincompat.errors and names, and no
    cycles."""
    exe = shutil.which("lint-imports", path=str(pathlib.Path(sys.executable).parent))
    if exe is None:
        pytest.skip("import-linter is not installed (the test extra has it)")
    out = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout[-3000:]
    assert "BROKEN" not in out.stdout and "KEPT" in out.stdout


@pytest.mark.parametrize("path", _modules(), ids=lambda p: str(p.relative_to(ROOT)))
def test_no_module_is_longer_than_600_lines(path):
    lines = path.read_text().count("\n")
    assert lines <= LONG, f"{path.relative_to(ROOT)} has {lines} lines: split it by concern"
