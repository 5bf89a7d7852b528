"""The panels' worker child is isolated from the user's folder, and what it writes on its pipe is
checked: a ``pickle.py`` in the folder the panel was started from does not run inside the child, and
a child that writes garbage ends the job with one line (``WorkFailed``), not a raw exception."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from ltl_stack.errors import Exit

CONFIG = Path(__file__).resolve().parents[3] / "config"
SIMPLE = CONFIG / "simple" / "simple.structuredslugs"


def test_a_pickle_module_in_the_current_folder_does_not_run_in_the_child(tmp_path, monkeypatch):
    from ltl_stack.gui.controller_model import ViewOptions
    from ltl_stack.gui.worker_process import WorkerProcess, controller_model

    marker = tmp_path / "ran"
    (tmp_path / "pickle.py").write_text(f"open({str(marker)!r}, 'w').close()\nraise SystemExit(7)\n")
    monkeypatch.chdir(tmp_path)
    worker = WorkerProcess()
    try:
        model = controller_model(worker, str(SIMPLE), ViewOptions(), lambda _text: None)
    finally:
        worker.close()
    assert not marker.exists()
    assert model.automaton is not None and len(model.automaton.states) > 0


# what a broken child writes on its stdout -> the start of the one line the panel shows
GARBAGE = {
    "not a pickle": (b"garbage\n", "the worker process sent an unreadable reply"),
    "a pickle that is not a reply": (b"\x80\x04K\x05.", "the worker process sent a malformed reply (5)"),
    "an error reply of the wrong shape": (b"\x80\x04\x95\x0b\x00\x00\x00\x00\x00\x00\x00\x8c\x05error\x94\x85\x94.",
                                          "the worker process sent a malformed 'error' reply"),
    "nothing": (b"", "the worker process ended unexpectedly"),
}


@pytest.mark.parametrize("case", list(GARBAGE))
def test_garbage_on_the_childs_pipe_is_one_line(case, monkeypatch):
    from ltl_stack.gui import worker_process

    data, message = GARBAGE[case]
    code = f"import sys; sys.stdin.buffer.read(1); sys.stdout.buffer.write({data!r}); sys.stdout.flush()"
    monkeypatch.setattr(worker_process, "child_command", lambda: [sys.executable, "-I", "-c", code])
    worker = worker_process.WorkerProcess()
    try:
        with pytest.raises(worker_process.WorkFailed) as err:
            list(worker.run("automaton", {"spec": "x"}, lambda _text: None))
    finally:
        worker.close()
    assert str(err.value).startswith(message) and "\n" not in str(err.value), str(err.value)
    assert err.value.code == Exit.NEGATIVE


def test_the_child_command_is_isolated_and_names_no_relative_path(tmp_path, monkeypatch):
    from ltl_stack.gui.worker_process import child_command

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", ["", ".", str(tmp_path), *sys.path])
    command = child_command()
    assert command[:3] == [sys.executable, "-I", "-c"], command
    assert repr(str(tmp_path)) not in command[3] and "'.'" not in command[3] and "''" not in command[3]
    assert os.path.isabs(command[0])
