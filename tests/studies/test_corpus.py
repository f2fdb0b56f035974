"""The hostile-input corpus (ngincompat.studies.corpus): its values, and outcomes that are
classified as what they are, a hang and a crash included."""

import json
import signal
from pathlib import Path

import pytest

from ngincompat.parameters import _Float, _Floats, _Int
from ngincompat.studies import corpus
from ngincompat.studies.corpus import Interrupt, Try

HERE = Path(__file__).resolve().parent


@pytest.mark.parametrize("kind, values", [
    (_Float("[0.001, 1000]"), ["0.001", "0.0009999999999999998", "1000.0",
                                      "1000.0000000000001"]),
    (_Float("(-1, 0.5)"), ["-1.0", "-0.9999999999999999", "0.5",
                                  "0.49999999999999994"]),
    (_Int("[1, 8]"), ["1", "0", "8", "9"]),
    (_Floats(2, "[0, 1]"), ["0.0,0.0", "-5e-324,-5e-324", "1.0,1.0",
                                   "1.0000000000000002,1.0000000000000002"]),
    (_Float("> 0"), ["0.0", "5e-324"]),
], ids=["closed", "open", "int", "tuple", "half"])
def test_the_boundary_values_are_each_end_and_the_nearest_number_past_or_inside_it(kind,
                                                                                  values):
    assert corpus.boundary_values(kind) == values


def test_every_numeric_parameter_gets_the_hostile_values_and_its_boundaries(tmp_path):
    tries = corpus.parameter_tries("cube", "side", tmp_path)
    values = [t.value for t in tries]
    assert values[:len(corpus.HOSTILE)] == list(corpus.HOSTILE)
    assert values[len(corpus.HOSTILE):] == ["0.001", "0.0009999999999999998", "1000.0",
                                            "1000.0000000000001"]
    first = tries[0].args
    assert first[:4] == ["run", "cube", "--preset", "preview"]
    assert first[first.index("--set") + 1] == "side=1e308"
    # a scene's quick settings never override the parameter tried
    folding = corpus.parameter_tries("folding", "t_end", tmp_path)[0].args
    assert "t_end=1e308" in folding and "t_end=10" not in folding


def test_hangs_crashes_tracebacks_and_exit_codes_are_classified_and_the_rest_still_run(
        tmp_path, monkeypatch):
    """The driver's process hangs on one try and crashes on another: each is recorded and
    the tries after it run in a new process; a try stopped at the limit while it reports
    progress is a long run, not a hang; what a try prints past Python's sys.stdout (as
    Netgen does) does not mix with the driver's records."""
    monkeypatch.setenv("PYTHONPATH", str(HERE))
    tries = [Try("x", "k", v, [v]) for v in ("0", "hang", "2", "crash", "3", "raise", "noise",
                                             "exit", "130", "slow", "5")]
    corpus.run_in_one_process(tries, limit=5.0, entry="corpus_entry:main")
    assert [t.outcome for t in tries] == ["done", "hang", "refused", "signal", "not converged",
                                          "traceback", "done", "other", "interrupted",
                                          "time limit", "other"]
    assert tries[3].message == "killed by SIGSEGV" and tries[7].code == 7


@pytest.mark.parametrize("metrics, outcome", [
    ({"a": 1.0, "b": 2, "c": "x", "d": [1.0, 2.0]}, "done"),
    ({"a": None}, "non-finite"), ({"a": float("nan")}, "non-finite"),
    ({"a": [1.0, float("inf")]}, "non-finite")])
def test_a_done_run_with_a_metric_that_is_not_a_finite_number_is_a_defect(metrics, outcome,
                                                                         tmp_path):
    (tmp_path / "results.json").write_text(json.dumps({"metrics": metrics}))
    record = {"code": 0, "traceback": False}
    assert corpus._classify(record, tmp_path) == outcome


@pytest.mark.parametrize("corpus_sigint", [signal.default_int_handler, signal.SIG_IGN],
                         ids=["from a terminal", "in the background"])
def test_an_interrupted_run_ends_interrupted_and_its_environment_is_its_own(tmp_path,
                                                                            corpus_sigint):
    """The try takes Ctrl-C as from a terminal also where the corpus runs in the background
    (Ctrl-C ignored, which its children would inherit: the run rightly ignored it)."""
    attempt = Try("cube", "interrupt", "SIGINT", ["run", "cube", "--preset", "preview",
                                                  "--out", str(tmp_path / "run")])
    previous = signal.signal(signal.SIGINT, corpus_sigint)
    try:
        corpus.run_alone(attempt, interrupt=Interrupt("x", (), signal.SIGINT, "growth: from",
                                                      0.0))
    finally:
        signal.signal(signal.SIGINT, previous)
    assert attempt.outcome == "interrupted" and attempt.code == 130, attempt
    assert not (tmp_path / "run" / ".ngincompat.lock").exists()
    blank = Try("environment", "NGS_NUM_THREADS", "", ["run", "cube", "--out",
                                                       str(tmp_path / "b")],
                {"NGS_NUM_THREADS": ""})
    assert corpus.run_alone(blank).outcome == "refused"
    assert blank.message.startswith("ngincompat: error: NGS_NUM_THREADS")


def test_the_quick_corpus_counts_its_tries_by_outcome(tmp_path):
    lines = corpus.main(quick=True, out=tmp_path)
    rows = json.loads((tmp_path / "corpus.json").read_text())["rows"]
    total = rows[-1]
    assert total["group"] == "total" and total["tries"] == sum(r["tries"] for r in rows[:-1])
    assert total["tries"] == sum(total[o] for o in corpus.OUTCOMES)
    assert all(total[o] == 0 for o in corpus.DEFECTS), lines
    assert total["done"] > 0 and total["refused"] > 0


def test_a_corpus_run_again_into_the_same_folder_gives_the_same_outcomes(tmp_path,
                                                                        monkeypatch):
    """The runs of the first corpus are removed: they had refused the second's tries as
    other runs in their folders ("holds another run"), a refusal of the folder, not of the
    value."""
    monkeypatch.setattr(corpus, "QUICK_TRIES", (("cube", "side"),))
    monkeypatch.setattr(corpus, "ENVIRONMENT", {"NGS_NUM_THREADS": ("abc",)})
    outcomes = []
    for _ in range(2):
        corpus.main(quick=True, out=tmp_path)
        rows = json.loads((tmp_path / "tries.json").read_text())["rows"]
        outcomes.append([(r["key"], r["value"], r["outcome"]) for r in rows])
    assert any(o == "done" for *_, o in outcomes[0])       # a run whose folder it reuses
    assert outcomes[0] == outcomes[1]
