"""``ngincompat expansion``: every expander, one summary (coarse)."""

import json

from conftest import SKIN_COARSE

from ngincompat.cli import main

#: The expanders' volume on the coarse settings.
VOLUME = float(dict(item.split("=") for item in SKIN_COARSE[1::2])["volume"])


def test_two_expanders_and_their_summary(tmp_path):
    """The default expander is the dome in contact: its columns, not the pressure's."""
    assert main(["expansion", "--out", str(tmp_path), "-q", "--footprints", "circle",
                 "square", *SKIN_COARSE]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert [r["footprint"] for r in summary["rows"]] == ["circle", "square"]
    for row in summary["rows"]:
        assert row["status"] == "done"
        assert abs(row["volume_inflated"] - VOLUME) < 1e-3 * VOLUME
        assert row["expander_height_inflated"] > 0 and row["contact_area_inflated"] > 0
        assert "pressure_inflated" not in row
        assert row["theta_max"] > 1.0
    table = (tmp_path / "summary.md").read_text()
    assert "volume_inflated [cm^3]" in table and "expander_height_inflated [cm]" in table


def test_a_bad_setting_is_refused_before_any_expander_runs(tmp_path, capsys):
    assert main(["expansion", "--out", str(tmp_path), "--set", "volume=-1"]) == 2
    assert "volume = -1" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
