"""The validation and performance pages include only what benchmarks wrote.

Every table and figure the pages include is a file under ``docs/_generated/``, committed, in a
folder whose ``made_by.md`` names the command that wrote it; that command is one the page
shows. Each benchmark the pages show runs here on coarse settings into a scratch folder and
must write every table the page includes from its folder, and its ``made_by.md``.
"""

import re
import shlex
from pathlib import Path

import pytest
from conftest import peer_stand_in

from ngincompat.cli import main

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
PAGES = ("validation.md", "performance.md")
GENERATED = "_generated/"
#: MyST includes and markdown images of a page.
INCLUDE = re.compile(r"^```\{include\}\s+(\S+)\s*$", re.MULTILINE)
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")
#: The command a made_by.md names.
MADE_BY = re.compile(r"^Made by `([^`]+)` on \d{4}-\d\d-\d\d \d\d:\d\d UTC")
#: Coarse settings of each benchmark the pages show (they replace the page's options); the
#: peer's folder is a stand-in made in the scratch folder (the peer itself needs its own
#: set-up, see ../shared/peer).
COARSE = {
    "validation": ["--quick"],
    "cube": ["--maxh", "1", "--orders", "2", "3"],
    "accuracy": ["--quick"],
    "curvature": ["--quick"],
    "stability": ["--quick"],
    "skin": ["--quick"],
    "inputs": ["--quick"],
    "scenes": ["--scenes", "cube", "--presets", "preview"],
    "folding": ["--axons", "straight", "--preset", "preview", "--set", "t_end=10",
                "--set", "release=false"],
    "peer": ["--peer", "peer", "--pairs", "1", "--set", "order=2", "--set", "maxh=1"],
    "scaling": ["--quick", "--solvers", "sparsecholesky"],
    "mpi": ["--maxh", "4", "--ranks", "2", "--set", "t_end=2", "--set", "dt=1"],
}
#: Benchmarks whose coarse settings take more than about 30 s.
SLOW = {"validation", "skin"}


def included(page):
    """The files ``page`` includes (paths relative to docs/)."""
    text = (DOCS / page).read_text()
    return INCLUDE.findall(text) + [p for p in IMAGE.findall(text) if "://" not in p]


def shown_commands(page):
    """The ``ngincompat bench`` commands of the page's bash blocks, as argument lists after
    ``ngincompat`` (environment settings before it dropped)."""
    text = (DOCS / page).read_text()
    commands = []
    for block in re.findall(r"```bash\n(.*?)```", text, re.DOTALL):
        for line in block.splitlines():
            words = shlex.split(line, comments=True)
            while words and re.match(r"^[A-Z_]+=", words[0]):
                words = words[1:]
            if words[:2] == ["ngincompat", "bench"]:
                commands.append(words[1:])
    return commands


def out_of(argv):
    return argv[argv.index("--out") + 1]


def made_by(folder):
    """The command that wrote ``folder`` (after ``ngincompat``), from its made_by.md."""
    match = MADE_BY.match((Path(folder) / "made_by.md").read_text())
    assert match, f"{folder}/made_by.md does not name its command"
    return shlex.split(match.group(1))[1:]


@pytest.mark.parametrize("page", PAGES)
def test_every_included_file_was_written_by_a_command_the_page_shows(page):
    files = included(page)
    assert files, f"{page} includes nothing"
    shown = {tuple(argv) for argv in shown_commands(page)}
    for name in files:
        assert name.startswith(GENERATED), f"{page} includes {name}, not a generated file"
        assert (DOCS / name).is_file(), f"{page} includes {name}, which is not there"
        if name.endswith(".png"):
            assert (DOCS / name).stat().st_size > 1000, name
        folder = str(Path(name).parent)
        argv = made_by(DOCS / folder)
        assert tuple(argv) in shown, (
            f"{folder} was made by `ngincompat {shlex.join(argv)}`, which {page} does not show")
        assert out_of(argv) == f"docs/{folder}"


@pytest.mark.parametrize("page", PAGES)
def test_every_shown_benchmark_has_a_coarse_rule_and_writes_where_the_page_reads(page):
    folders = {str(Path(name).parent) for name in included(page)}
    for argv in shown_commands(page):
        assert argv[1] in COARSE, f"no coarse settings for `ngincompat {shlex.join(argv)}`"
        assert out_of(argv).removeprefix("docs/") in folders, argv


def _cases():
    seen = {}
    for page in PAGES:
        for argv in shown_commands(page):
            seen.setdefault(argv[1], (page, argv))
    return [pytest.param(page, argv, id=argv[1],
                         marks=[pytest.mark.slow] if argv[1] in SLOW else [])
            for page, argv in seen.values()]


@pytest.mark.parametrize("page,argv", _cases())
def test_shown_benchmark_writes_the_included_tables(page, argv, tmp_path, monkeypatch, capsys):
    """The benchmark on coarse settings writes, into its folder, every markdown table that a
    page includes from the folder the page's command writes, and its made_by.md; and at
    least one of the figures the page includes from there."""
    monkeypatch.chdir(tmp_path)
    if argv[1] == "peer":
        peer_stand_in(tmp_path / "peer")
    out = tmp_path / "out"
    assert main(["bench", argv[1], *COARSE[argv[1]], "--out", str(out)]) == 0
    assert "|" in capsys.readouterr().out
    folder = out_of(argv).removeprefix("docs/")
    names = {Path(name).name for p in PAGES for name in included(p)
             if str(Path(name).parent) == folder}
    for name in (n for n in names if n.endswith(".md")):
        assert (out / name).is_file(), f"bench {argv[1]} did not write {name}"
    figures = [n for n in names if n.endswith(".png")]
    if figures:
        assert any((out / n).stat().st_size > 1000 for n in figures if (out / n).is_file())
    assert made_by(out) == ["bench", argv[1], *COARSE[argv[1]], "--out", str(out)]
