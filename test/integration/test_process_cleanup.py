"""Stopping a roslaunch stops its nodes, even when roslaunch itself has to be killed: roslaunch starts
each node in a session of its own, so a signal to roslaunch's process group does not reach them. And a
session started with SIGINT ignored (a background job of a script) does not pass that on."""
from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest
from helpers import REPO_ROOT, wait_for

from ltl_stack.sim.session import _running, descendants, stop_leftovers

pytestmark = pytest.mark.ros


def test_nodes_of_a_killed_roslaunch_are_stopped_too(ros_master):
    args = [str(REPO_ROOT / "launch" / "simple.launch"), "start_executor:=false"]
    nodes = subprocess.run(["roslaunch", "--nodes", *args], capture_output=True, text=True, check=True,
                           timeout=300).stdout.split()
    launch = ros_master.run(["roslaunch", *args], name="simple")
    try:
        # every node started (one process each), so none can start after the snapshot
        tree = wait_for(lambda: (t := descendants(launch.popen.pid)) and len(t) >= len(nodes) and t, 90,
                        f"roslaunch to start its {len(nodes)} nodes")
        os.killpg(launch.popen.pid, signal.SIGKILL)
        launch.popen.wait(60)
        # roslaunch is gone, its nodes are not: each runs in a session of its own
        assert _running(tree), "no node outlived roslaunch; the test shows nothing"
        stop_leftovers(tree, timeout=30)
        assert _running(tree) == []
    finally:
        launch.stop()


def test_a_session_started_with_sigint_ignored_starts_children_that_obey_it(tmp_path):
    code = ("from ltl_stack.sim.session import RosSession\n"
            "with RosSession() as ros:\n"
            "    ros.start(['sleep', '60'])\n"
            "    for proc in ros.processes:  # the master and the sleep\n"
            "        status = open(f'/proc/{proc.pid}/status').read().splitlines()\n"
            "        print(next(line.split()[1] for line in status if line.startswith('SigIgn:')))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=tmp_path,
                          preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    assert done.returncode == 0, done.stdout + done.stderr
    masks = [int(word, 16) for word in done.stdout.split()]
    assert len(masks) == 2, done.stdout
    assert all(not mask & (1 << (signal.SIGINT - 1)) for mask in masks), done.stdout


def test_a_session_stopped_with_sigterm_stops_its_processes(tmp_path):
    """``./tools/demo`` (or a test's ``terminate()``) ended by SIGTERM left roslaunch and its nodes running:
    they run in sessions of their own. The session now stops them on the way out, exit 128 + 15."""
    code = ("import sys, time\n"
            "from ltl_stack.sim.session import RosSession\n"
            "with RosSession() as ros:\n"
            "    child = ros.start(['sleep', '600'])\n"
            "    print(child.pid, flush=True)\n"
            "    time.sleep(600)\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        child = int(proc.stdout.readline())
        tree = [t for t in descendants(proc.pid) if t[0] == child]
        assert _running(tree), "the child never ran; the test shows nothing"
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(120) == 128 + signal.SIGTERM
        wait_for(lambda: not _running(tree), 60, "the session's child to be stopped")
    finally:
        proc.kill()
        proc.wait(60)
