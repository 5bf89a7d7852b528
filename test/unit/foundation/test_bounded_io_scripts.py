"""Endless and special files through the real scripts: where a tool expects a file, a
device (``/dev/zero``), a FIFO or a folder is refused before a byte is read (never a read until
memory runs out, never a blocked open), also for a ``Map:`` inside a ``.spec``; an output naming a
FIFO or a folder is refused, never replaced by a regular file. Each case: its exit code, exactly one
``<tool>: error:`` line on stderr naming the path, no traceback, every file of the folder as it was.
No ROS master is needed: each tool stops before it would talk to one."""
from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import REPO_ROOT, script_marks, shared_dir

from ltl_stack.errors import Exit
from ltl_stack.fileio import output_refusal

SPEC = (REPO_ROOT / "config" / "simple" / "simple.structuredslugs").read_text()
MAPPING = (REPO_ROOT / "config" / "simple" / "simple.yaml").read_text()
ENGLISH = (REPO_ROOT / "config" / "clean_and_patrol" / "clean_and_patrol.spec").read_text()
SNAPSHOT = "format: ltl_stack/graph_snapshot/1\nnodes: [/a]\ntopics: {}\n"
PROGRAM = (REPO_ROOT / "test" / "data" / "transfer" / "keyboard_jackal.py").read_text()
FIFO_IN = "is a FIFO (named pipe), not a regular file"
DEVICE_IN = "/dev/zero: is a character device, not a regular file"
FIFO_OUT = "{d}/fifo: cannot be an output: it is a FIFO (named pipe), not a regular file"
DIR_OUT = "{d}/folder: cannot be an output: it is a directory, not a regular file"
ANALYZE = ["--mapping", "{d}/simple.yaml", "--snapshot", "{d}/snap.yaml"]
TRANSFER = ["--from", "jackal", "--to", "turtlebot", "--robots", "{robots}", "-q"]

# case: (tool, arguments ({d}: the case's folder), exit code, text of the one error line)
CASES = {
    "synthesize spec /dev/zero": ("synthesize", ["/dev/zero"], Exit.BAD_INPUT, DEVICE_IN),
    "synthesize spec FIFO": ("synthesize", ["{d}/fifo"], Exit.BAD_INPUT, "{d}/fifo: " + FIFO_IN),
    "synthesize Map: /dev/zero": ("synthesize", ["{d}/zero.spec"], Exit.BAD_INPUT,
                                  "{d}/zero.spec:12:6: cannot read the map: " + DEVICE_IN),
    "synthesize Map: FIFO": ("synthesize", ["{d}/fifo.spec"], Exit.BAD_INPUT,
                             "{d}/fifo.spec:12:6: cannot read the map: {d}/fifo: " + FIFO_IN),
    "synthesize --strategy-json FIFO": ("synthesize", ["{d}/simple.structuredslugs", "--strategy-json", "{d}/fifo"],
                                        Exit.BAD_INPUT, FIFO_OUT),
    "synthesize --dot folder": ("synthesize", ["{d}/simple.structuredslugs", "--dot", "{d}/folder"],
                                Exit.BAD_INPUT, DIR_OUT),
    "generate_launch mapping /dev/zero": ("generate_launch", ["/dev/zero"], Exit.BAD_INPUT, DEVICE_IN),
    "generate_launch mapping FIFO": ("generate_launch", ["{d}/fifo"], Exit.BAD_INPUT, "{d}/fifo: " + FIFO_IN),
    "generate_launch spec FIFO": ("generate_launch", ["{d}/simple.yaml", "--spec", "{d}/fifo"], Exit.BAD_INPUT,
                                  "{d}/fifo: " + FIFO_IN),
    "generate_launch -o FIFO": ("generate_launch", ["{d}/simple.yaml", "-o", "{d}/fifo"], Exit.BAD_INPUT, FIFO_OUT),
    "generate_launch -o folder": ("generate_launch", ["{d}/simple.yaml", "-o", "{d}/folder"], Exit.BAD_INPUT,
                                  DIR_OUT),
    "analyze_graph spec /dev/zero": ("analyze_graph", ["--spec", "/dev/zero", *ANALYZE], Exit.BAD_INPUT, DEVICE_IN),
    "analyze_graph mapping FIFO": ("analyze_graph", ["--spec", "{d}/simple.structuredslugs", "--mapping", "{d}/fifo",
                                                     "--snapshot", "{d}/snap.yaml"], Exit.BAD_INPUT,
                                   "{d}/fifo: " + FIFO_IN),
    "analyze_graph snapshot /dev/zero": ("analyze_graph", ["--spec", "{d}/simple.structuredslugs", "--mapping",
                                                           "{d}/simple.yaml", "--snapshot", "/dev/zero"],
                                         Exit.BAD_INPUT, DEVICE_IN),
    "analyze_graph --apply FIFO": ("analyze_graph", ["--spec", "{d}/simple.structuredslugs", *ANALYZE, "--apply",
                                                     "{d}/fifo"], Exit.BAD_INPUT, FIFO_OUT),
    "analyze_graph --save-snapshot folder": ("analyze_graph", ["--spec", "{d}/simple.structuredslugs", *ANALYZE,
                                                               "--save-snapshot", "{d}/folder"], Exit.BAD_INPUT,
                                             DIR_OUT),
    "mine_channels -o FIFO": ("mine_channels", ["{d}/programs", "--robot", "jackal", "-q", "-o", "{d}/fifo"],
                              Exit.BAD_INPUT, FIFO_OUT),
    "ros_code_transfer source FIFO": ("ros_code_transfer", ["{d}/fifo", *TRANSFER, "-o", "{d}/out.py"],
                                      Exit.BAD_INPUT, "{d}/fifo: " + FIFO_IN),
    "ros_code_transfer -o FIFO": ("ros_code_transfer", ["{d}/programs/drive.py", *TRANSFER, "-o", "{d}/fifo"],
                                  Exit.BAD_INPUT, FIFO_OUT),
    "ros_code_transfer --json-report folder": ("ros_code_transfer", ["{d}/programs/drive.py", *TRANSFER, "-o",
                                                                     "{d}/out.py", "--json-report", "{d}/folder"],
                                               Exit.BAD_INPUT, DIR_OUT),
}


def _state(folder: Path) -> dict[str, object]:
    """Every entry under ``folder``: a regular file's bytes, else its kind (a FIFO is never read)."""
    out: dict[str, object] = {}
    for p in sorted(folder.rglob("*")):
        mode = p.lstat().st_mode
        out[str(p.relative_to(folder))] = p.read_bytes() if stat.S_ISREG(mode) else stat.S_IFMT(mode)
    return out


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "simple.structuredslugs").write_text(SPEC)
    (tmp_path / "simple.yaml").write_text(MAPPING)
    (tmp_path / "snap.yaml").write_text(SNAPSHOT)
    (tmp_path / "zero.spec").write_text(ENGLISH.replace("Map: clean_and_patrol.regions", "Map: /dev/zero"))
    (tmp_path / "fifo.spec").write_text(ENGLISH.replace("Map: clean_and_patrol.regions", f"Map: {tmp_path}/fifo"))
    (tmp_path / "programs").mkdir()
    (tmp_path / "programs" / "drive.py").write_text(PROGRAM)
    (tmp_path / "folder").mkdir()
    os.mkfifo(tmp_path / "fifo")
    return tmp_path


def test_the_english_spec_uses_its_map_on_line_12():
    assert ENGLISH.splitlines()[11] == "Map: clean_and_patrol.regions"


@pytest.mark.parametrize("case", [pytest.param(c, marks=script_marks(CASES[c][0])) for c in CASES])
def test_special_files_are_refused_with_one_error_line(folder, case):
    tool, arguments, code, message = CASES[case]
    robots = shared_dir()
    if "{robots}" in arguments and robots is None:
        pytest.skip("../shared/robots is absent")
    args = [a.format(d=folder, robots=robots and robots / "robots") for a in arguments]
    before = _state(folder)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO_ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    env.pop("ROS_MASTER_URI", None)
    # a FIFO opened for reading the old way blocked forever: the timeout turns that into a failure
    done = subprocess.run([sys.executable, str(REPO_ROOT / "scripts" / tool), *args], capture_output=True,
                          text=True, timeout=120, env=env, cwd=folder, stdin=subprocess.DEVNULL)
    assert done.returncode == code, (done.returncode, done.stderr[-2000:])
    lines = done.stderr.splitlines()
    errors = [line for line in lines if "error:" in line]
    assert len(errors) == 1 and lines == errors and errors[0].startswith(f"{tool}: error: "), lines
    assert message.format(d=folder) in errors[0], (message.format(d=folder), errors[0])
    assert "Traceback" not in done.stderr + done.stdout, done.stderr[-3000:]
    assert _state(folder) == before


@pytest.mark.parametrize("path, refused", [
    ("/dev/null", "it is a character device, not a regular file"), ("/dev/zero", "character device"),
    (".", "it is a directory, not a regular file"), ("no/such/file", None), ("new.json", None),
])
def test_output_refusal_names_what_is_there(path, refused, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    got = output_refusal(path)
    assert (got is None) if refused is None else (refused in got), got
