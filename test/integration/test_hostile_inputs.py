"""Hostile and merely unusual input, third round, through the real scripts and nodes against a real
master: every row ends in one error line naming the file, line, parameter or proposition and the
exit code of the one table (a node: one ``[FATAL]`` line and exit 2), no traceback, and no file
created or changed.
"""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from helpers import (
    REPO_ROOT,
    RosMaster,
    assert_one_error_line,
    assert_one_fatal_line,
    direct_script,
    folder_files,
    run_case,
)

from ltl_stack.errors import Exit

pytestmark = pytest.mark.ros

SIMPLE = REPO_ROOT / "config" / "simple"
SPEC = str(SIMPLE / "simple.structuredslugs")
HALL = REPO_ROOT / "test" / "data" / "ltlmop"
PROGRAM = str(REPO_ROOT / "test" / "data" / "transfer" / "wander_turtlebot.py")
TURTLEBOT_LIMITS = (REPO_ROOT / "src" / "ltl_stack" / "transfer" / "robots" / "limits" / "turtlebot.yaml").read_bytes()
LONG = "7" * 5000


def _within(distance: str) -> bytes:
    """The hall project with one more sentence: ``visit within <distance> of dock``."""
    text = (HALL / "hall.spec").read_text()
    return text.replace("infinitely often not parcel", "infinitely often not parcel\n"
                        f"if you are sensing parcel then visit within {distance} of dock").encode()


def _state_bag(path: Path, keys_per_message: list[int]) -> None:
    """A bag of ControllerState messages whose inputs have the given numbers of keys (one value each)."""
    import rosbag
    import rospy

    from ltl_stack.msg import ControllerState

    with rosbag.Bag(str(path), "w") as bag:
        for i, keys in enumerate(keys_per_message):
            msg = ControllerState(state_id=i)
            msg.inputs.keys, msg.inputs.values = ["person", "x", "y"][:keys], [True]
            msg.outputs.keys, msg.outputs.values = ["move", "stop"], [True, False]
            msg.header.stamp = rospy.Time(1 + i)
            bag.write("/simple/controller_executor/state", msg, rospy.Time(1 + i))


MAPPING = (SIMPLE / "simple.yaml").read_bytes()
SCHEDULE = b"events:\n  - {at: 0.5, topic: /env/person, value: true}\n"

# case: (command after `rosrun ltl_stack`, files {name: bytes}, exit code, expected text of the one error line)
TOOLS = {
    "LTLMoP within 5000 digits": (["synthesize", "{d}/hall.spec"],
                                  {"hall.spec": _within(LONG), "hall.regions": (HALL / "hall.regions").read_bytes()},
                                  Exit.BAD_INPUT, "{d}/hall.spec:59:45: 'within N of dock': N has 5000 digits"),
    "transfer to a robot of nan limits": (["ros_code_transfer", "--from", "turtlebot", "--to", "nanlimits",
                                           "--robots", "{d}", "-o", "{d}/out.py", PROGRAM],
                                          {"nanlimits.yaml": b"limits: limits.yaml\n",
                                           "limits.yaml": b"linear:\n  x: {lower: .nan, upper: .inf}\n",
                                           "turtlebot.yaml": b"limits: turtlebot_limits.yaml\n",
                                           "turtlebot_limits.yaml": TURTLEBOT_LIMITS},
                                          Exit.BAD_INPUT, "{d}/limits.yaml: linear.x.lower: expected a finite number"),
    "transfer --to '*'": (["ros_code_transfer", "--from", "turtlebot", "--to", "*", "-o", "{d}/out.py", PROGRAM], {},
                          Exit.BAD_INPUT, "argument --to: '*' is not a robot name"),
    "transfer with a non-UTF-8 URDF not used": (["ros_code_transfer", "--from", "turtlebot", "--to", "nosuch",
                                                 "--robots", "{d}", "-o", "{d}/out.py", PROGRAM],
                                                {"turtlebot.yaml": b"drive: differential\n",
                                                 "urdf": "folder", "urdf/x.urdf": b"<robot name='\xff\xfe'/>\n"},
                                                Exit.BAD_INPUT, "no robot named 'nosuch'"),
    "English: an action sensed": (["synthesize", "{d}/e.spec"],
                                  {"e.spec": b"Sensors: person\nActions: move\n\nIf you are sensing move then do person.\n"},
                                  Exit.BAD_INPUT, "{d}/e.spec:4:20: 'move' is an action, not a sensor"),
    "English: a keyword declared": (["synthesize", "{d}/e.spec"], {"e.spec": b"Sensors: and\nActions: move\n\nAlways move.\n"},
                                    Exit.BAD_INPUT, "{d}/e.spec:1:10: 'and' is a word of the sentences"),
    "mapping negotiation of the wrong shape": (["controller_executor", SPEC, "{d}/m.yaml", "--check"],
                                               {"m.yaml": MAPPING + b"negotiation: [robot1]\n"}, Exit.BAD_INPUT,
                                               "{d}/m.yaml:31: negotiation: expected a mapping with robot:"),
    "characterized spec in an unwritable folder": (["controller_executor", SPEC, "--characterized-spec",
                                                    "/proc/self/learned.slugsin", "--check"], {}, Exit.BAD_INPUT,
                                                   "--characterized-spec '/proc/self/learned.slugsin': cannot write in "
                                                   "its folder /proc/self"),
    "check_run: more keys than values": (["check_run", SPEC, str(SIMPLE / "simple.yaml"), "{d}/run.bag"],
                                         {"run.bag": [1, 2, 1]}, Exit.BAD_INPUT,
                                         "{d}/run.bag: /simple/controller_executor/state: message 2: inputs has 2 "
                                         "keys but 1 values"),
    "controller_trace --bag: more keys than values": (["controller_trace", "--bag", "{d}/run.bag"],
                                                      {"run.bag": [1, 3]}, Exit.BAD_INPUT,
                                                      "{d}/run.bag: /simple/controller_executor/state: message 2: "
                                                      "inputs has 3 keys but 1 values"),
}

# case: (command after `rosrun ltl_stack`, files, expected text of the one [FATAL] line)
NODES = {
    "publish_on_edge on_true not a bool": (["publish_on_edge", "_topic:=/x", "_on_true:={data: notabool}"], {},
                                           "~on_true {'data': 'notabool'} does not fit std_msgs/Bool"),
    "publish_on_edge integer beyond XML-RPC": (["publish_on_edge", "_topic:=/x", "_type:=std_msgs/Int64",
                                                "_on_true:={data: 5000000000000}"], {},
                                               "parameter ~on_true: '5000000000000' is beyond a ROS parameter's"),
    "scripted_environment value of the wrong type": (["scripted_environment", "_schedule:={d}/env.yaml"],
                                                     {"env.yaml": SCHEDULE.replace(b"true", b"notabool")},
                                                     "{d}/env.yaml:2: value {'data': 'notabool'} does not fit "
                                                     "std_msgs/Bool"),
    "controller_executor characterized_spec a number": (["controller_executor", SPEC, "_characterized_spec:=5"], {},
                                                        "parameter ~characterized_spec must be a string, got the "
                                                        "number 5"),
    "controller_executor characterized_spec unwritable": (["controller_executor", SPEC,
                                                           "_characterized_spec:=/proc/self/learned.slugsin"], {},
                                                          "cannot write in its folder /proc/self"),
    "topic_predicate_sensor condition nested 1000 deep": (["topic_predicate_sensor", "_topic:=/t",
                                                           "_type:=std_msgs/Int8", "_conditions:=" + "[" * 1000], {},
                                                          "parameter ~conditions is nested more than 100 levels deep"),
    "move_base_region pose of booleans": (["move_base_region", f"_regions_file:={SIMPLE.parent}/clean_and_patrol/"
                                           "clean_and_patrol.regions", "_region:=topLane", "_pose:=[true, false]"], {},
                                          "must be [x, y] or [x, y, yaw] (finite numbers), not [True, False]"),
    "a parameter that is not UTF-8": (["sim_robot", "_frame_id:=\udcff"], {},
                                      "argument '_frame_id:=\\udcff' is not UTF-8 text"),
    "a remapping that is not UTF-8": (["set_velocity", "cmd_vel:=\udcff"], {},
                                      "argument 'cmd_vel:=\\udcff' is not UTF-8 text"),
}


@pytest.fixture(scope="module")
def master(tmp_path_factory):
    """One real master for the whole table (each case is a short-lived process)."""
    ros = RosMaster(tmp_path_factory.mktemp("master"))
    try:
        yield ros
    finally:
        ros.shutdown()


def _prepare(folder: Path, files: dict) -> dict[str, bytes | None]:
    """Folders and bags made here; the other files are written by ``run_case``."""
    plain = {}
    for name, data in files.items():
        if data == "folder":
            (folder / name).mkdir()
        elif isinstance(data, list):
            _state_bag(folder / name, data)
        else:
            plain[name] = data
    return plain


@pytest.mark.parametrize("case", list(TOOLS))
def test_a_tool_refuses_hostile_input_in_one_line(master, tmp_path, case):
    command, files, code, message = TOOLS[case]
    done, before = run_case(master, tmp_path, command, _prepare(tmp_path, files))
    assert_one_error_line(done, command[0], code, message.replace("{d}", str(tmp_path)))
    assert folder_files(tmp_path) == before


@pytest.mark.parametrize("case", list(NODES))
def test_a_node_refuses_a_hostile_parameter_with_one_fatal_line(master, tmp_path, case):
    command, files, message = NODES[case]
    name = f"__name:=hostile{list(NODES).index(case)}"  # the master keeps private parameters after a node
    done, before = run_case(master, tmp_path, [*command, name], _prepare(tmp_path, files))
    assert_one_fatal_line(done, message.replace("{d}", str(tmp_path)))
    assert folder_files(tmp_path) == before


def test_a_file_name_that_is_not_utf8_is_printed_back_as_its_bytes(master, tmp_path):
    """``PYTHONIOENCODING=utf-8`` makes stdout strict: printing the bag's name was a UnicodeEncodeError."""
    bag = os.fsdecode(b"run\xff.bag")
    _state_bag(tmp_path / bag, [1, 1])
    done = subprocess.run(direct_script(["rosrun", "ltl_stack", "check_run", SPEC, str(SIMPLE / "simple.yaml"), bag],
                                        master.env),
        env=dict(master.env, PYTHONIOENCODING="utf-8"), capture_output=True, timeout=300, cwd=tmp_path)
    assert done.returncode == Exit.OK, done.stderr[-2000:]
    assert done.stdout.startswith(b"run\xff.bag: /simple/controller_executor/state\n"), done.stdout[:200]
    assert b"Traceback" not in done.stderr, done.stderr[-2000:]
