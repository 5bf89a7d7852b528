"""The package's scripts and the repository's tools as a user runs them: ``rosrun`` from the devel space,
``./tools/test --help`` and ``./tools/demo --help``. (``--help`` of every script, with no master to
reach, is checked from the install space: test_install_space.py.)"""
from __future__ import annotations

import fcntl
import json
import os
import subprocess

from helpers import REPO_ROOT, bootstrap_paths, closed_port

from ltl_stack.spec import parse_slugsin
from ltl_stack.synthesis import synthesize

LOCK = (REPO_ROOT / "test" / "unit" / "runtime" / "lock.slugsin").read_text()


def no_master_env() -> dict[str, str]:
    """This environment with ROS_MASTER_URI at a closed port: a node that ignores --help and starts
    fails or hangs (and the subprocess timeout ends the test) instead of finding a master."""
    return dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{closed_port()}/")


def test_controller_executor_checks_a_saved_strategy_from_the_command_line(tmp_path):
    spec_file = tmp_path / "lock.slugsin"
    spec_file.write_text(LOCK)
    strategy = tmp_path / "lock.json"
    strategy.write_text(json.dumps(synthesize(parse_slugsin(LOCK, str(spec_file))).strategy.explicit().to_json()))
    proc = subprocess.run(["rosrun", "ltl_stack", "controller_executor", str(spec_file), "--check", "--json",
                           "--strategy", str(strategy), "--init-props", "a=0,lock=1"],
                          capture_output=True, text=True, timeout=300, env=no_master_env())
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["initial_state"]["outputs"] == {"out": False, "busy": True}, summary
    assert summary["inputs"] == {"a": "/lock/inputs/a", "lock": "/lock/inputs/lock"}, summary


def run_tool(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(REPO_ROOT / "tools" / args[0]), *args[1:]], capture_output=True, text=True,
                          timeout=600, env=no_master_env(), stdin=subprocess.DEVNULL, cwd="/")


def test_tools_test_help_says_what_it_runs_without_running_it():
    proc = run_tool("test", "--help")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.startswith("usage: ./tools/test [PYTEST ARGUMENTS...]"), proc.stdout
    assert "Every argument goes to pytest" in proc.stdout and "ruff" in proc.stdout, proc.stdout
    assert "[test]" not in proc.stderr, proc.stderr  # neither ruff nor pytest ran


def test_tools_demo_help_lists_the_demo_options():
    proc = run_tool("demo", "--help")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.startswith("usage:"), proc.stdout
    for option in ("--scenario", "--json", "--cycles", "--timeout"):
        assert option in proc.stdout, proc.stdout


def test_an_up_to_date_bootstrap_does_not_wait_for_another_shells_build():
    """tools/bootstrap.sh takes its lock only to build: while another shell builds (a second clone's
    first bootstrap), ``./tools/demo`` and the tests of an up-to-date clone still start."""
    with open(bootstrap_paths()["home"] / ".bootstrap.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # held by this process, released when the file is closed
        proc = subprocess.run(["bash", str(REPO_ROOT / "tools" / "bootstrap.sh")], capture_output=True, text=True,
                              timeout=300, stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stderr
    assert "waiting" not in proc.stderr, proc.stderr
