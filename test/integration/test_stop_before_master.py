"""A node stopped while it waits for a ROS master that is not there (Ctrl-C, or roslaunch's SIGTERM):
rospy raised ``ROSInitException`` with a traceback; now one ``<node>: error:`` line naming the master,
exit 130 (never a traceback for an environment condition). No master runs: the master URI
names a loopback port bound by this test session and never listened on."""
from __future__ import annotations

import os
import signal
import subprocess
import time

import pytest
from helpers import REPO_ROOT, closed_port, direct_script

from ltl_stack.errors import Exit

SIMPLE = REPO_ROOT / "config" / "simple" / "simple.structuredslugs"
WAITING = "Unable to register with master node"  # rospy's own line (on stdout) once its first attempt failed
NODES = {
    "controller_executor": ["controller_executor", str(SIMPLE)],
    "region_sensor": ["region_sensor"],
}


def master_env(tmp_path) -> tuple[str, dict[str, str]]:
    uri = f"http://127.0.0.1:{closed_port()}/"
    return uri, dict(os.environ, ROS_MASTER_URI=uri, ROS_LOG_DIR=str(tmp_path))


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("node", list(NODES))
def test_a_node_stopped_while_waiting_for_the_master_says_so_in_one_line(node, sig, tmp_path):
    uri, env = master_env(tmp_path)
    out, err = tmp_path / "stdout.txt", tmp_path / "stderr.txt"
    with out.open("w") as stdout, err.open("w") as stderr:
        proc = subprocess.Popen(direct_script(["rosrun", "ltl_stack", *NODES[node]], env), env=env, cwd=tmp_path,
                                stdin=subprocess.DEVNULL, stdout=stdout, stderr=stderr)
        try:
            deadline = time.monotonic() + 120
            while WAITING not in out.read_text() and proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.1)
            assert proc.poll() is None and WAITING in out.read_text(), (out.read_text() + err.read_text())[-2000:]
            proc.send_signal(sig)
            code = proc.wait(60)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    text = err.read_text()
    assert "Traceback" not in text + out.read_text(), text[-3000:]
    errors = [line for line in text.splitlines() if "error:" in line]
    assert errors == [f"{node}: error: stopped while waiting for the ROS master at {uri}"], text[-2000:]
    assert code == Exit.INTERRUPTED


@pytest.mark.parametrize("node, args", [("region_sensor", ["_region:=left"]),
                                        ("controller_executor", [str(SIMPLE), "_rate:=2"])])
def test_a_node_with_parameters_and_no_master_says_so_in_one_line(node, args, tmp_path):
    """rospy puts ``_param:=`` arguments on the master before waiting for it: with none there it failed at
    once with ConnectionRefusedError's traceback."""
    uri, env = master_env(tmp_path)
    done = subprocess.run(direct_script(["rosrun", "ltl_stack", node, *args], env), env=env, cwd=tmp_path,
                          stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    assert "Traceback" not in done.stderr + done.stdout, done.stderr[-3000:]
    errors = [line for line in done.stderr.splitlines() if "error:" in line]
    assert errors == [f"{node}: error: no ROS master at {uri} (Connection refused)"], done.stderr[-2000:]
    assert done.returncode == Exit.NO_ROS
