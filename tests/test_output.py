"""The output folder: checked before anything is computed, never mixing two runs."""

import pytest

from ngincompat.errors import ParameterError
from ngincompat.scenes import CubeScene
from ngincompat.workflow import output


def test_a_file_as_output_folder_is_refused(tmp_path):
    target = tmp_path / "results.txt"
    target.write_text("mine")
    with pytest.raises(ParameterError, match="is a file"):
        output.prepare(target)
    with pytest.raises(ParameterError, match="lies under the file"):
        output.prepare(target / "run")
    assert target.read_text() == "mine"


def test_a_folder_that_cannot_be_created_is_refused():
    """/proc takes no new folders, whoever asks (the tests may run as root, who may write
    into any ordinary folder)."""
    with pytest.raises(ParameterError, match="cannot be created"):
        output.prepare("/proc/ngincompat-test/run")


def test_a_folder_with_another_run_is_refused_unless_overwrite(tmp_path):
    scene = CubeScene(order=1, maxh=1.0, outputs="vtk")
    scene.run(tmp_path)
    (tmp_path / "notes.txt").write_text("the user's own file")
    with pytest.raises(ParameterError, match="holds another run.*--overwrite"):
        output.prepare(tmp_path)
    # overwrite removes what the old run wrote, and nothing else
    output.prepare(tmp_path, overwrite=True)
    assert {p.name for p in tmp_path.iterdir()} == {"notes.txt"}


def test_overwrite_leaves_only_the_new_runs_files(tmp_path):
    """A run with figures, then one without: no figure of the first run is left beside the
    second's results (two runs mixed in one folder)."""
    CubeScene(order=1, maxh=1.0).run(tmp_path)
    assert (tmp_path / "stress.png").is_file()
    results = CubeScene(order=1, maxh=1.0, outputs="none").run(tmp_path, overwrite=True)
    assert {p.name for p in tmp_path.iterdir()} == {"results.json"} == set(results.files)


def test_the_folder_is_checked_before_the_solve(tmp_path, monkeypatch):
    from ngincompat.scenes import prescribed

    def forbidden(*args, **kwargs):
        raise AssertionError("the case was built")

    target = tmp_path / "file"
    target.write_text("")
    monkeypatch.setattr(prescribed.PrescribedCase, "solve", forbidden)
    monkeypatch.setattr(CubeScene, "build", forbidden)
    with pytest.raises(ParameterError, match="is a file"):
        CubeScene().run(target)


def test_growth_output_writes_the_mesh_and_the_growth_field(tmp_path):
    results = CubeScene(order=2, maxh=0.5, outputs="growth").run(tmp_path)
    assert {"mesh.vol", "growth.npz"} <= set(results.files)
    assert (tmp_path / "mesh.vol").stat().st_size > 0


def test_vtk_fields_are_interpolated_once_and_gridfunctions_kept():
    """The VTK file gets element-wise interpolants of the fields (exact for a polynomial of
    their order), the GridFunctions themselves."""
    import ngsolve as ngs

    from geometries import cube

    mesh = cube(maxh=0.5)
    u = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    fields = {"u": u, "s": ngs.x * ngs.y * ngs.z, "v": ngs.CF((ngs.x, ngs.y ** 2, 1))}
    out = output.interpolated(fields, mesh, 3)
    assert out["u"] is u
    point = mesh(0.3, 0.6, 0.7)
    assert out["s"](point) == pytest.approx(0.3 * 0.6 * 0.7, rel=1e-10)
    assert out["v"](point) == pytest.approx((0.3, 0.36, 1.0), rel=1e-10)
