"""Never a traceback, through the real scripts: every tool and node started with its
stdout closed (``tool >&-``), integer literals past Python's 4300-digit limit in specs, and numbers
of more than 18 digits in options. Each is one ``<tool>: error:`` line on stderr and the exit code of
the one table. No ROS master is needed (every script and node: test/integration/test_tools_bad_input.py)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import REPO_ROOT, script_marks

from ltl_stack.errors import Exit

#: the scripts that run without generated messages (test/integration/test_tools_bad_input.py: all)
ROS_FREE = ["synthesize", "generate_launch", "analyze_graph", "ros_code_transfer", "mine_channels"]
SIMPLE = REPO_ROOT / "config" / "simple"
LONG = "7" * 5000
CLOSED = "cannot write the output: standard output is closed"


def run(args: list[str], cwd: Path, close_stdout: bool = False) -> subprocess.CompletedProcess:
    """``python scripts/<tool> ARGS`` without a master; with stdout closed as ``>&-`` does."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO_ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    env.pop("ROS_MASTER_URI", None)
    command = [sys.executable, str(REPO_ROOT / "scripts" / args[0]), *args[1:]]
    if close_stdout:
        command = ["bash", "-c", 'exec "$@" >&-', "bash", *command]
    return subprocess.run(command, capture_output=not close_stdout, stderr=subprocess.PIPE if close_stdout else None,
                          text=True, timeout=300, env=env, cwd=cwd, stdin=subprocess.DEVNULL)


def one_error(done: subprocess.CompletedProcess, tool: str) -> str:
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr[-3000:]
    errors = [line for line in done.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1 and errors[0].startswith(f"{tool}: error: "), done.stderr[-2000:]
    return errors[0]


@pytest.mark.parametrize("tool", [pytest.param(t, marks=script_marks(t)) for t in ROS_FREE])
def test_help_with_stdout_closed_is_one_error_line_and_exit_4(tool, tmp_path):
    done = run([tool, "--help"], tmp_path, close_stdout=True)
    assert done.returncode == Exit.WRITE_FAILED, (done.returncode, done.stderr[-2000:])
    assert one_error(done, tool) == f"{tool}: error: {CLOSED}"


@pytest.mark.parametrize("args", [
    ["synthesize", str(SIMPLE / "simple.structuredslugs")],
    ["synthesize", str(SIMPLE / "simple.structuredslugs"), "--json"],
    ["generate_launch", str(SIMPLE / "simple.yaml"), "--spec", str(SIMPLE / "simple.structuredslugs")],
    ["mine_channels", str(REPO_ROOT / "test" / "data" / "transfer"), "--robot", "jackal", "-q"],
], ids=lambda a: " ".join(x if "/" not in x else Path(x).name for x in a))
def test_a_tool_whose_stdout_is_closed_says_so_in_one_line(args, tmp_path):
    done = run(args, tmp_path, close_stdout=True)
    assert done.returncode == Exit.WRITE_FAILED, (done.returncode, done.stderr[-2000:])
    assert one_error(done, args[0]) == f"{args[0]}: error: {CLOSED}"
    assert list(tmp_path.iterdir()) == []  # nothing landed in a file that took stdout's place


def test_a_tool_writing_only_files_ignores_a_closed_stdout(tmp_path):
    done = run(["synthesize", str(SIMPLE / "simple.structuredslugs"), "--strategy-json", "out.json", "--json"],
               tmp_path, close_stdout=True)
    assert done.returncode == Exit.WRITE_FAILED, done.stderr
    assert (tmp_path / "out.json").read_text().startswith("{")


# case: (file name, text) of a spec, the error line's text
SPECS = {
    "structured number": ("a.structuredslugs", f"[INPUT]\nx:0...3\n[OUTPUT]\ny\n[SYS_TRANS]\ny' <-> x' = {LONG}\n",
                          "a.structuredslugs:6:13: a number of 5000 digits (at most 18)"),
    "structured sum": ("a.structuredslugs", f"[INPUT]\nx:0...3\n[OUTPUT]\ny\n[SYS_TRANS]\ny' <-> x' + {LONG} = 2\n",
                       "a.structuredslugs:6:13: a number of 5000 digits (at most 18)"),
    "integer bound": ("b.structuredslugs", f"[INPUT]\nx:0...{LONG}\n[OUTPUT]\ny\n",
                      "b.structuredslugs:2:1: integer 'x' has a bound of more than 18 digits"),
    "19-digit bound": ("b.structuredslugs", f"[INPUT]\nx:-{'1' * 19}...0\n[OUTPUT]\ny\n",
                       "b.structuredslugs:2:1: integer 'x' has a bound of more than 18 digits"),
    "slugsin $ count": ("c.slugsin", f"[INPUT]\nx\n[OUTPUT]\ny\n[SYS_TRANS]\n$ {LONG} y\n",
                        "c.slugsin:6:3: expected a positive number of entries after '$'"),
    "slugsin ? index": ("c.slugsin", f"[INPUT]\nx\n[OUTPUT]\ny\n[SYS_TRANS]\n$ 2 y & ? {LONG} x\n",
                        "c.slugsin:6:11: expected an entry number after '?'"),
}


@pytest.mark.parametrize("case", list(SPECS))
def test_over_long_numbers_in_a_spec_are_one_error_line(case, tmp_path):
    name, text, message = SPECS[case]
    (tmp_path / name).write_text(text)
    done = run(["synthesize", name], tmp_path)
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, done.stderr[-2000:])
    assert one_error(done, "synthesize").startswith(f"synthesize: error: {message}"), done.stderr[-500:]


def test_a_slugs_integer_bit_with_a_long_bound_is_a_plain_proposition(tmp_path):
    (tmp_path / "d.slugsin").write_text(f"[INPUT]\nx@0.0.{LONG}\n[OUTPUT]\ny\n")
    done = run(["synthesize", "d.slugsin"], tmp_path)
    assert done.returncode == Exit.OK and "Traceback" not in done.stderr, done.stderr[-2000:]


@pytest.mark.parametrize("option, value", [("--timeout", "1" * 19), ("--timeout", "1e19"), ("--max-states", "9" * 19),
                                           ("--timeout", LONG), ("--max-states", LONG), ("--timeout", "1e-300")])
def test_over_long_option_numbers_are_one_error_line(option, value, tmp_path):
    done = run(["synthesize", str(SIMPLE / "simple.structuredslugs"), option, value], tmp_path)
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, done.stderr[-2000:])
    assert f"argument {option}: " in one_error(done, "synthesize")


@pytest.mark.ros_python
def test_the_readme_says_what_the_input_nodes_allow_for_a_zero_rate():
    """README and ``topic_threshold_sensor --help`` once disagreed on ``_rate:=0``: it is allowed
    (only on change), and the README says so."""
    from ltl_stack.ros.proposition_node import INPUT_PARAMS
    from ltl_stack.runtime.config.node_params import Bound, coerce_param

    rate = next(p for p in INPUT_PARAMS if p.name == "rate")
    assert rate.bound is Bound.RATE_OR_ZERO and "0: only on change" in rate.doc and coerce_param(rate, 0) == 0
    readme = " ".join((REPO_ROOT / "README.md").read_text().split())
    assert "an input node's `_rate:=0` is allowed: it publishes only on change" in readme


MISFIT = "inputs:\n  person: {node: /p}\n  nosuch: {node: /n}\noutputs:\n  other: {node: /o}\n"
SPEC_OF = "[INPUT]\nperson\n[OUTPUT]\nstop\n[SYS_TRANS]\n{}\n"

# case: (arguments, files {name: text}, the whole of stderr: one line)
ONE_LINE = {
    "generate_launch mapping misfit": (["generate_launch", "m.yaml", "--spec", "s.structuredslugs"],
                                       {"m.yaml": MISFIT, "s.structuredslugs": SPEC_OF.format("stop'")},
                                       "generate_launch: error: m.yaml:3: input 'nosuch' is not a proposition of the "
                                       "spec (its inputs: person) (and 1 more mapping errors)"),
    "analyze_graph mapping misfit": (["analyze_graph", "--spec", "s.structuredslugs", "--mapping", "m.yaml",
                                      "--snapshot", "snap.yaml"],
                                     {"m.yaml": MISFIT, "s.structuredslugs": SPEC_OF.format("stop'"),
                                      "snap.yaml": "nodes: [/p]\n"},
                                     "analyze_graph: error: m.yaml:3: input 'nosuch' is not a proposition of the "
                                     "spec (its inputs: person) (and 1 more mapping errors)"),
    "synthesize =>": (["synthesize", "s.structuredslugs"], {"s.structuredslugs": SPEC_OF.format("person' => stop'")},
                      "synthesize: error: s.structuredslugs:6:1: 'person' is a Boolean proposition; only integer "
                      "variables (name:lo...hi) can be compared or added; for 'implies' write '->' (not '=>')"),
    "synthesize = between propositions": (
        ["synthesize", "s.structuredslugs"], {"s.structuredslugs": SPEC_OF.format("stop' = person'")},
        "synthesize: error: s.structuredslugs:6:1: 'stop' is a Boolean proposition; only integer variables "
        "(name:lo...hi) can be compared or added; for 'if and only if' between propositions write '<->'"),
    "synthesize == between propositions": (
        ["synthesize", "s.structuredslugs"], {"s.structuredslugs": SPEC_OF.format("(stop == person)")},
        "synthesize: error: s.structuredslugs:6:2: 'stop' is a Boolean proposition; only integer variables "
        "(name:lo...hi) can be compared or added; for 'if and only if' between propositions write '<->'"),
}


@pytest.mark.parametrize("case", [pytest.param(c, marks=script_marks(ONE_LINE[c][0][0])) for c in ONE_LINE])
def test_every_error_is_exactly_one_line_on_stderr(case, tmp_path):
    args, files, line = ONE_LINE[case]
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    done = run(args, tmp_path)
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, done.stderr[-2000:])
    assert done.stderr.splitlines() == [line], done.stderr[-2000:]
