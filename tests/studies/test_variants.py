"""The drivers' shared machinery (:mod:`ngincompat.studies.variants`): every variant into its
folder,
one summary, a failed variant a row of its own."""

import json

import pytest

from ngincompat.errors import ConvergenceError
from ngincompat.studies.variants import run_variants, write_summary
from ngincompat.workflow.results import NOT_CONVERGED, MeshInfo, Results


class StandIn:
    """A scene that reports a metric, or fails after measuring its last converged state."""

    def __init__(self, value, fail=False):
        self.value, self.fail = value, fail

    def run(self, out, overwrite=False, progress=None, label=""):
        results = Results("stand-in", {}, {}, MeshInfo(1, 4, 1, 1.0, ndof=12),
                          metrics={"m": self.value})
        if out is not None:
            out.mkdir()
        if self.fail:
            results.status = NOT_CONVERGED
            err = ConvergenceError(f"{label}: no")
            err.results = results
            raise err
        return results


def test_a_failed_variant_is_a_row_and_the_others_still_run(tmp_path):
    scenes = {"a": StandIn(1.0), "b": StandIn(2.0, fail=True), "c": StandIn(3.0)}
    rows, results = run_variants(scenes, tmp_path / "out", key="name", metrics=("m", "n"))
    assert [(r["name"], r["status"], r["m"], r["n"]) for r in rows] == [
        ("a", "done", 1.0, None), ("b", NOT_CONVERGED, 2.0, None), ("c", "done", 3.0, None)]
    assert set(results) == {"a", "b", "c"} and all(r["ndof"] == 12 for r in rows)
    assert all((tmp_path / "out" / name).is_dir() for name in scenes)
    write_summary(tmp_path / "out", rows, ["name", "status", "m"], {"m": "cm"},
                  files=["fields.png"])
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["columns"] == ["name", "status", "m"]
    assert summary["files"] == ["a", "b", "c", "fields.png", "summary.md", "summary.csv",
                                "summary.json"]
    assert "| b | not converged | 2 |" in (tmp_path / "out" / "summary.md").read_text()


def test_without_a_folder_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rows, _ = run_variants({"a": StandIn(1.0)}, key="name", metrics=("m",))
    assert rows[0]["m"] == 1.0 and list(tmp_path.iterdir()) == []


def test_an_existing_run_is_kept_without_overwrite(tmp_path):
    out = tmp_path / "out"
    run_variants({"a": StandIn(1.0)}, out, key="name")
    write_summary(out, [{"name": "a"}], ["name"], {})
    with pytest.raises(Exception, match="overwrite"):
        run_variants({"a": StandIn(1.0)}, out, key="name")
