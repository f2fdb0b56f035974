"""The package's shape: the layers' contracts hold, and no module grows past 600 lines (a
concern that outgrows them becomes a package of modules)."""

import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
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


def test_the_tests_mirror_the_layers_and_no_folder_shadows_a_package():
    """tests/<layer> for each layer of ngincompat that has tests (the base modules in
    tests/base), tests/geometry for the geometries, tests/project for the repository; the
    folders are on the test path (pyproject's pythonpath), so none may be named like a
    package the tests import."""
    folders = {p.name for p in (ROOT / "tests").iterdir()
               if p.is_dir() and not p.name.startswith((".", "_"))}
    layers = {p.name for p in (ROOT / "ngincompat").iterdir()
              if p.is_dir() and (p / "__init__.py").is_file()}
    assert folders - layers <= {"base", "cli", "geometry", "project"}, folders - layers
    assert not folders & {"ngincompat", "geometries"}
    assert all(any(p.glob("test_*.py")) for p in (ROOT / "tests").iterdir()
               if p.name in folders)


def mirror(module):
    """The test module of a module: ngincompat/<dir>/<m>.py -> tests/<dir>/test_<m>.py, the
    top-level modules in tests/base (cli.py in tests/cli), geometries/<m>.py in
    tests/geometry."""
    rel = module.relative_to(ROOT)
    package, *inner, name = rel.parts
    name = name.removesuffix(".py")
    if package == "geometries":
        folder = ("geometry",)
    elif not inner:
        folder = ("cli",) if name == "cli" else ("base",)
    else:
        folder = tuple(inner)
    return ROOT.joinpath("tests", *folder, f"test_{name}.py")


@pytest.mark.parametrize("path", [p for p in _modules()
                                  if p.name != "__init__.py" and not p.name.startswith("_")],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_every_module_has_its_test_module(path):
    test = mirror(path)
    assert test.is_file(), f"{path.relative_to(ROOT)} has no {test.relative_to(ROOT)}"
    assert "def test_" in test.read_text()
