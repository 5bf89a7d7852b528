"""ROS-free parts of the proposition-node bases: edge detection, staleness, parameter coercion."""
from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.runtime.config.node_params import Bound, NodeConfigError, Param, coerce_param, describe_params
from ltl_stack.runtime.propositions.edges import FALLING, RISING, EdgeDetector, StaleWatch


def test_edges_of_a_hand_written_sequence():
    edges = EdgeDetector()
    got = [edges.update(v) for v in [False, True, True, False, False, True]]
    assert got == [None, RISING, None, FALLING, None, RISING], got


def test_stale_watch_fires_once_per_gap_and_clears_on_sensing():
    watch = StaleWatch(0.5, now=10.0)
    assert [watch.check(t) for t in (10.2, 10.49)] == [False, False]
    assert watch.check(10.5) is True and watch.stale
    assert watch.check(11.0) is False  # once per stale period
    assert watch.seen(11.2) is True and not watch.stale  # sensing ends the period
    assert watch.seen(11.3) is False
    assert [watch.check(t) for t in (11.7, 11.8)] == [False, True]


@given(st.lists(st.tuples(st.booleans(), st.floats(0, 1)), max_size=60), st.floats(0.05, 1))
def test_stale_exactly_when_the_last_sensing_is_older_than_the_limit(events, after):
    """Replay sensing/check events in time order: the watch is stale iff the last sensing (or the
    start) lies at least ``after`` back when checked, and it reports each stale period once."""
    now = 0.0
    watch = StaleWatch(after, now)
    last = now
    stale = False
    for is_sensing, dt in events:
        now += dt
        if is_sensing:
            assert watch.seen(now) is stale
            last, stale = now, False
        else:
            fired = watch.check(now)
            should = not stale and now - last >= after
            assert fired is should, (now, last, after)
            stale = stale or should
        assert watch.stale is stale


def test_stale_watch_disabled_by_zero():
    watch = StaleWatch(0.0, now=0.0)
    assert watch.check(1e9) is False and not watch.stale


@given(st.lists(st.booleans()))
def test_edges_alternate_and_track_the_value(values):
    edges = EdgeDetector()
    got = [e for e in (edges.update(v) for v in values) if e is not None]
    # Rising and falling alternate, starting with rising (the value starts false).
    assert all(e == (RISING if i % 2 == 0 else FALLING) for i, e in enumerate(got)), got
    assert edges.value == (values[-1] if values else False)
    assert len(got) == sum(1 for a, b in zip([False, *values], values) if a != b)


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


@pytest.mark.parametrize("param, raw, message", [
    (Param("rate", 10.0, bound=Bound.POSITIVE), 0, "~rate must be a number > 0, got 0.0"),
    (Param("rate", 10.0, bound=Bound.POSITIVE), -5, "~rate must be a number > 0"),
    (Param("rate", 10.0, bound=Bound.POSITIVE), "nan", "~rate must be a number > 0, got nan"),
    (Param("rate", 10.0, bound=Bound.NON_NEGATIVE), float("inf"), "~rate must be a number >= 0"),
    (Param("threshold", 0.0), float("-inf"), "~threshold must be a finite number"),
    (Param("delay", 1.0, bound=Bound.NON_NEGATIVE), -0.5, "~delay must be a number >= 0"),
    (Param("steps", 16, bound=Bound.NON_NEGATIVE), 2.5, "~steps must be an integer"),
    (Param("mode", "diff", choices=("diff", "holonomic")), "tank", "~mode must be one of diff, holonomic"),
    (Param("topic", "cmd_vel", ros_name=True), "cmd vel", "~topic must be a legal ROS name"),
    (Param("topic", "cmd_vel", ros_name=True), "see-person", "~topic must be a legal ROS name"),
    (Param("topic", "cmd_vel", ros_name=True, required=True), "", "~topic must be a legal ROS name"),
    (Param("actions", [], kind=list, ros_name=True), ["pick", "2drop"], "~actions must be a legal ROS name"),
    (Param("init", "", kind=(str, dict)), 5, "~init must be a str or dict"),
    (Param("flag", False), 2, "~flag must be a bool"),
    (Param("region", "", kind=str, required=True), None, "~region is required"),
])
def test_params_out_of_range_are_refused_naming_the_parameter(param, raw, message):
    with pytest.raises(NodeConfigError) as err:
        coerce_param(param, raw, "/node")
    assert message in str(err.value) and err.value.code == Exit.BAD_INPUT, str(err.value)


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_a_checked_positive_number_is_finite_and_positive(value):
    param = Param("rate", 1.0, bound=Bound.POSITIVE)
    try:
        got = coerce_param(param, value)
    except NodeConfigError:
        assert not (1e-9 <= value < 1e18), value  # at most 18 digits, not below ROS' nanoseconds
    else:
        assert 1e-9 <= got < 1e18 and got == value


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
    assert got["kind"] == "output" and names[:4] == ["proposition_topic", "rate", "deadman", "topic"], names
    assert {"vx", "vy", "vz", "ax", "ay", "az"} <= set(names)


def test_node_cli_without_options_returns_so_the_node_runs():
    from ltl_stack.ros.proposition_node import parse_node_cli

    assert parse_node_cli("n", "input", "d", [Param("x", 1.0)], []) is None


def test_the_pure_layers_of_the_nodes_import_without_ros():
    import subprocess
    import sys

    code = ("import sys\n"
            "for m in ('rospy', 'actionlib', 'genpy', 'roslib', 'rostopic', 'rosgraph'): sys.modules[m] = None\n"
            "import ltl_stack.runtime.config.node_params, ltl_stack.runtime.propositions.edges, ltl_stack.runtime.propositions.sensing\n"
            "import ltl_stack.runtime.executor.setup, ltl_stack.runtime.config.ros_names, ltl_stack.sim.kinematics\n"
            "import ltl_stack.sim.schedule\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
