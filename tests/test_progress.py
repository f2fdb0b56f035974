"""Progress reports: named cases, stages and steps, plain lines when not on a terminal."""

import io

from ngincompat.fem.solver import NewtonSolver
from ngincompat.progress import Progress
from ngincompat.scenes import CubeScene


def test_plain_lines_name_case_stage_and_step():
    stream = io.StringIO()
    CubeScene(order=1, maxh=1.0, steps=2).run(progress=Progress(stream=stream),
                                              label="my cube")
    lines = stream.getvalue().splitlines()
    assert lines[0] == "[my cube] started"
    assert any(line.startswith("[my cube] growth: t = 0.5/1 (") for line in lines)
    assert any(line.startswith("[my cube] growth: t = 1/1 (") for line in lines)
    assert any("incompatibility" in line for line in lines)
    assert lines[-1].startswith("[my cube] finished in")


def test_quiet_reports_nothing():
    stream = io.StringIO()
    CubeScene(order=1, maxh=1.0).run(progress=Progress(quiet=True, stream=stream))
    assert stream.getvalue() == ""


def test_a_cut_step_is_reported_when_it_happens(monkeypatch):
    original, calls = NewtonSolver.minimise, []

    def first_fails(self, record):
        calls.append(record.t)
        if len(calls) == 1:
            record.reason = "simulated failure"
            return False
        return original(self, record)

    monkeypatch.setattr(NewtonSolver, "minimise", first_fails)
    stream = io.StringIO()
    CubeScene(order=1, maxh=1.0).run(progress=Progress(stream=stream))
    lines = stream.getvalue().splitlines()
    cut = [i for i, line in enumerate(lines) if "failed (simulated failure)" in line]
    assert cut and "retrying with 0.5" in lines[cut[0]]
    # reported before the steps that follow it
    assert any("growth: t = 0.5/1" in line for line in lines[cut[0]:])
