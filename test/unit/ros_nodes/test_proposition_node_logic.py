"""ROS-free parts of the proposition-node bases: edge detection and parameter coercion."""
from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.ros.proposition_node import (
    FALLING,
    RISING,
    EdgeDetector,
    NodeConfigError,
    Param,
    coerce_param,
    describe_params,
)


def test_edges_of_a_hand_written_sequence():
    edges = EdgeDetector()
    got = [edges.update(v) for v in [False, True, True, False, False, True]]
    assert got == [None, RISING, None, FALLING, None, RISING], got


@given(st.lists(st.booleans()))
def test_edges_alternate_and_track_the_value(values):
    edges = EdgeDetector()
    got = [e for e in (edges.update(v) for v in values) if e is not None]
    # Rising and falling alternate, starting with rising (the value starts false).
    assert all(e == (RISING if i % 2 == 0 else FALLING) for i, e in enumerate(got)), got
    assert edges.value == (values[-1] if values else False)
    assert len(got) == sum(1 for a, b in zip([False, *values], values, strict=False) if a != b)


@pytest.mark.parametrize("param, raw, expected", [
    (Param("vx", 0.0), "0.5", 0.5),
    (Param("vx", 0.0), 35, 35.0),
    (Param("tag_no", 0), 3.0, 3),
    (Param("flag", False), "true", True),
    (Param("flag", False), 0, False),
    (Param("topic", "cmd_vel"), "/x", "/x"),
    (Param("region_list", [], kind=list), "a b c", ["a", "b", "c"]),
])
def test_coerce_param_accepts_mapping_style_values(param, raw, expected):
    got = coerce_param(param, raw)
    assert got == expected and type(got) is type(expected), got


@pytest.mark.parametrize("param, raw, message", [
    (Param("vx", 0.0), "fast", "~vx must be a number"),
    (Param("vx", 0.0), True, "~vx must be a number"),
    (Param("tag_no", 0), 1.5, "~tag_no must be an integer"),
    (Param("flag", False), "maybe", "~flag must be a bool"),
    (Param("goal", {}), "x", "~goal must be a dict"),
])
def test_coerce_param_rejects_wrong_values_naming_the_parameter(param, raw, message):
    with pytest.raises(NodeConfigError) as err:
        coerce_param(param, raw, "/node")
    assert str(err.value).startswith("/node: ") and message in str(err.value), str(err.value)


def test_describe_params_is_what_json_prints():
    got = describe_params("output", "d", [Param("vx", 0.0, "linear x", aliases=("v",))])
    assert got == {"kind": "output", "description": "d", "params": [
        {"name": "vx", "default": 0.0, "required": False, "aliases": ["v"], "doc": "linear x"}]}, got


def test_node_cli_json_prints_the_parameters_and_exits(capsys):
    import json

    from ltl_stack.ros.actuators import SET_VELOCITY
    from ltl_stack.ros.proposition_node import parse_node_cli

    with pytest.raises(SystemExit) as done:
        parse_node_cli("set_velocity", SET_VELOCITY.kind, SET_VELOCITY.description, SET_VELOCITY.params,
                       ["--json"])
    assert done.value.code == 0
    got = json.loads(capsys.readouterr().out)
    names = [p["name"] for p in got["params"]]
    assert got["kind"] == "output" and names[:3] == ["proposition_topic", "rate", "topic"], names
    assert {"vx", "vy", "vz", "ax", "ay", "az"} <= set(names)


def test_node_cli_without_options_returns_so_the_node_runs():
    from ltl_stack.ros.proposition_node import parse_node_cli

    assert parse_node_cli("n", "input", "d", [Param("x", 1.0)], []) is None


def test_node_modules_import_without_ros():
    import subprocess
    import sys

    code = ("import sys\n"
            "for m in ('rospy', 'actionlib', 'genpy', 'roslib', 'rostopic'): sys.modules[m] = None\n"
            "import ltl_stack.ros.proposition_node, ltl_stack.ros.sensors, ltl_stack.ros.regions\n"
            "import ltl_stack.ros.actuators, ltl_stack.ros.action_proposition, ltl_stack.sim.kinematics\n"
            "import ltl_stack.sim.schedule, ltl_stack.sim.robot, ltl_stack.sim.navigation\n"
            "import ltl_stack.sim.manipulation, ltl_stack.sim.environment\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
