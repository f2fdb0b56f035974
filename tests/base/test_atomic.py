"""ngincompat.atomic: a write renamed into place; an interrupted one leaves the old file whole."""

import os
import stat

import pytest

from ngincompat.atomic import atomic_path


def test_the_file_appears_with_its_content_and_its_folders(tmp_path):
    target = tmp_path / "a" / "b" / "results.json"
    with atomic_path(str(target)) as tmp:
        assert tmp.parent == target.parent and tmp != target
        assert tmp.is_file() and tmp.read_bytes() == b""      # exists, empty
        assert not target.exists()                             # not before the end
        tmp.write_text('{"step": 1}')
    assert target.read_text() == '{"step": 1}'
    assert os.listdir(target.parent) == ["results.json"]


def test_the_temporary_name_is_hidden_and_keeps_the_suffix(tmp_path):
    """A dotted name that globbing for ``*.png`` and the like does not pick up half-written;
    its suffix stays the target's, for writers that choose the format by it."""
    with atomic_path(tmp_path / "figure.png") as tmp:
        assert tmp.name.startswith(".figure.png.") and tmp.suffix == ".png"
        tmp.write_bytes(b"png")
    assert [p.name for p in tmp_path.iterdir()] == ["figure.png"]


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path, error):
    target = tmp_path / "results.json"
    target.write_text("old")
    with pytest.raises(error):
        with atomic_path(target) as tmp:
            tmp.write_text("partial")
            raise error("stopped")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["results.json"]


def test_an_interrupted_first_write_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_path(tmp_path / "new.txt") as tmp:
            tmp.write_text("partial")
            raise RuntimeError
    assert list(tmp_path.iterdir()) == []


def test_a_reader_of_the_old_file_keeps_reading_it_whole(tmp_path):
    """The rename replaces the directory entry, not the old file's content: a reader that
    opened it before goes on reading the old file, a new reader sees the new one."""
    target = tmp_path / "table.csv"
    target.write_text("old,old\n")
    with open(target) as reader:
        with atomic_path(target) as tmp:
            tmp.write_text("new,new,new\n")
        assert reader.read() == "old,old\n"
    assert target.read_text() == "new,new,new\n"


def test_two_writes_to_one_name_use_two_temporaries(tmp_path):
    target = tmp_path / "x.txt"
    with atomic_path(target) as first, atomic_path(target) as second:
        assert first != second
        first.write_text("first")
        second.write_text("second")
    assert target.read_text() == "first"            # the outer block ends last
    assert [p.name for p in tmp_path.iterdir()] == ["x.txt"]


@pytest.mark.skipif(os.name != "posix", reason="file modes and the umask are POSIX")
def test_the_file_gets_the_mode_open_would_give(tmp_path):
    old = os.umask(0o027)
    try:
        with atomic_path(tmp_path / "out.txt") as tmp:
            tmp.write_text("x")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "out.txt").stat().st_mode) == 0o640
