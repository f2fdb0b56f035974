"""The base of every scene's case (ngincompat.scenes.case): the record of a stopped run."""

from dataclasses import dataclass, field

import pytest

from ngincompat.scenes.case import SceneCase
from ngincompat.scenes.cube import CubeScene
from ngincompat.workflow.pipeline import Solution
from ngincompat.workflow.results import INTERRUPTED, NOT_CONVERGED


class _State:
    ndof = 1234


@dataclass(eq=False)
class _Noting(SceneCase):
    """A case that notes a metric, takes a frame and keeps a file."""

    scene: object
    mesh: object
    noted: dict = field(default_factory=lambda: {"onset_growth": 1.25})
    frames: list = field(default_factory=lambda: [(1.0, {"theta": None})])

    def solve(self, solution, progress, workdir=None):
        solution.state = _State()

    def measure(self, solution, progress):
        return self.interrupted(solution)

    def keep(self, results):
        results.files = ["checkpoint.npz"]


@pytest.fixture(scope="module")
def cube_case():
    return CubeScene(maxh=1.0, order=1).build()


def test_a_case_must_say_how_it_solves_and_measures(cube_case):
    class Half(SceneCase):
        def solve(self, solution, progress, workdir=None):
            pass

    with pytest.raises(TypeError, match="measure"):
        Half()
    assert isinstance(cube_case, SceneCase)


def test_a_run_stopped_before_its_problem_records_no_unknowns_and_no_metrics(cube_case):
    solution = Solution(status=INTERRUPTED, error="interrupted while setting up")
    results = cube_case.interrupted(solution)
    assert (results.status, results.error) == (INTERRUPTED, "interrupted while setting up")
    assert results.mesh.ndof is None
    assert results.metrics == {} and results.frames == [] and results.files == []
    assert results.scene == "cube" and results.params["maxh"] == 1.0


def test_a_stopped_run_keeps_what_its_case_noted_took_and_keeps(cube_case):
    case = _Noting(cube_case.scene, cube_case.mesh)
    solution = Solution(status=NOT_CONVERGED, error="no convergence")
    case.solve(solution, None)
    results = case.interrupted(solution)
    assert results.mesh.ndof == 1234
    assert results.metrics == {"onset_growth": 1.25}
    results.metrics["sulci"] = 3                # a copy: the case's notes are its own
    assert case.noted == {"onset_growth": 1.25}
    assert len(results.frames) == 1 and results.files == ["checkpoint.npz"]
