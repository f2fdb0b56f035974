"""The workers of a sweep and of the paper job (ngincompat.studies.workers): how a case
takes a stop."""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from ngincompat.studies import workers


def _deliver(signum):
    """Send ``signum`` to this process and give Python the moment to run its handler."""
    os.kill(os.getpid(), signum)
    time.sleep(0.05)


def test_a_case_takes_the_first_stop_and_ignores_the_next_while_it_cleans_up():
    """The stop reaches a worker twice (sent to the whole job, then by the pool): a second
    KeyboardInterrupt in the cleanup left the folder's lock behind or killed the worker.
    After the block the process's own handlers are back."""
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    cleaned = False
    with pytest.raises(KeyboardInterrupt):
        with workers._interruptible():
            try:
                _deliver(signal.SIGTERM)
                pytest.fail("SIGTERM did not interrupt the case")
            except KeyboardInterrupt:
                _deliver(signal.SIGINT)
                _deliver(signal.SIGTERM)
                cleaned = True
                raise
    assert cleaned
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before


def test_a_job_started_with_ctrl_c_ignored_ignores_it_in_its_workers_too(tmp_path):
    """A shell starts a job in the background with Ctrl-C ignored: the job's own process
    ignores it, and so do its workers' cases (they stopped the case they ran, and the job
    ended 0 with a case "interrupted")."""
    out = tmp_path / "paper"
    ignoring = ("import signal, sys; signal.signal(signal.SIGINT, signal.SIG_IGN); "
                "from ngincompat.cli import main; sys.exit(main(sys.argv[1:]))")
    process = subprocess.Popen([sys.executable, "-c", ignoring, "paper", "--only", "3.1,3.4",
                                "--jobs", "2", "--out", str(out)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    lines = []
    for line in process.stderr:
        lines.append(line)
        if "] growth" in line:
            os.killpg(process.pid, signal.SIGINT)
            break
    _, rest = process.communicate(timeout=300)
    err = "".join(lines) + rest
    assert process.returncode == 0, err
    rows = json.loads((out / "summary.json").read_text())["rows"]
    assert [(r["case"], r["status"]) for r in rows] == [("cube", "done"),
                                                        ("cylinder", "done")], err
