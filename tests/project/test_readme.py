"""Every command the README and the hand-written documentation pages show runs, on coarse
settings, as a user would follow them.

The pages (the README, then ``docs/getting-started.md``, ``docs/theory.md``, the user guide
``docs/guide/*.md`` and the measurement logs ``docs/measurements/*.md``) are read in that
order. Their ``bash`` blocks are read line by line (a trailing ``\\`` continues a line), and
so are the ``$ `` lines of ``console`` blocks; every ``ngincompat`` command in them, also
after ``&&``, environment settings or a ``.venv/bin/`` prefix, and every inline command of
the text that names an output folder (`` `ngincompat ... --out ...` ``), is run in order in
one scratch folder (so a command can use what an earlier one wrote, as in the pages),
through the command line's ``main``, with coarse settings appended by the rules below. Each
must exit 0 without a traceback and print its summary line. A command whose subcommand (or
scene, or benchmark) has no rule here fails the test: a new documented example cannot go
untested. A command shown on several pages runs once. The commands of the README and the
guide run in the default tier, those only in the measurement logs are marked slow (their
scenes are the coupled ones, each a few seconds to minutes even on coarse settings). The
pages' Python blocks are executed too.
"""

import re
import shlex
import tomllib
from pathlib import Path

import pytest
from conftest import (
    FOLDING_COARSE,
    FOLDING_CREASING,
    SKIN_COARSE,
    local_dask_cluster,
    peer_stand_in,
)

from ngincompat.cli import EXIT_FAILED_CASES, main
from ngincompat.workflow import io

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
#: The hand-written pages, in the order a reader meets them; the measurement logs last.
GUIDE = [DOCS / "getting-started.md", DOCS / "theory.md", *sorted((DOCS / "guide").glob("*.md"))]
MEASUREMENTS = sorted((DOCS / "measurements").glob("*.md"))
PAGES = [README, *GUIDE, *MEASUREMENTS]

#: Coarse settings appended to ``ngincompat run SCENE``, by scene.
RUN = {
    "cube": ["--order", "2", "--maxh", "0.5", "--set", "g_order=3"],
    "hemisphere": ["--order", "2", "--maxh", "0.5", "--set", "centre_maxh=0.25",
                   "--set", "g_order=3"],
    "disc": ["--order", "2", "--maxh", "0.4", "--set", "g_order=3"],
    "cylinder": ["--order", "2", "--maxh", "0.5", "--set", "g_order=3"],
    "custom": ["--order", "2", "--maxh", "0.5", "--set", "g_order=3"],
    "skin": SKIN_COARSE,
    "atrophy": ["--maxh", "1", "--set", "semi_axes=3,2.5,2", "--set", "gray_thickness=0.5",
                "--set", "seed=0,0,-2", "--set", "t_end=4", "--set", "dt=1", "--set",
                "snapshots=1", "--set", "g_order=2"],
    # without the release, most of the time, which test_folding.py runs; the cortex two
    # elements thick (the preview's; the default's four and the refinement study's finer
    # ones cost more); ``ngincompat folding`` runs on a creasing bilayer (``coarse``)
    "folding": [*FOLDING_COARSE, "--set", "release=false", "--set", "cortex_maxh=0.025"],
}
#: A folding run with a refined top: the thin default cortex refined twice (its own cortex
#: of 0.1 cm refined 4 times on the coarse bilayer: 76,441 dofs and 4 min 40 s at load 5).
FOLDING_REFINED_TOP = ["--set", "cortex_thickness=0.05", "--set", "top_refinement=2"]
#: The real brain coarser still: 2 cm voxels (a few hundred hexahedra), its own default seed
#: (the small ellipsoid's lies outside the template's MNI coordinates).
RUN_MNI152 = [*RUN["atrophy"], "--maxh", "2", "--set", "seed=entorhinal"]
#: The fsaverage hemisphere has no coarser mesh (40k tetrahedra): its transport, geometry and
#: measures run here, its mechanics in test_fsaverage_brain.py.
RUN_FSAVERAGE = ["--set", "t_end=4", "--set", "dt=1", "--set", "snapshots=1", "--set",
                 "mechanics=false"]
#: Coarse settings of ``ngincompat bench CASE``, by case.
BENCH = {
    "scenes": ["--scenes", "cube", "--presets", "preview"],
    "folding": ["--axons", "straight", "--preset", "preview", "--set", "t_end=10", "--set",
                "release=false"],
    "cube": ["--maxh", "1", "--orders", "1", "2"],
    "accuracy": ["--quick"],
    "curvature": ["--quick"],
    # a stand-in of the FEniCSx peer in the scratch folder (the peer itself needs its own
    # set-up, see ../shared/peer): the benchmark's plumbing runs, against a coarse cube
    "peer": ["--peer", "peer", "--pairs", "1", "--set", "order=2", "--set", "maxh=1"],
    "stability": ["--quick"],
    "scaling": ["--quick", "--solvers", "sparsecholesky"],
    # two launches of a small brain on 2 ranks (the mpi extra: mpi4py, mpich)
    "mpi": ["--maxh", "4", "--ranks", "2", "--set", "t_end=2", "--set", "dt=1"],
}
#: What each subcommand prints when it is done.
SUMMARY = {
    "list": "cube",
    "run": "results written to",
    "paper": "report written to",
    "expansion": "summary written to",
    "folding": "summary written to",
    "bench": "|",
    "sweep": "written to",
    "--version": "ngincompat",
}


def readme_commands(text):
    """The ngincompat command lines of a page's bash blocks and console prompts, then its
    inline commands with an output folder, each in the order of the page and once."""
    commands = []
    blocks = re.findall(r"```bash\n(.*?)```", text, flags=re.S)
    blocks += ["\n".join(line[2:] for line in block.splitlines() if line.startswith("$ "))
               for block in re.findall(r"```console\n(.*?)```", text, flags=re.S)]
    prose = re.sub(r"```.*?```", "", text, flags=re.S)
    blocks += [span for span in re.findall(r"`([^`\n]+)`", prose)
               if span.startswith("ngincompat ") and "--out" in span.split()]
    for block in blocks:
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            words = shlex.split(line, comments=True)
            starts = [0] + [i + 1 for i, w in enumerate(words) if w == "&&"]
            ends = [i for i, w in enumerate(words) if w == "&&"] + [len(words)]
            for start, end in zip(starts, ends, strict=True):
                while start < end and re.fullmatch(r"[A-Z_]+=\S*", words[start]):
                    start += 1                       # an environment setting before it
                if end > start and Path(words[start]).name == "ngincompat":
                    commands.append(words[start + 1:end])
    unique = {tuple(argv): argv for argv in commands}  # a command shown twice runs once
    return list(unique.values())


def coarse(argv, scheduler=None):
    """``argv`` with the coarse settings of its rule appended (KeyError: no rule); a Dask
    scheduler's address is replaced by ``scheduler``."""
    command = argv[0]
    if command == "run":
        rule = (RUN_MNI152 if "geometry=mni152" in argv else
                RUN_FSAVERAGE if "geometry=fsaverage" in argv else RUN[argv[1]])
        if any(word.startswith("top_refinement=") for word in argv):
            rule = [*rule, *FOLDING_REFINED_TOP]
        return [*argv, *rule, "-q"]
    if command == "paper":
        return [*argv, "--only", "3.1,3.4", "-q"]
    if command == "expansion":
        return [*argv, "--footprints", "circle", *SKIN_COARSE, "-q"]
    if command == "folding":     # the driver on a bilayer that creases into self-contact
        return [*argv, "--axons", "curved", *FOLDING_CREASING, "--set", "release=false", "-q"]
    if command == "bench":
        return [*argv, *BENCH[argv[1]]]
    if command == "sweep":
        if "--scheduler" in argv:
            argv = list(argv)
            argv[argv.index("--scheduler") + 1] = scheduler
        if argv[1] != "run":
            return argv
        return [*argv, *_sweep_coarse(argv[2]), "-q"]
    if command in ("list", "--version"):
        return argv
    raise KeyError(command)


def _sweep_coarse(file):
    """The coarse options of a README sweep: two cases, or one of the skin's, a contact run on
    the skin's coarse settings (those the sweep does not vary: 45 s where the file's own took
    275 s, both at load 4-5) on one NGSolve thread (the default, two threads for one case on
    the 2 cores, oversubscribes them beside the other pytest-xdist worker)."""
    with open(ROOT / file, "rb") as f:
        spec = tomllib.load(f)
    if spec["scene"] != "skin":
        return ["--max-cases", "2"]
    varied = {*spec.get("vary", {}), *spec.get("zip", {})}
    settings = [s for s in SKIN_COARSE[1::2] if s.partition("=")[0] not in varied]
    return ["--max-cases", "1", "--threads", "1", *[w for s in settings for w in ("--set", s)]]


def expected_code(argv, scratch):
    """0, or for a sweep the exit code of failed cases (4) when its table has failed rows:
    the README's example sweep fails nu = 0.5 on purpose, and only that case may fail."""
    if argv[:2] != ["sweep", "run"]:
        return 0
    rows = io.read_json(scratch / argv[argv.index("--out") + 1] / "sweep.json")["rows"]
    failed = [row for row in rows if row["status"] != "done"]
    assert all(row["nu"] == 0.5 and row["status"] == "failed" for row in failed), failed
    return EXIT_FAILED_CASES if failed else 0


def documented_commands(pages):
    """(argv, page) of every command of ``pages``, in their order, each argv once (on the
    first page that shows it)."""
    first = {}
    for page in pages:
        for argv in readme_commands(page.read_text()):
            first.setdefault(tuple(argv), (argv, page))
    return list(first.values())


DOCUMENTED = documented_commands(PAGES)
COMMANDS = [argv for argv, _ in DOCUMENTED]


def test_make_runs_the_two_commands_of_the_readme():
    """``make demo`` and ``make test`` are the README's two set-up commands, word for word."""
    two = re.search(r"## Two commands.*?```bash\n(.*?)```", README.read_text(), flags=re.S)
    commands = [line for line in two.group(1).splitlines()
                if line and not line.startswith("#")]
    recipes = re.findall(r"^(demo|test):\n\t(.+)$", (ROOT / "Makefile").read_text(), flags=re.M)
    assert dict(recipes) == {"demo": commands[0], "test": commands[1]}
    assert "ngincompat paper" in commands[0] and "pytest" in commands[1]


def test_the_main_job_installs_no_extra_and_runs_again():
    """``make demo`` installs the core dependencies alone (the main job needs no extra; the
    test extra brings Dask, MPI, pyarrow, nilearn, ...) and replaces an earlier demo's
    results instead of refusing its folder; ``make test`` installs the test extra."""
    recipes = dict(re.findall(r"^(demo|test):\n\t(.+)$", (ROOT / "Makefile").read_text(),
                              flags=re.M))
    demo, test = (shlex.split(recipes[name]) for name in ("demo", "test"))
    assert demo[demo.index("install") + 1:][:2] == ["-e", "."]
    assert "--overwrite" in demo[demo.index("paper"):]
    assert test[test.index("install") + 1:][:2] == ["-e", ".[test]"]


def test_the_readmes_output_folders_are_ignored_by_git():
    """Every folder the README's commands write into (its first part) is in .gitignore."""
    ignored = set((ROOT / ".gitignore").read_text().split())
    tops = {Path(argv[argv.index("--out") + 1]).parts[0] for argv in COMMANDS
            if "--out" in argv}
    assert {"results", "runs", "sweeps"} <= tops
    assert {f"{top}/" for top in tops} <= ignored, tops


def test_the_readme_is_short_and_undated():
    """The README is a front page (at most 200 lines) with nothing that goes stale: no
    dates, no commit hashes, no timings; measurements live in docs/measurements/."""
    text = README.read_text()
    assert len(text.splitlines()) <= 200
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text)
    assert not re.search(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b", text)
    assert not re.search(r"\b\d+(\.\d+)? ?(s|min|seconds|minutes)\b", text)


def test_the_pages_the_readme_links_exist():
    links = re.findall(r"\]\(((?:docs/|CHANGELOG)[^)#]*)", README.read_text())
    assert len(links) > 10
    missing = [link for link in links if not (ROOT / link).exists()]
    assert not missing, missing


def test_the_documentation_pages_link_only_to_existing_files():
    """Relative links between the hand-written pages (and to their figures) resolve."""
    for page in [*GUIDE, *MEASUREMENTS]:
        for link in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", page.read_text()):
            assert (page.parent / link).exists(), (page.name, link)


def test_the_docs_show_commands_of_every_kind():
    kinds = {argv[0] for argv in COMMANDS}
    assert {"list", "run", "paper", "expansion", "folding", "bench", "sweep"} <= kinds
    assert {argv[1] for argv in COMMANDS if argv[0] == "run"} == set(RUN)


def test_every_readme_command_has_a_coarse_rule():
    for argv in COMMANDS:
        coarse(argv)   # raises KeyError naming what has no rule


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    folder = tmp_path_factory.mktemp("readme")
    (folder / "examples").symlink_to(ROOT / "examples")
    peer_stand_in(folder / "peer")
    return folder


@pytest.fixture(scope="module")
def dask_scheduler():
    """A local Dask cluster, for the README's ``--scheduler tcp://host:8786``."""
    with local_dask_cluster() as cluster:
        yield cluster.scheduler_address


def _tier(page):
    """The measurement logs' own commands are slow; the README's and the guide's are not."""
    return [pytest.mark.slow] if page in MEASUREMENTS else []


@pytest.mark.parametrize("index", [pytest.param(i, marks=_tier(page))
                                   for i, (_, page) in enumerate(DOCUMENTED)],
                         ids=[f"{page.stem}: {' '.join(argv[:3])}" for argv, page in DOCUMENTED])
def test_readme_command_runs(index, scratch, monkeypatch, capsys, request):
    argv = COMMANDS[index]
    scheduler = request.getfixturevalue("dask_scheduler") if "--scheduler" in argv else None
    argv = coarse(argv, scheduler)
    monkeypatch.chdir(scratch)
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(scratch / "cache"))   # built meshes (mni152)
    code = main(argv)
    captured = capsys.readouterr()
    assert code == expected_code(argv, scratch), (argv, captured.err[-2000:])
    assert "Traceback" not in captured.err
    assert SUMMARY[argv[0]] in captured.out, captured.out[-2000:]


PYTHON_PAGES = [page for page in PAGES if "```python" in page.read_text()]


@pytest.mark.parametrize("page", [pytest.param(p, marks=_tier(p)) for p in PYTHON_PAGES],
                         ids=[p.stem for p in PYTHON_PAGES])
def test_readme_python_blocks_run(page, monkeypatch, tmp_path):
    """Each Python block of a page runs on its own (its imports included), in a scratch
    folder, in the order of the page."""
    monkeypatch.chdir(tmp_path)
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
    assert blocks
    for block in blocks:
        exec(compile(block, str(page.relative_to(ROOT)), "exec"), {})


def test_the_readme_and_the_python_guide_have_python_examples():
    for page in (README, DOCS / "guide" / "python.md"):
        assert re.search(r"```python\n", page.read_text()), page
