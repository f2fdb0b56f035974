"""The hostile-value corpus of tests/test_inputs_hostile.py through the whole command line, in
separate processes (slow tier): a value that segfaults or hangs cannot be seen in-process.

Every numeric parameter of every scene gets every value of the corpus; the values the scene
accepts run to the end on its ``preview`` preset. Asserted: the process is not killed by a
signal and ends within its time limit, every value ends with an exit code of the documented
table (0 done, 2 bad input, 3 not converged), and a run that exits 0 has only finite metrics.
"""

import json
import subprocess
import sys

import pytest
from test_inputs_hostile import CORPUS, HOSTILE, HOSTILE_INT, _texts

from ngincompat.parameters import _Int
from ngincompat.scenes import SCENES

pytestmark = pytest.mark.slow

#: Seconds one parameter's values may take together: refusals take a second or two each, an
#: accepted value a preview run.
TIMEOUT = 1200

DRIVER = """
import json, sys
from ngincompat.cli import main
scene, key, preset, out, values = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], \\
    json.loads(sys.argv[5])
for k, text in enumerate(values):
    print(json.dumps({"value": text, "started": True}), flush=True)
    code = main(["run", scene, "--preset", preset, "--set", f"{key}={text}",
                 "--out", f"{out}/{k}", "-q"])
    print(json.dumps({"value": text, "code": code, "folder": f"{out}/{k}"}), flush=True)
"""


@pytest.mark.parametrize("scene, key", CORPUS, ids=[f"{s}-{k}" for s, k in CORPUS])
def test_no_value_of_the_corpus_crashes_hangs_or_ends_done_with_a_non_finite_metric(
        scene, key, tmp_path):
    cls = SCENES[scene]
    p = cls.declarations()[key]
    values = [_texts(p, v) for v in HOSTILE + (HOSTILE_INT if isinstance(p.kind, _Int) else ())]
    preset = "preview" if "preview" in cls.preset_names() else "default"
    try:
        done = subprocess.run([sys.executable, "-c", DRIVER, scene, key, preset, str(tmp_path),
                               json.dumps(values)], capture_output=True, text=True,
                              timeout=TIMEOUT)
    except subprocess.TimeoutExpired as err:
        lines = (err.stdout or b"").decode().splitlines() if isinstance(err.stdout, bytes) \
            else (err.stdout or "").splitlines()
        pytest.fail(f"{scene} {key}: no end within {TIMEOUT} s; last: {lines[-1:]}")
    records = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    last = records[-1] if records else None
    assert done.returncode == 0, (f"{scene} {key}: exit {done.returncode} while running "
                                  f"{last}: {done.stderr[-2000:]}")
    assert "Traceback" not in done.stderr, done.stderr[-2000:]
    ended = [r for r in records if "code" in r]
    assert [r["value"] for r in ended] == values
    for record in ended:
        assert record["code"] in (0, 2, 3), record
        if record["code"] == 0:
            metrics = json.loads((tmp_path / record["folder"].split("/")[-1] /
                                  "results.json").read_text())["metrics"]
            assert all(v is not None for v in metrics.values()), (record, metrics)
