"""NGSolve's thread count: one unless NGS_NUM_THREADS says otherwise."""

import os
import subprocess
import sys


def _threads(env):
    code = ("import ngincompat, ngsolve\n"
            "with ngsolve.TaskManager():\n"
            "    from pyngcore import GetNumThreads; print(GetNumThreads())")
    env = {k: v for k, v in os.environ.items() if k != "NGS_NUM_THREADS"} | env
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True, cwd=os.path.dirname(os.path.dirname(__file__)))
    return int(out.stdout.split()[-1])


def test_one_thread_by_default_and_the_environment_overrides():
    assert _threads({}) == 1
    assert _threads({"NGS_NUM_THREADS": "2"}) == 2
