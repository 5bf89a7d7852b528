"""Every rate has an upper bound, through the real scripts against a real master.

A node's rate or frequency ``~param`` (and ``controller_executor --rate``, ``set_propositions
--rate``) above ``MAX_RATE`` (1000 Hz) is refused at start-up: one ``[FATAL]`` line naming the
parameter (a tool: one ``<tool>: error:`` line naming the option), exit 2. Before, ``_rate:=1e17``
started the node, which then spun a core. Every rate ``Param`` of the package is declared with a
rate bound (the source check below), so a new node cannot forget it.
"""
from __future__ import annotations

import ast
import subprocess
from pathlib import Path

import pytest
from helpers import REPO_ROOT, RosMaster, direct_script

from ltl_stack.errors import Exit

pytestmark = pytest.mark.ros

SIMPLE = REPO_ROOT / "config" / "simple"
TOO_FAST = "at most 1000 (Hz"

# case: (command after `rosrun ltl_stack`, expected text of the one [FATAL] line)
NODES = {
    "action_proposition ~rate": (["action_proposition", "_action:=/a", "_completion_topic:=/c", "_rate:=1e17"],
                                 f"parameter ~rate must be {TOO_FAST}"),
    "kitchen_world ~rate": (["kitchen_world", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "publish_on_edge ~rate": (["publish_on_edge", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "region_sensor ~rate": (["region_sensor", "_region:=left", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "scripted_environment ~rate": (["scripted_environment", "_schedule:=/nonexistent", "_rate:=1e17"],
                                   f"parameter ~rate must be {TOO_FAST}"),
    "set_color ~rate": (["set_color", "_topic:=/led", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "set_velocity ~rate": (["set_velocity", "_topic:=/cmd_vel", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "sim_manipulation_server ~feedback_rate": (["sim_manipulation_server", "_feedback_rate:=1e17"],
                                               f"parameter ~feedback_rate must be {TOO_FAST}"),
    "sim_navigation_server ~rate": (["sim_navigation_server", "_action:=/goto", "_rate:=1e17"],
                                    f"parameter ~rate must be {TOO_FAST}"),
    "sim_robot ~rate": (["sim_robot", "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "sim_robot ~rate 1001": (["sim_robot", "_rate:=1001"], f"parameter ~rate must be {TOO_FAST}"),
    "timed_proposition_server ~feedback_rate": (["timed_proposition_server", "_action:=/t", "_feedback_rate:=1e17"],
                                                f"parameter ~feedback_rate must be {TOO_FAST}"),
    "topic_threshold_sensor ~rate": (["topic_threshold_sensor", "_topic:=/x", "_type:=std_msgs/Float64",
                                      "_rate:=1e17"], f"parameter ~rate must be {TOO_FAST}"),
    "controller_executor ~rate": (["controller_executor", str(SIMPLE / "simple.structuredslugs"), "_rate:=1e17"],
                                  f"parameter ~rate must be {TOO_FAST}"),
    "controller_executor --rate": (["controller_executor", str(SIMPLE / "simple.structuredslugs"), "--rate", "2000"],
                                   f"--rate must be {TOO_FAST}"),
}

# case: (command, expected text of the one error line)
TOOLS = {
    "set_propositions --rate": (["set_propositions", "/x", "a=1", "--rate", "1e17"],
                                "argument --rate: '1e17' is above 1000 Hz"),
}


@pytest.fixture(scope="module")
def master(tmp_path_factory):
    ros = RosMaster(tmp_path_factory.mktemp("master"))
    try:
        yield ros
    finally:
        ros.shutdown()


def _run(master: RosMaster, folder: Path, command: list[str]) -> subprocess.CompletedProcess:
    # a node that takes the rate runs until killed: the timeout ends it (the test then fails)
    return subprocess.run(direct_script(["rosrun", "ltl_stack", *command], master.env), env=master.env,
                          capture_output=True, text=True, timeout=120, cwd=folder, stdin=subprocess.DEVNULL)


@pytest.mark.parametrize("case", list(NODES))
def test_a_node_refuses_a_rate_above_the_bound_in_one_fatal_line(master, tmp_path, case):
    command, message = NODES[case]
    done = _run(master, tmp_path, [*command, f"__name:=rate{list(NODES).index(case)}"])
    out = done.stdout + done.stderr
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, out[-2000:])
    fatal = [line for line in out.splitlines() if "[FATAL]" in line]
    assert len(fatal) == 1 and message in fatal[0], out[-2000:]
    assert "Traceback" not in out and list(tmp_path.iterdir()) == [], out[-3000:]


@pytest.mark.parametrize("case", list(TOOLS))
def test_a_tool_refuses_a_rate_above_the_bound_in_one_error_line(master, tmp_path, case):
    command, message = TOOLS[case]
    done = _run(master, tmp_path, command)
    assert done.returncode == Exit.BAD_INPUT, (done.returncode, done.stderr[-2000:])
    errors = [line for line in done.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1 and errors[0].startswith(f"{command[0]}: error: ") and message in errors[0], done.stderr
    assert "Traceback" not in done.stderr


def _rate_params() -> list[tuple[str, str, str]]:
    """(module, parameter, bound) of every ``Param`` of the package that is a rate: named ``*rate`` or
    documented in Hz or per second."""
    found = []
    for path in sorted((REPO_ROOT / "src" / "ltl_stack").rglob("*.py")):
        source = path.read_text()
        for node in ast.walk(ast.parse(source, str(path))):
            if not (isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Param" and node.args):
                continue
            name = node.args[0].value if isinstance(node.args[0], ast.Constant) else ""
            doc = ast.get_source_segment(source, node.args[2]) if len(node.args) > 2 else ""
            if str(name).endswith("rate") or "Hz" in doc or "per second" in doc:
                bound = next((ast.get_source_segment(source, k.value) for k in node.keywords if k.arg == "bound"),
                             "none")
                found.append((path.relative_to(REPO_ROOT).as_posix(), name, bound))
    return found


def test_every_rate_param_of_the_package_has_the_rate_bound():
    found = _rate_params()
    assert len(found) >= 9, found  # input and output proposition nodes share one each
    unbounded = [f for f in found if f[2] not in ("Bound.RATE", "Bound.RATE_OR_ZERO")]
    assert unbounded == [], unbounded
