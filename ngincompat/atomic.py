"""Files written atomically: a temporary name in the target folder, then renamed.

``os.replace`` is atomic on POSIX, so an interrupted run never leaves a half-written file
behind: a reader sees the old file or the new one, never a part of either.
"""

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it to ``path``.

    The temporary file is created empty with mode 0o666, so the kernel applies the umask (and
    a default ACL of the folder) exactly as for a file made with :func:`open`: the result is
    as readable as any other file the user writes (``tempfile.mkstemp`` would make it 0o600).

    Parameters
    ----------
    path : str or pathlib.Path
        The final name; missing parent folders are created.

    Yields
    ------
    pathlib.Path
        The temporary file to write (it exists, empty); it is removed if the block fails.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        tmp = path.with_name(f".{path.name}.{os.urandom(6).hex()}{path.suffix}")
        try:
            fd = os.open(tmp, flags, 0o666)
        except FileExistsError:
            continue
        break
    else:  # pragma: no cover - 100 collisions of 48 random bits
        raise FileExistsError(f"no free temporary name next to {path}")
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
