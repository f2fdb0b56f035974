"""ngincompat.config: NGSolve's heap and threads (one unless NGS_NUM_THREADS or configure())."""

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


@pytest.mark.parametrize("value", ["1", " 4 ", "256"])
def test_a_usable_thread_count_in_the_environment_passes(value):
    config.check_environment({"NGS_NUM_THREADS": value})


def test_an_unset_thread_count_passes():
    config.check_environment({})
    config.check_environment({"OMP_NUM_THREADS": "0"})


@pytest.mark.parametrize("value", ["0", "", "  ", "two", "-1", "2.0", "257", "\u0663"])
def test_an_unusable_thread_count_in_the_environment_names_the_variable(value):
    """0 and an empty value (which NGSolve reads as 0), a word, a number past MAX_THREADS and a
    digit that is not ASCII are refused with the allowed range."""
    with pytest.raises(ParameterError, match=r"^NGS_NUM_THREADS = .*\[1, 256\]"):
        config.check_environment({"NGS_NUM_THREADS": value})


def test_threads_come_from_configure_else_the_environment_else_one(monkeypatch):
    monkeypatch.setitem(config._configured, "threads", None)
    monkeypatch.delenv("NGS_NUM_THREADS", raising=False)
    assert config.threads() == 1
    monkeypatch.setenv("NGS_NUM_THREADS", " 3 ")
    assert config.threads() == 3
    monkeypatch.setenv("NGS_NUM_THREADS", "0")
    with pytest.raises(ParameterError, match="^NGS_NUM_THREADS = '0'"):
        config.threads()
    config.configure(threads=2)
    assert config.threads() == 2 and config.settings()["threads"] == 2


@pytest.mark.parametrize("kwargs, name", [
    (dict(threads=True), "threads"), (dict(threads=1.0), "threads"),
    (dict(threads=-2), "threads"), (dict(heap=True), "heap"), (dict(heap=1e9), "heap"),
    (dict(heap=999_999), "heap"),
])
def test_configure_takes_integers_only(kwargs, name, monkeypatch):
    monkeypatch.setitem(config._configured, "threads", None)
    monkeypatch.setitem(config._configured, "heap", None)
    with pytest.raises(ParameterError, match=f"^{name} = "):
        ngincompat.configure(**kwargs)
    assert config._configured == {"threads": None, "heap": None}


def test_using_restores_the_threads_configured_before_even_after_an_error(monkeypatch):
    monkeypatch.setitem(config._configured, "threads", 1)
    with pytest.raises(RuntimeError, match="inside"):
        with config.using(threads=2) as settings:
            assert settings["threads"] == 2 == config.threads()
            raise RuntimeError("inside")
    assert config.threads() == 1


def test_the_heap_rises_to_what_is_asked_for_and_the_settings_say_so():
    before = config.settings()["heap"]
    config.ensure_heap(before + 10**6)
    assert config.settings()["heap"] == before + 10**6
    config.ensure_heap(0)
    assert config.settings()["heap"] == before + 10**6


def test_nested_task_managers_run_on_the_configured_threads(monkeypatch):
    """The thread count is set by the outermost task manager, kept by the inner ones (it
    cannot change inside a running one), and NGSolve's own comes back after the outermost."""
    import ngsolve
    from pyngcore import GetNumThreads

    monkeypatch.setitem(config._configured, "threads", None)
    with ngsolve.TaskManager():
        own = GetNumThreads()
    with config.using(threads=2):
        with config.task_manager():
            outer = GetNumThreads()
            with config.task_manager():
                inner = GetNumThreads()
            after_inner = GetNumThreads()
    assert outer == inner == after_inner == 2
    with ngsolve.TaskManager():
        assert GetNumThreads() == own


def test_the_version_is_the_installed_metadata():
    from importlib import metadata

    assert config.VERSION == metadata.version("ngincompat") == ngincompat.__version__
