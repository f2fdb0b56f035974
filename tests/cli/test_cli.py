"""The command line: exit codes, one-line errors, folders that never mix two runs."""

import json
import re
from pathlib import Path

import pytest
from conftest import SKIN_COARSE

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.fem.solver import NewtonSolver

CUBE = ["run", "cube", "--order", "1", "--maxh", "1"]


def test_not_converged_exits_3_with_the_last_converged_state_written(tmp_path, monkeypatch,
                                                                     capsys):
    def never(self, record):
        record.reason = "simulated failure"
        return False

    monkeypatch.setattr(NewtonSolver, "minimise", never)
    assert main([*CUBE, "--out", str(tmp_path), "-q"]) == 3
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    assert captured.err.strip().splitlines()[-1].startswith("ngincompat: not converged:")
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["status"] == "not converged" and "simulated failure" in results["error"]
    # measured in the last converged state, t = 0: no growth, no stress
    assert results["metrics"]["strain_energy"] == pytest.approx(0.0, abs=1e-20)
    assert results["solver"]["growth"]["t_reached"] == 0.0
    assert "cube: not converged" in captured.out


def test_interrupt_exits_130_with_one_line_and_marked_results(tmp_path, monkeypatch, capsys):
    def interrupt(self, record):
        raise KeyboardInterrupt

    monkeypatch.setattr(NewtonSolver, "minimise", interrupt)
    assert main([*CUBE, "--out", str(tmp_path), "-q"]) == 130
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert err.startswith("ngincompat: interrupted")
    results = json.loads((tmp_path / "results.json").read_text())
    assert results["status"] == "interrupted" and results["metrics"] == {}


def test_a_folder_with_a_run_is_refused_in_one_line_then_overwritten(tmp_path, capsys):
    assert main([*CUBE, "--out", str(tmp_path), "-q"]) == 0
    capsys.readouterr()
    assert main([*CUBE, "--out", str(tmp_path), "-q", "--outputs", "mechanics"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "holds another run" in err and "--overwrite" in err
    assert main([*CUBE, "--out", str(tmp_path), "-q", "--outputs", "mechanics",
                 "--overwrite"]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_a_file_as_out_is_refused_before_computing(tmp_path, capsys, monkeypatch):
    from ngincompat.scenes import CubeScene

    def forbidden(self):
        raise AssertionError("built")

    monkeypatch.setattr(CubeScene, "build", forbidden)
    target = tmp_path / "o"
    target.write_text("keep me")
    assert main([*CUBE, "--out", str(target / "sub")]) == 2
    assert "lies under the file" in capsys.readouterr().err
    assert target.read_text() == "keep me"


def test_run_prints_its_summary_with_units(tmp_path, capsys):
    assert main([*CUBE, "--out", str(tmp_path), "-q"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("cube: done; ndof ")
    assert "strain_energy" in out and "units: length mm, stress MPa" in out


def test_skin_runs_through_the_command_line(tmp_path, capsys):
    """A run with several stages prints its summary (it ended in a KeyError before)."""
    code = main(["run", "skin", "--set", "footprint=square", "--out", str(tmp_path),
                 *SKIN_COARSE, "--set", "outputs=none"])
    out, err = capsys.readouterr()
    assert code == 0, out
    assert "skin: done" in out and "inflation" in out and "hold" in out
    assert "volume_inflated" in out and "expander_height_inflated" in out   # the default
    # the progress: the hold marches in the scene's time unit, each stage with its place
    assert re.search(r"^\[skin\] hold \(stage 3 of 6\): t = 0\.5/0\.5 day \(\d+ Newton",
                     err, flags=re.M), err
    assert re.search(r"^\[skin\] inflation \(stage 1 of 6\): t = 1/1 \(", err, flags=re.M)


def test_outputs_name_every_optional_output_of_a_scene():
    from ngincompat.cli import OUTPUT_NAMES, _outputs
    from ngincompat.workflow.output import OUTPUTS
    assert OUTPUT_NAMES[2:] == OUTPUTS
    assert _outputs("incompatibility,curvature,growth") == {
        "mechanics": False, "outputs": "growth,curvature"}
    assert _outputs("mechanics") == {"mechanics": True, "outputs": "none"}
    # as --set outputs=none, the word list -v shows: no files, the mechanics as set
    assert _outputs("none") == {"outputs": "none"}
    with pytest.raises(ParameterError, match="or none"):
        _outputs("none,vtk")


def test_version_names_ngincompat_and_ngsolve(capsys):
    import ngsolve

    from ngincompat.config import VERSION
    assert main(["--version"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"ngincompat {VERSION} ")
    assert f"NGSolve {ngsolve.__version__}" in out


def test_the_version_is_written_once_in_pyproject_and_read_from_the_metadata():
    import tomllib
    from importlib import metadata

    import ngincompat
    from ngincompat import config
    root = Path(__file__).resolve().parents[2]
    declared = tomllib.loads((root / "pyproject.toml").read_text())["project"]["version"]
    assert config.VERSION == ngincompat.__version__ == metadata.version("ngincompat")
    assert config.VERSION == declared
    written = [p.relative_to(root) for p in (root / "ngincompat").rglob("*.py")
               if f'"{declared}"' in p.read_text()]
    assert written == []


def _run_help(capsys):
    with pytest.raises(SystemExit) as exit:
        from ngincompat.cli import build_parser
        build_parser().parse_args(["run", "--help"])
    assert exit.value.code == 0
    return " ".join(capsys.readouterr().out.split())       # argparse wraps the lines


def test_run_help_names_every_scene(capsys):
    from ngincompat.scenes import SCENES
    text = _run_help(capsys)
    scene_help = text.split("scene the scene: ", 1)[1]
    assert all(name in scene_help for name in SCENES), scene_help


def test_run_help_gives_the_true_default_of_outputs(capsys):
    """--outputs left out computes mechanics and writes the scenes' default files."""
    from ngincompat.cli import DEFAULT_FILES
    from ngincompat.parameters import Outputs
    from ngincompat.scenes import SCENES
    for cls in SCENES.values():
        declared = cls.declarations()
        assert declared["mechanics"].default is True
        assert declared["outputs"].default == Outputs(DEFAULT_FILES)
    text = _run_help(capsys)
    assert "(default: all)" not in text
    assert "default: incompatibility,mechanics,vtk,figures" in text


def test_list_verbose_shows_type_default_unit_and_range(capsys):
    assert main(["list", "-v"]) == 0
    lines = capsys.readouterr().out.splitlines()
    cube = lines[:lines.index(next(line for line in lines if line.startswith("hemisphere")))]
    maxh = next(line for line in cube if line.startswith("    maxh "))
    assert maxh == "    maxh (float, default 0.5 mm): allowed in [0.001, 1000]"
    assert "    order (int, default 6): allowed an integer in [1, 10]" in cube
    nu = next(line for line in cube if line.startswith("    nu "))
    assert nu.startswith("    nu (float, default 0.4): allowed ") and "0.5" in nu
    assert cube[cube.index(maxh) + 1] == "        mesh size"


#: The extras' packages (pyproject.toml's [test], [mpi], [brain], [dask], [parquet],
#: [notebooks]): the main job (`ngincompat paper`) must run on the core dependencies alone.
OPTIONAL = ("dask", "distributed", "mpi4py", "nilearn", "nibabel", "pyarrow", "sklearn",
            "jupytext", "nbclient", "nbformat", "ipykernel", "hypothesis", "pytest",
            "importlinter")


def test_the_main_jobs_imports_need_no_extra():
    """Importing the command line, the paper's driver and every scene loads no package of an
    extra (a light install, `pip install -e .`, runs the main job)."""
    import subprocess
    import sys
    code = ("import sys, ngincompat.cli, ngincompat.studies.paper, ngincompat.scenes; "
            "ngincompat.cli.build_parser(); "
            f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({OPTIONAL!r})))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "[]", done.stdout
    # the check itself sees an import of an extra
    code = code.replace("ngincompat.scenes;", "ngincompat.scenes, pytest;")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "['pytest']"


def test_the_command_lines_help_imports_neither_ngsolve_nor_the_geometries():
    """The parser takes its name lists from :mod:`ngincompat.names`: ``ngincompat --help``
    answers without loading NGSolve."""
    import subprocess
    import sys
    code = ("import sys, ngincompat.cli; ngincompat.cli.build_parser(); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'ngsolve', 'netgen', "
            "'geometries'}))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "[]", done.stdout
