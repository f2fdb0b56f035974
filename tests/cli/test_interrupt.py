"""Ctrl-C at every phase of a run: exit 130, one line that says what was kept, and files that
say "interrupted" where a run had begun computing; nothing left where it had not."""

import contextlib
import json
import os
import signal

import pytest

from ngincompat.cli import EXIT_INTERRUPTED, main
from ngincompat.progress import Progress
from ngincompat.scenes import CubeScene, prescribed
from ngincompat.workflow import output

pytestmark = pytest.mark.usefixtures("ctrl_c_raises")

ARGS = ["run", "cube", "--maxh", "1", "--order", "2", "-q"]


def _interrupt_once(monkeypatch, owner, name):
    """SIGINT to this process the first time ``owner.name`` is called."""
    original, sent = getattr(owner, name), []

    def interrupted(*args, **kwargs):
        if not sent:
            sent.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, interrupted)


@pytest.mark.parametrize("owner, name", [(prescribed.PrescribedCase, "measure"),
                                         (output, "write")],
                         ids=["incompatibility and stresses", "writing"])
def test_ctrl_c_after_the_solve_marks_the_run_interrupted(tmp_path, monkeypatch, capsys,
                                                          owner, name):
    _interrupt_once(monkeypatch, owner, name)
    out = tmp_path / "run"
    assert main([*ARGS, "--out", str(out)]) == EXIT_INTERRUPTED
    assert json.loads((out / "results.json").read_text())["status"] == "interrupted"
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "interrupted" in err and "Traceback" not in err


def test_ctrl_c_just_after_the_results_are_written_leaves_them_done(tmp_path, monkeypatch,
                                                                    capsys):
    """The signal lands as the phase that wrote a complete results.json ends (a sweep's
    worker hit as its case ends): exit 130, and the finished record stands instead of being
    rewritten "interrupted"."""
    original = Progress.phase

    @contextlib.contextmanager
    def phase(self, name):
        with original(self, name):
            yield
        if name == "writing results":
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(Progress, "phase", phase)
    out = tmp_path / "run"
    assert main([*ARGS, "--out", str(out)]) == EXIT_INTERRUPTED
    record = output.read(out)
    assert record.status == "done" and record.metrics["strain_energy"] > 0
    assert "Traceback" not in capsys.readouterr().err


def test_ctrl_c_while_meshing_says_nothing_was_written_and_leaves_no_folder(tmp_path,
                                                                          monkeypatch, capsys):
    _interrupt_once(monkeypatch, CubeScene, "build")
    out = tmp_path / "run"
    assert main([*ARGS, "--out", str(out)]) == EXIT_INTERRUPTED
    assert capsys.readouterr().err == ("ngincompat: interrupted while meshing: nothing was "
                                       "computed, nothing written\n")
    assert not out.exists()


def test_a_folder_the_user_made_is_kept_when_the_run_writes_nothing(tmp_path, monkeypatch):
    _interrupt_once(monkeypatch, CubeScene, "build")
    (tmp_path / "run").mkdir()
    assert main([*ARGS, "--out", str(tmp_path / "run")]) == EXIT_INTERRUPTED
    assert (tmp_path / "run").is_dir() and list((tmp_path / "run").iterdir()) == []


def test_sigterm_from_outside_ends_a_run_as_interrupted(tmp_path):
    """A real process, stopped by SIGTERM once its growth solve has begun: exit 130, the
    folder's results.json says "interrupted", and its last progress line says so too."""
    import subprocess
    import sys

    out = tmp_path / "run"
    process = subprocess.Popen([sys.executable, "-m", "ngincompat.cli", "run", "cube",
                                "--out", str(out)], stderr=subprocess.PIPE, text=True)
    lines = []
    for line in process.stderr:
        lines.append(line)
        if "growth: from" in line:
            process.send_signal(signal.SIGTERM)
            break
    lines += process.stderr.readlines()
    assert process.wait(timeout=120) == EXIT_INTERRUPTED, lines
    assert json.loads((out / "results.json").read_text())["status"] == "interrupted"
    progress = [line for line in lines if line.startswith("[cube]")]
    assert progress[-1].startswith("[cube] interrupted after"), lines
    assert not any("finished in" in line for line in lines)
    assert "Traceback" not in "".join(lines)


#: The command line with Ctrl-C's default handler, whatever this process inherited (a test
#: started in a script's background has SIGINT ignored, which the command line keeps).
AS_FROM_A_TERMINAL = ("import signal; signal.signal(signal.SIGINT, "
                      "signal.default_int_handler); from ngincompat.cli import run; run()")


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["ctrl-c", "sigterm"])
def test_a_long_meshing_stops_within_seconds_of_the_signal(tmp_path, signum):
    """A 1000 mm cylinder takes minutes to mesh (it passes the element count); Netgen kept
    Ctrl-C waiting until the mesh was done, and SIGTERM took 370 s. Now the signal stops the
    mesher: exit 130, one line, no folder and no lock left, long before the mesh could have
    been done."""
    import subprocess
    import sys
    import time

    out = tmp_path / "run"
    process = subprocess.Popen([sys.executable, "-c", AS_FROM_A_TERMINAL, "run", "cylinder",
                                "--preset", "preview", "--set", "length=1000", "--set",
                                "max_dofs=2000000", "--out",
                                str(out)], stderr=subprocess.PIPE, text=True)
    lines = []
    for line in process.stderr:
        lines.append(line)
        if "meshing ..." in line:
            time.sleep(1.0)                 # well into Netgen's mesher
            process.send_signal(signum)
            break
    lines += process.stderr.readlines()
    # the mesh takes minutes: ended by the signal, the run never reaches its solve
    code = process.wait(timeout=120)
    assert code == EXIT_INTERRUPTED, lines
    assert "interrupted while meshing" in lines[-1] and "Traceback" not in "".join(lines)
    assert not any("setting up" in line for line in lines), lines
    assert not out.exists()


#: A script (or a notebook's cell) that runs the 1000 mm cylinder through the Python API (at
#: the preview's mesh size: a minute of meshing), is interrupted 1 s into its meshing and goes
#: on: the process's CPU time from the interrupt to the end of the stop and over the two
#: seconds after it, then a small cube run.
GOES_ON = """
import json, os, resource, signal, threading, time
from ngincompat.errors import Interrupted
from ngincompat.progress import Progress
from ngincompat.scenes import SCENES

def cpu():
    return resource.getrusage(resource.RUSAGE_SELF).ru_utime

class Signal(Progress):
    def phase(self, name):
        if name == "meshing":
            threading.Timer(1.0, self.fire).start()
        return super().phase(name)

    def fire(self):
        self.sent = cpu()
        os.kill(os.getpid(), signal.SIGINT)

signal.signal(signal.SIGINT, signal.default_int_handler)
progress = Signal(quiet=True)
try:
    SCENES["cylinder"].from_settings({"length": 1000, "maxh": 0.5, "order": 2,
                                       "max_dofs": 2000000, "outputs": "none"}).run(
        None, progress=progress)
    error = None
except Interrupted as err:
    error = str(err)
stopping = cpu() - progress.sent
time.sleep(2.0)
after = cpu() - progress.sent - stopping
cube = SCENES["cube"].from_settings({"maxh": 1.0, "order": 1, "outputs": "none"}).run(None)
print(json.dumps({"error": error, "stopping": stopping, "after": after,
                  "cube": cube.status}))
"""


def test_a_script_interrupted_while_meshing_stops_the_mesher_and_goes_on():
    """Ctrl-C in a script or a notebook (no command line around it): the run is interrupted
    while meshing, and the mesher stops: from the interrupt to the exception, and while the
    script then sleeps, the process uses next to no CPU (a mesher left running would finish
    its minute of meshing first, or go on in the background, where it also crashed the
    interpreter's exit at random). Netgen's complaints of unmeshed faces are not printed,
    the script meshes and solves again, and it ends with exit 0."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", GOES_ON], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    record = json.loads(done.stdout.splitlines()[-1])
    assert record["error"].startswith("interrupted while meshing"), record
    assert record["stopping"] < 5.0 and record["after"] < 0.5, record
    assert record["cube"] == "done"
    assert "ERROR" not in done.stdout and "Traceback" not in done.stderr
