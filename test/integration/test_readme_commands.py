"""The README's commands that need no master, and docs/chapter2.md's example commands, run as written
from a clone that has no ``../shared`` beside it (a new user's clone), and what they write and
read stays inside the package.

The clone is a folder of links to the repository's top-level entries, so ``../shared`` (relative to
where the commands run) does not exist. The commands that need a running master (``roslaunch``,
``controller_trace``, ``analyze_graph --live``) are the scenario tests' (test_analysis_scenarios,
test_install_space); ``./tools/demo --bag`` with ``check_run`` is test_scenarios'.
"""
from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys

import pytest
from helpers import REPO_ROOT, run_script

from ltl_stack.transfer.thesis_table import ROWS

pytestmark = pytest.mark.ros

MASTER_FREE = ("synthesize", "ros_code_transfer")


def readme_commands() -> list[list[str]]:
    """Every ``rosrun ltl_stack TOOL ...`` of the README's "Using it from your own shell" blocks
    (continuation lines joined, comments dropped)."""
    text = (REPO_ROOT / "README.md").read_text()
    section = text[text.index("## Using it from your own shell"):text.index("Resilient execution (thesis ch. 4")]
    commands = []
    for block in re.findall(r"```bash\n(.*?)```", section, re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.split(" #", 1)[0].strip()
            for part in line.split("&&"):
                words = shlex.split(part)
                if words[:2] == ["rosrun", "ltl_stack"]:
                    commands.append(words)
    return commands


def test_the_readme_names_files_that_exist_and_passes_what_the_tools_need():
    commands = readme_commands()
    tools = [c[2] for c in commands]
    assert set(MASTER_FREE) <= set(tools), tools
    for words in commands:
        for word in words[3:]:
            if "/" in word and not word.startswith(("/", "$")) and not word.endswith((".bag", ".py", ".dot")):
                assert (REPO_ROOT / word).exists(), f"{word} (README: {' '.join(words)})"
    transfer = next(c for c in commands if c[2] == "ros_code_transfer")
    assert (REPO_ROOT / transfer[3]).is_file() and "--robots" not in transfer  # the package's profiles


@pytest.mark.parametrize("tool", MASTER_FREE)
def test_readme_command_runs_from_a_clone_without_shared(tmp_path, tool):
    clone = tmp_path / "clone"
    clone.mkdir()
    for entry in REPO_ROOT.iterdir():
        if entry.name != ".git":
            (clone / entry.name).symlink_to(entry)
    assert not (clone.parent / "shared").exists()
    words = next(c for c in readme_commands() if c[2] == tool)
    done = run_script(words, cwd=clone, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "shared" not in done.stdout + done.stderr, done.stdout + done.stderr
    for word in words:
        if word.endswith((".py", ".dot")) and words[words.index(word) - 1] in ("-o", "--dot"):
            assert (clone / word).is_file() and (clone / word).stat().st_size > 0, word
    if tool == "ros_code_transfer":
        out = (clone / words[words.index("-o") + 1]).read_text()
        assert "cmd_vel_mux/input/navi" in out  # the channel the shipped TurtleBot statistics choose (A.1)


def chapter2_commands() -> list[list[str]]:
    """The commands of docs/chapter2.md: ``python -m ...`` in code blocks, ``ros_code_transfer ...`` in cells."""
    text = (REPO_ROOT / "docs" / "chapter2.md").read_text()
    commands = [shlex.split(line.split(" #", 1)[0]) for block in re.findall(r"```\n(.*?)```", text, re.S)
                for line in block.splitlines() if line.startswith("python -m ltl_stack")]
    return commands + [shlex.split(c) for c in re.findall(r"`(ros_code_transfer [^`]*)`", text)]


def test_chapter2_example_commands_run_from_a_clone_without_shared(tmp_path):
    """The package itself is copied (its code must not find ../shared beside it either); the rest linked."""
    clone = tmp_path / "clone"
    clone.mkdir()
    for entry in REPO_ROOT.iterdir():
        if entry.name == "src":
            shutil.copytree(entry, clone / "src", ignore=shutil.ignore_patterns("__pycache__"))
        elif entry.name != ".git":
            (clone / entry.name).symlink_to(entry)
    assert not (tmp_path / "shared").exists()
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(clone / "src"), os.environ.get("PYTHONPATH", "")]))
    where = subprocess.run([sys.executable, "-c", "import ltl_stack; print(ltl_stack.__file__)"], env=env,
                           capture_output=True, text=True, check=True).stdout
    assert where.startswith(str(clone / "src")), where
    commands = chapter2_commands()
    assert [c[:3] for c in commands if c[0] == "python"] == [["python", "-m", "ltl_stack.transfer.thesis_table"]]
    assert len([c for c in commands if c[0] == "ros_code_transfer"]) >= 2, commands
    for words in commands:
        if words[0] == "python":
            argv = [sys.executable, *words[1:]]
            answers = ""
        else:
            argv = [sys.executable, str(clone / "scripts" / "ros_code_transfer"), *words[1:]]
            target, program = words[words.index("--to") + 1], words[1].rsplit("/", 1)[-1]
            row = next(r for r in ROWS if (r.target, r.program) == (target, program))
            answers = "".join(a.split("=")[1] + "\n" for a in row.choose)   # the thesis' answers, typed
        done = subprocess.run(argv, cwd=clone, env=env, input=answers, capture_output=True, text=True,
                              timeout=300)
        assert done.returncode == 0, (words, done.stdout + done.stderr)
        assert "shared" not in done.stdout + done.stderr, (words, done.stderr)
        if "-o" in words:
            assert (clone / words[words.index("-o") + 1]).stat().st_size > 0, words
        else:
            assert done.stdout.count("\n| Example ") == 7, done.stdout  # the seven rows of Table 2.5
