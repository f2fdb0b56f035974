"""``ngincompat bench peer``: the peer's folder, its RESULT line, the ratio of solve times."""

import json
import sys

import pytest
from conftest import peer_stand_in

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.studies import peer
from ngincompat.studies.bench import CUBE_ENERGY


def test_missing_peer_is_one_clear_line(monkeypatch, tmp_path, capsys):
    monkeypatch.delenv(peer.PEER_VARIABLE, raising=False)
    with pytest.raises(ParameterError, match="not installed"):
        peer.peer_folder()
    assert main(["bench", "peer", "--peer", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "missing fenicsx_growth.py, env_dolfinx.sh, debroot" in err


@pytest.fixture
def stand_in(tmp_path):
    return peer_stand_in(tmp_path)


def test_ratio_of_solve_times_and_energy_errors(stand_in, tmp_path):
    folder, record = stand_in
    rows, summary = peer.compare(folder, {"order": 2, "maxh": 1.0, "elements": "hex"}, pairs=1)
    theirs, ours = rows
    assert theirs["solve_s"] == record["t_solve"]
    assert theirs["energy_error"] == pytest.approx(5e-2)
    assert ours["code"] == "ngincompat" and ours["ndof"] == 81
    assert ours["energy_error"] == pytest.approx(
        abs(ours["strain_energy"] - CUBE_ENERGY) / CUBE_ENERGY)
    assert summary["ratio"] == pytest.approx(record["t_solve"] / ours["solve_s"])
    # the verdict compares the two errors
    assert summary["equal_or_better"] == (ours["energy_error"] <= 5e-2)
    lines = peer.main(folder, {"order": 2, "maxh": 1.0, "elements": "hex"}, pairs=1,
                      out=tmp_path / "t")
    assert "solve-time ratio" in lines[-2]
    assert json.loads((tmp_path / "t" / "peer.json").read_text())["rows"][0]["ndof"] == 14739


def test_peer_failure_names_its_output(tmp_path):
    (tmp_path / "debroot").mkdir()
    (tmp_path / peer.PEER_ENV).write_text(f'PY="{sys.executable}"\n')
    (tmp_path / peer.PEER_SCRIPT).write_text("raise SystemExit('dolfinx missing')\n")
    with pytest.raises(RuntimeError, match="dolfinx missing"):
        peer.run_peer(tmp_path)
