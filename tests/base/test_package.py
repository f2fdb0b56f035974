"""ngincompat (its __init__): a flat public API loaded on first use, no NGSolve at import."""

import subprocess
import sys

import pytest

import ngincompat


def test_importing_the_package_does_not_load_ngsolve():
    code = "import sys, ngincompat\nprint('ngsolve' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"]


def test_the_public_api_is_flat():
    from ngincompat import SCENES, CubeScene, Results
    assert SCENES["cube"] is CubeScene and Results.__name__ == "Results"
    assert set(ngincompat.__all__) <= set(dir(ngincompat))
    with pytest.raises(AttributeError):
        ngincompat.NoSuchThing  # noqa: B018
