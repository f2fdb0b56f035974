"""The Results record: what a run returns, round-tripped through JSON."""

import json
import math

import numpy as np
import pytest

from ngincompat.scenes import CubeScene
from ngincompat.workflow import output
from ngincompat.workflow.results import Results


@pytest.fixture(scope="module")
def cube():
    """A coarse cube, run without an output folder."""
    return CubeScene(order=2, maxh=0.5, elements="hex").run()


def test_a_run_without_folder_returns_results_with_fields(cube):
    assert cube.converged and cube.status == "done"
    assert cube.scene == "cube" and cube.params["order"] == 2
    assert cube.units["length"] == "mm"
    assert cube.mesh.ne == 8 and cube.mesh.ndof > 0
    assert cube.newton_iterations == cube.solver["growth"].newton_iterations > 0
    assert cube.solve_seconds == pytest.approx(cube.timings["growth"])
    # the fields live on the run's mesh and can be evaluated (and drawn) there
    assert {"theta", "G", "u", "Psi", "S11", "|b_n2|"} <= set(cube.fields)
    theta = cube.fields["theta"](cube.domain(1.0, 0.5, 0.5))
    assert theta == pytest.approx(1.25)
    assert cube.files == []


def test_results_round_trip_through_json(cube):
    text = json.dumps(cube.to_dict())
    back = Results.from_dict(json.loads(text))
    assert back.to_dict() == json.loads(text)   # every serialised field, exactly
    assert back.fields == {} and back.domain is None
    assert back.solver["growth"].steps[0].residuals == cube.solver["growth"].steps[0].residuals
    np.testing.assert_array_equal(back.profile("line")["X1"], cube.profile("line")["X1"])
    assert back.figures[0].file == "profile.png"


def test_results_record_their_provenance(cube):
    data = json.loads(json.dumps(cube.to_dict()))
    assert {"date", "host", "threads", "command"} <= set(data["provenance"])
    # one rank's peak memory in a serial run: at least the NGSolve it loaded
    (peak,) = data["provenance"]["peak_mib"]
    assert peak > 50
    assert set(data["versions"]) >= {"ngincompat", "ngsolve", "netgen", "numpy", "scipy",
                                     "python"}


def test_results_of_older_runs_without_provenance_load(cube):
    data = json.loads(json.dumps(cube.to_dict()))
    del data["provenance"]
    del data["versions"]["scipy"]
    back = Results.from_dict(data)
    assert back.provenance == {} and back.metrics == cube.metrics
    assert back.versions["ngsolve"] == cube.versions["ngsolve"]


def test_non_finite_numbers_are_written_as_null_and_read_as_nan(cube):
    data = cube.to_dict()
    data["metrics"]["strain_energy"] = None
    back = Results.from_dict(json.loads(json.dumps(data)))
    assert math.isnan(back.metrics["strain_energy"])


def test_written_results_read_back_equal(cube, tmp_path):
    output.write(cube, tmp_path)
    back = output.read(tmp_path)
    assert back.metrics == cube.metrics and back.status == "done"
    assert set(back.files) == {"results.json", "fields.vtu", "profile.png", "burgers.png",
                               "stress.png"}
    assert {p.name for p in tmp_path.iterdir()} == set(back.files)


def test_reading_what_is_not_results_is_a_clear_error(tmp_path):
    from ngincompat.errors import ParameterError
    with pytest.raises(ParameterError, match="does not exist"):
        output.read(tmp_path)
    (tmp_path / "results.json").write_text('{"something": 1}')
    with pytest.raises(ParameterError, match="not a results file"):
        output.read(tmp_path)
