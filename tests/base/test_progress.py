"""Progress reports: named cases, stages and steps, plain lines when not on a terminal."""

import io
import re
import time

import pytest

from ngincompat import progress as progress_module
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


def _lines(stream):
    return stream.getvalue().splitlines()


def test_a_marching_stage_names_its_place_unit_and_sensible_digits():
    stream = io.StringIO()
    progress = Progress(stream=stream, bars=False)
    with progress.case("folding"):
        progress.plan(["approach", "perfect", "buckling", "equilibrium", "release"])
        report = progress.march("buckling", 0.0, 2.7598812, "day")
        report.step(0.34499999, 0.345, 3)
        report.cut(0.34499999, 0.1234567, "energy not finite")
        progress.march("perfect", 0.0, 75.0, "day").step(61.25, 1.25, 2)
    lines = _lines(stream)
    assert lines[1] == "[folding] buckling (stage 3 of 5): from 0 to 2.76 day"
    assert lines[2] == "[folding] buckling (stage 3 of 5): t = 0.345/2.76 day (3 Newton " \
                       "iterations)"
    assert lines[3] == "[folding] buckling (stage 3 of 5): step from t = 0.345 day by 0.123 " \
                       "failed (energy not finite); retrying with 0.0617"
    assert lines[5] == "[folding] perfect (stage 2 of 5): t = 61.25/75 day (2 Newton iterations)"


def test_stages_outside_the_plan_or_alone_carry_no_number():
    stream = io.StringIO()
    progress = Progress(stream=stream, bars=False)
    with progress.case("cube"):
        progress.plan(["growth"])
        progress.march("growth", 0.0, 1.0).step(0.5, 0.5, 4)
    with progress.case("skin"):         # a new case starts without the last one's plan
        progress.march("hold", 0.0, 10.0, "day").step(5.0, 5.0, 4)
    assert "[cube] growth: t = 0.5/1 (4 Newton iterations)" in _lines(stream)
    assert "[skin] hold: t = 5/10 day (4 Newton iterations)" in _lines(stream)


@pytest.mark.parametrize("bars", [False, True], ids=["lines", "bars"])
def test_a_case_silent_for_still_seconds_says_it_is_still_computing(monkeypatch, bars):
    """A 100 cm bilayer meshed for 92 s and iterated its first step for three minutes
    without a word. Silent for :data:`STILL` seconds, a case says so, naming what it was
    last doing; a marching stage's bar that moves is not silence; after the case, nothing."""
    monkeypatch.setattr(progress_module, "STILL", 0.4)
    stream = io.StringIO()
    report = Progress(stream=stream, bars=bars)
    with report.case("big"):
        report.line("meshing ...")
        time.sleep(1.0)
        stage = report.march("growth", 0.0, 1.0)
        for k in range(1, 7):
            time.sleep(0.15)
            stage.step(k / 6, 1 / 6, 3)
        stage.close()
    ended = stream.getvalue()
    time.sleep(0.8)
    lines = stream.getvalue().splitlines()
    assert stream.getvalue() == ended
    still = [k for k, line in enumerate(lines) if "still computing" in line]
    # the seconds it counts depend on the machine's load: the line's form and what it names
    assert still and re.match(r"\[big\] still computing \(\d+ s since: meshing \.\.\.",
                              lines[still[0]])
    assert all(k < next(i for i, line in enumerate(lines) if "growth" in line) for k in still)


def test_a_quiet_case_says_nothing_while_silent(monkeypatch):
    monkeypatch.setattr(progress_module, "STILL", 0.2)
    stream = io.StringIO()
    with Progress(quiet=True, stream=stream).case("big"):
        time.sleep(0.6)
    assert stream.getvalue() == ""
