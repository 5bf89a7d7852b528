"""Bad input to the real ``scripts/analyze_graph`` (a subprocess, no ROS master, no catkin workspace):
every case exits with its code from the one table, prints exactly one ``analyze_graph: error:`` line
naming the file (and line), no traceback, and leaves every file in the folder as it was (no output
created, no input changed)."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from ltl_stack.errors import Exit

REPO = Path(__file__).resolve().parents[3]
SCRIPT = REPO / "scripts" / "analyze_graph"
SPEC = """[INPUT]
person

[OUTPUT]
move
stop

[SYS_TRANS]
move'
person' -> stop'
"""
MAPPING = """inputs:
  person: {node: /person, node_publish_topic: /simple/inputs/person}
outputs:
  move: {node: /move, node_subscribe_topic: /simple/outputs/move}
  stop: {node: /stop, node_subscribe_topic: /simple/outputs/stop}
"""
SNAPSHOT = """format: ltl_stack/graph_snapshot/1
nodes: [/person, /move, /stop, /base]
topics:
  /simple/inputs/person: {type: std_msgs/Bool, publishers: [/person], subscribers: []}
  /simple/outputs/move: {type: std_msgs/Bool, publishers: [], subscribers: [/move]}
  /simple/outputs/stop: {type: std_msgs/Bool, publishers: [], subscribers: [/stop]}
  /cmd_vel: {type: geometry_msgs/Twist, publishers: [/move, /stop], subscribers: [/base]}
"""
DEEP = 100000
LONG = "7" * 5000


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# case: (files to write over the good ones {name: bytes}, extra args, exit code, expected error text)
# The error text may use {d} for the folder. The good files are spec.structuredslugs, map.yaml, snap.yaml, snap.json.
CASES = {
    "binary spec": ({"spec.structuredslugs": b"[INPUT]\nperson\n\x00\x01\n"}, [], Exit.BAD_INPUT,
                    "{d}/spec.structuredslugs:3: not a text spec file: it holds a NUL byte"),
    "non-UTF-8 spec": ({"spec.structuredslugs": b"[INPUT]\npers\xf6n\n"}, [], Exit.BAD_INPUT,
                       "{d}/spec.structuredslugs:2: not a text spec file: not UTF-8"),
    "binary mapping": ({"map.yaml": b"inputs:\n  person: {node: /p\x00}\n"}, [], Exit.BAD_INPUT,
                       "{d}/map.yaml:2: not a text mapping file: it holds a NUL byte"),
    "non-UTF-8 mapping": ({"map.yaml": b"inputs:\n\n  person: {node: /caf\xe9}\n"}, [], Exit.BAD_INPUT,
                          "{d}/map.yaml:3: not a text mapping file: not UTF-8"),
    "mapping does not fit the spec": ({"map.yaml": MAPPING.encode() + b"  nosuch: {node: /n}\n"}, [], Exit.BAD_INPUT,
                                      "{d}/map.yaml:6: output 'nosuch' is not a proposition of the spec"),
    "mapping key 5": ({"map.yaml": MAPPING.encode() + b"  5: {node: /x}\n"}, [], Exit.BAD_INPUT,
                      "{d}/map.yaml:6: key '5' is not a string"),
    "mapping key yes": ({"map.yaml": b"inputs:\n  yes: {node: /x}\n"}, [], Exit.BAD_INPUT,
                        "{d}/map.yaml:2: key 'yes' is not a string"),
    "mapping key ~": ({"map.yaml": b"~: 1\n"}, [], Exit.BAD_INPUT, "{d}/map.yaml:1: key '~' is not a string"),
    "mapping deeply nested": ({"map.yaml": b"inputs:\n  person: " + b"[" * DEEP + b"\n"}, [], Exit.BAD_INPUT,
                              "{d}/map.yaml:2: nested more than 100 levels deep"),
    "mapping long integer": ({"map.yaml": MAPPING.replace("/person}", "/person, parameters: {n: " + LONG + "}}")
                              .encode()}, [], Exit.BAD_INPUT, "{d}/map.yaml:2: integer of 5000 digits"),
    "binary snapshot": ({"snap.yaml": b"nodes: [/a]\n\x00"}, [], Exit.BAD_INPUT,
                        "{d}/snap.yaml:2: not a text snapshot: it holds a NUL byte"),
    "non-UTF-8 snapshot": ({"snap.json": b'{"nodes":\n ["/caf\xe9"]}'}, ["--snapshot", "{d}/snap.json"],
                           Exit.BAD_INPUT, "{d}/snap.json:2: not a text snapshot: not UTF-8"),
    "snapshot key 5": ({"snap.yaml": SNAPSHOT.encode() + b"5: x\n"}, [], Exit.BAD_INPUT,
                       "{d}/snap.yaml:8: key '5' is not a string"),
    "snapshot key yes": ({"snap.yaml": b"topics:\n  yes: {}\n"}, [], Exit.BAD_INPUT,
                         "{d}/snap.yaml:2: key 'yes' is not a string"),
    "snapshot key ~": ({"snap.yaml": b"~: 1\n"}, [], Exit.BAD_INPUT, "{d}/snap.yaml:1: key '~' is not a string"),
    "snapshot deeply nested YAML": ({"snap.yaml": b"nodes: " + b"[" * DEEP}, [], Exit.BAD_INPUT,
                                    "{d}/snap.yaml:1: nested more than 100 levels deep"),
    "snapshot deeply nested JSON": ({"snap.json": b'{"nodes":\n' + b"[" * DEEP + b"]" * DEEP + b"}"},
                                    ["--snapshot", "{d}/snap.json"], Exit.BAD_INPUT,
                                    "{d}/snap.json:2: nested more than 100 levels deep"),
    "snapshot long integer YAML": ({"snap.yaml": b"nodes: [/a]\ntaken: " + LONG.encode() + b"\n"}, [],
                                   Exit.BAD_INPUT, "{d}/snap.yaml:2: integer of 5000 digits"),
    "snapshot long integer JSON": ({"snap.json": b'{"taken": ' + LONG.encode() + b"}"},
                                   ["--snapshot", "{d}/snap.json"], Exit.BAD_INPUT,
                                   "{d}/snap.json: invalid JSON value"),
    "apply = spec": ({}, ["--apply", "{d}/spec.structuredslugs"], Exit.BAD_INPUT,
                     "{d}/spec.structuredslugs: output would overwrite the input {d}/spec.structuredslugs"),
    "save-snapshot = mapping": ({}, ["--save-snapshot", "{d}/map.yaml"], Exit.BAD_INPUT,
                                "{d}/map.yaml: output would overwrite the input {d}/map.yaml"),
    "save-snapshot = snapshot": ({}, ["--save-snapshot", "{d}/snap.yaml"], Exit.BAD_INPUT,
                                 "{d}/snap.yaml: output would overwrite the input {d}/snap.yaml"),
    "apply = spec through a symlink": ({}, ["--apply", "{d}/link.slugsin"], Exit.BAD_INPUT,
                                       "{d}/link.slugsin: output would overwrite the input {d}/spec.structuredslugs"),
    "save-snapshot = snapshot, other spelling": ({}, ["--save-snapshot", "{d}/../{n}/./snap.yaml"], Exit.BAD_INPUT,
                                                 "output would overwrite the input {d}/snap.yaml"),
    "apply = save-snapshot": ({}, ["--apply", "{d}/same", "--save-snapshot", "{d}/same"], Exit.BAD_INPUT,
                              "{d}/same: named for two outputs"),
    "malformed master URI": ({}, ["--live", "--master-uri", "localhost:11311"], Exit.BAD_INPUT,
                             "--master-uri 'localhost:11311' is not a ROS master URI"),
    "master URI port out of range": ({}, ["--live", "--master-uri", "http://127.0.0.1:99999/"], Exit.BAD_INPUT,
                                     "--master-uri 'http://127.0.0.1:99999/' is not a ROS master URI"),
    "unreachable master": ({}, ["--live", "--master-uri", "http://127.0.0.1:{port}/"], Exit.NO_ROS,
                           "cannot read the graph from the ROS master at http://127.0.0.1:{port}/"),
    "master URI without --live": ({}, ["--master-uri", "http://127.0.0.1:1/"], Exit.BAD_INPUT,
                                  "--master-uri needs --live"),
    "suggestion number out of range": ({}, ["--suggestions", "7"], Exit.BAD_INPUT,
                                       "--suggestions: '7' is not a suggestion number (there are 1)"),
}


def _run(folder: Path, extra: list[str]) -> subprocess.CompletedProcess:
    args = ["--spec", f"{folder}/spec.structuredslugs", "--mapping", f"{folder}/map.yaml"]
    if "--snapshot" not in extra and "--live" not in extra:
        args += ["--snapshot", f"{folder}/snap.yaml"]
    if "--apply" not in extra and "--save-snapshot" not in extra and "--live" not in extra:
        args += ["--apply", f"{folder}/out.slugsin", "--save-snapshot", f"{folder}/out.json"]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO / "src"), os.environ.get("PYTHONPATH", "")]))
    env.pop("ROS_MASTER_URI", None)
    return subprocess.run([sys.executable, str(SCRIPT), *args, *extra], capture_output=True, text=True,
                          timeout=300, env=env, cwd=folder)


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() if p.is_file() else b"<link or dir>" for p in sorted(folder.iterdir())}


@pytest.fixture
def folder(tmp_path) -> Path:
    (tmp_path / "spec.structuredslugs").write_text(SPEC)
    (tmp_path / "map.yaml").write_text(MAPPING)
    (tmp_path / "snap.yaml").write_text(SNAPSHOT)
    (tmp_path / "link.slugsin").symlink_to(tmp_path / "spec.structuredslugs")
    return tmp_path


@pytest.mark.parametrize("case", list(CASES))
def test_bad_input_through_the_real_script(folder, case):
    files, extra, code, message = CASES[case]
    for name, data in files.items():
        (folder / name).write_bytes(data)
    port = str(_free_port())
    fill = {"d": str(folder), "n": folder.name, "port": port}
    extra = [a.format(**fill) for a in extra]
    before = _files(folder)
    done = _run(folder, extra)
    assert done.returncode == code, (done.returncode, done.stderr[-2000:])
    errors = [line for line in done.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1, done.stderr[-2000:]
    # no continuation line: every line is the tool's own (progress, or the one error)
    assert all(line.startswith("analyze_graph: ") for line in done.stderr.splitlines()), done.stderr[-2000:]
    assert errors[0].startswith("analyze_graph: error: ") and errors[0].count("error:") == 1, errors
    assert message.format(**fill) in errors[0], errors
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
    assert done.stdout == "", done.stdout[-2000:]
    assert _files(folder) == before, "an output was created or an input changed"


def test_the_good_files_pass_and_both_outputs_are_written(folder):
    """The table's base case works, so each bad case fails for its own reason: thesis Example 7's
    move/stop conflict is found, and excluding them makes "always move" unrealizable (exit 10); the
    patched spec is still written, for the user to edit, with the snapshot."""
    done = _run(folder, [])
    assert done.returncode == Exit.UNREALIZABLE, done.stderr[-2000:]
    assert "move and stop are mutually exclusive" in done.stdout, done.stdout
    assert "The new spec is UNREALIZABLE" in done.stdout, done.stdout
    assert (folder / "out.slugsin").is_file() and (folder / "out.json").is_file()
    assert "analyze_graph: spec written to" in done.stderr and "Traceback" not in done.stderr
    assert "error:" not in done.stderr, done.stderr


def test_help_exits_0_and_lists_the_exit_codes():
    done = subprocess.run([sys.executable, str(SCRIPT), "--help"], capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO / "src"),
                                                                           os.environ.get("PYTHONPATH", "")])))
    assert done.returncode == 0 and "exit codes: 0 " in done.stdout and "10 the specification is unrealizable" \
        in done.stdout, done.stdout
