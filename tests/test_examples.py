"""The measuring scripts under ``examples/`` that the README quotes run, on a coarse bilayer,
as a user would call them (``python examples/folding/<script>.py key=value ...``)."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The folding tests' coarse bilayer (``conftest.FOLDING_COARSE``) as the scripts' arguments.
COARSE = ["length=0.5", "height=0.3", "maxh=0.15", "cortex_maxh=0.025"]


def _run(script, *args):
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "folding" / script), *args],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    return done.stdout


def test_step_costs_times_every_part_of_a_step():
    out = _run("step_costs.py", *COARSE)
    for part in ("residual", "tangent assembly", "factorisation umfpack", "eigenpairs (6)",
                 "top_stretch"):
        line = next(line for line in out.splitlines() if line.startswith(part))
        assert float(line.split()[-2]) > 0


def test_march_reports_the_onset_and_the_march_records():
    """The coarse bilayer's perfect branch finds the onset at its step to t = 40 (theta_c =
    1.283 at t = 35.4), and the march goes on to t_end = 42 in 3 steps (45 s alone; to
    t_end = 45, 10 steps and a cut, 70 s)."""
    out = _run("march.py", "axons=curved", "t_end=42", "dt=10", "onset_dt=10", *COARSE)
    assert "onset {" in out and "onset_growth" in out
    assert "buckling:" in out
    assert out.rstrip().endswith("status done None")
