"""write_atomic leaves either the old file or the whole new one, never a part."""
import os

import pytest

from ltl_stack.fileio import write_atomic


def test_writes_the_whole_file_with_the_given_mode(tmp_path):
    target = tmp_path / "out.txt"
    write_atomic(target, "hello\n", mode=0o640)
    assert target.read_text() == "hello\n"
    assert (target.stat().st_mode & 0o777) == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_failure_keeps_the_old_file_and_leaves_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "out.txt"
    target.write_text("old")

    def broken_replace(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(OSError):
        write_atomic(target, "new")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_unwritable_folder_raises_oserror(tmp_path):
    with pytest.raises(OSError):
        write_atomic(tmp_path / "missing" / "out.txt", "x")
