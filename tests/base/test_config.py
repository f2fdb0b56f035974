"""NGSolve's threads and heap: importing the package changes nothing; the package runs on one
thread unless NGS_NUM_THREADS or configure() says otherwise."""

import os
import subprocess
import sys

import pytest

import ngincompat
from ngincompat import config
from ngincompat.errors import ParameterError


def _threads(env, code="import ngincompat\n"):
    code += ("from ngincompat import config\n"
             "with config.task_manager():\n"
             "    from pyngcore import GetNumThreads; print(GetNumThreads())")
    env = {k: v for k, v in os.environ.items() if k != "NGS_NUM_THREADS"} | env
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True, cwd=root)
    return int(out.stdout.split()[-1])


def test_one_thread_by_default_and_the_environment_and_configure_override():
    assert _threads({}) == 1
    assert _threads({"NGS_NUM_THREADS": "2"}) == 2
    assert _threads({}, "import ngincompat\nngincompat.configure(threads=2)\n") == 2


def test_importing_the_package_leaves_ngsolve_as_it_was():
    code = ("import ngsolve\nfrom pyngcore import GetNumThreads\n"
            "import ngincompat, ngincompat.scenes\n"
            "with ngsolve.TaskManager(): print(GetNumThreads())")
    env = {k: v for k, v in os.environ.items() if k != "NGS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True)
    assert int(out.stdout.split()[-1]) == os.cpu_count()   # NGSolve's own default


def test_after_the_package_ran_ngsolve_has_its_own_thread_count_back():
    code = ("import ngsolve\nfrom pyngcore import GetNumThreads\n"
            "from ngincompat import config\n"
            "with config.task_manager():\n    inside = GetNumThreads()\n"
            "with ngsolve.TaskManager(): print(inside, GetNumThreads())")
    env = {k: v for k, v in os.environ.items() if k != "NGS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True)
    assert [int(n) for n in out.stdout.split()] == [1, os.cpu_count()]


def test_importing_the_package_does_not_load_ngsolve():
    code = "import sys, ngincompat\nprint('ngsolve' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False"]


def test_configure_validates_and_only_raises_the_heap():
    with pytest.raises(ParameterError, match="^threads = 0"):
        ngincompat.configure(threads=0)
    with pytest.raises(ParameterError, match="^heap = "):
        ngincompat.configure(heap=10)
    before = config.settings()["heap"]
    config.ensure_heap(before // 2)
    assert config.settings()["heap"] == before
    with config.using(threads=3) as s:
        assert s["threads"] == 3 and config.threads() == 3
    assert config.threads() != 3


def test_the_public_api_is_flat():
    from ngincompat import SCENES, CubeScene, Results
    assert SCENES["cube"] is CubeScene and Results.__name__ == "Results"
    assert set(ngincompat.__all__) <= set(dir(ngincompat))
    with pytest.raises(AttributeError):
        ngincompat.NoSuchThing  # noqa: B018
