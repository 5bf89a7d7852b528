"""Stale inputs: freshness bounds from the mapping, and the controller with unknown inputs (the
cmd_vel story of a partition: a person may appear while the sensor's host is cut off)."""
from __future__ import annotations

import pytest

from ltl_stack.runtime.config.mapping import MappingError, parse_mapping
from ltl_stack.runtime.executor.freshness import (
    MIN_BOUND,
    Freshness,
    bound_for_rate,
    freshness_bounds,
    unknown_text,
)
from ltl_stack.runtime.executor.node_reports import ERROR, OK, WARN, NodeReports
from ltl_stack.runtime.executor.setup import build_strategy, make_controller, merge_options
from ltl_stack.spec import parse_structured

MAPPING = """\
inputs:
  person:
    node: /r/inputs/person
    node_publish_topic: /r/inputs/person
    type: topic_threshold_sensor
    parameters: {rate: 20}
  door:
    node: /r/inputs/door
    node_publish_topic: /r/inputs/door
    type: topic_threshold_sensor
  light:
    node_publish_topic: /r/inputs/light
    type: my_own_sensor
  quiet:
    node_publish_topic: /r/inputs/quiet
    type: region_sensor
    parameters: {rate: 0}
  hand:
    node_publish_topic: /r/inputs/hand
    type: topic_threshold_sensor
    freshness: 0.5
outputs:
  move:
    node_subscribe_topic: /r/outputs/move
"""


def test_bounds_come_from_the_mapping_then_the_node_rate_then_the_default():
    mapping = parse_mapping(MAPPING, "m.yaml")
    bounds = freshness_bounds(mapping, ["person", "door", "light", "quiet", "hand", "other"], default=3.0)
    assert bounds == {"person": MIN_BOUND, "door": bound_for_rate(10.0), "light": 3.0, "quiet": 0.0,
                      "hand": 0.5, "other": 3.0}
    assert bound_for_rate(1.0) == 5.0 and bound_for_rate(0) == 0.0
    assert freshness_bounds(None, ["a"]) == {"a": 0.0}  # no mapping, no --freshness: never stale


@pytest.mark.parametrize("value", ["-1", "soon", "true", ".inf"])
def test_a_bad_freshness_names_file_line_and_proposition(value):
    text = MAPPING.replace("freshness: 0.5", f"freshness: {value}")
    with pytest.raises(MappingError) as err:
        parse_mapping(text, "m.yaml")
    assert str(err.value).startswith("m.yaml:21: input 'hand': freshness must be")


def test_freshness_is_for_inputs_only():
    with pytest.raises(MappingError, match="m.yaml:25: output 'move': freshness is for inputs"):
        parse_mapping(MAPPING + "    freshness: 1\n", "m.yaml")


def test_stale_inputs_are_those_older_than_their_bound():
    fresh = Freshness({"a": 1.0, "b": 0.0, "c": 2.0})
    assert fresh.active and fresh.check_period() == 0.25
    fresh.seen("a", 10.0)
    fresh.seen("b", 10.0)
    assert fresh.stale(10.9) == []
    assert fresh.stale(11.5) == ["a"]  # b: never stale; c: never reported (the ready handshake's)
    fresh.seen("a", 11.6)
    assert fresh.stale(12.0) == []
    assert "a (/t/a, no message for 2.4 s > 1.0 s)" in unknown_text(["a"], {"a": "/t/a"}, fresh, 14.0)
    assert not Freshness({"a": 0.0}).active


CMD_VEL = """[INPUT]
person
[OUTPUT]
move
stop
[SYS_INIT]
move
!stop
[ENV_INIT]
!person
[SYS_TRANS]
move' <-> !person'
stop' <-> person'
"""
BRAKE = """[INPUT]
person
other
[OUTPUT]
go
brake
[SYS_TRANS]
person' -> !go'
go -> go' | brake'
[ENV_LIVENESS]
!person
[SYS_LIVENESS]
go
"""


def controller_of(text: str, **options):
    spec = parse_structured(text, "s.structuredslugs")
    opts = merge_options(options)
    return make_controller(build_strategy(spec, opts, log=lambda _t: None), opts, {})


def test_a_partition_the_sensor_goes_stale_every_output_false_with_an_error_then_resumes():
    controller = controller_of(CMD_VEL)
    reports = NodeReports(controller, "hold", True, {"person": "/r/inputs/person"}, 10.0)
    assert controller.report("person", False).outputs == {"move": True, "stop": False}
    state = controller.state
    update = controller.set_unknown(["person"])  # no output keeps rho_s for both values of person
    assert update.outputs == {"move": False, "stop": False} and update.unkeepable
    assert update.unknown == ["person"] and reports.current_mode() == "inputs_unknown"
    status = reports.unknown_report(update, "person (/r/inputs/person, no message for 3.0 s > 2.0 s)")
    assert status.level == ERROR and "s.structuredslugs:12: move' <-> !person'" in status.message
    assert reports.mode_report().status.level == ERROR
    assert controller.report("person", True).outputs == {"move": False, "stop": False}  # not stepped on it
    assert controller.state is state
    resumed = controller.set_unknown([])  # the message that made it fresh carried person = true
    assert resumed.stepped and resumed.outputs == {"move": False, "stop": True} and resumed.unknown == []
    assert reports.current_mode() != "inputs_unknown"
    assert reports.unknown_report(resumed, "").level == OK


def test_unknown_inputs_keep_the_outputs_nearest_to_those_published_that_are_safe_for_every_value():
    controller = controller_of(BRAKE, recovery=False)
    reports = NodeReports(controller, "hold", False, {"person": "/p", "other": "/o"}, 10.0)
    controller.report_many({"person": False, "other": False})
    controller.report_many({"person": False, "other": True})
    assert controller.current_outputs()["go"]
    update = controller.set_unknown(["person"])
    # person may be true: go must be false; go was published, so brake must be true (go -> go' | brake')
    assert update.outputs == {"go": False, "brake": True} and not update.unkeepable
    assert reports.unknown_report(update, "person").level == WARN
    assert controller.report("other", False).unknown == ["person"]  # a known input: still not stepping


def test_a_node_owning_several_inputs_has_a_valuation_topic():
    from ltl_stack.runtime.config.mapping import valuation_topics

    mapping = parse_mapping("""\
inputs:
  a_rc: {node: localization, node_publish_topic: a_rc, type: region_localization}
  b_rc: {node: localization, node_publish_topic: b_rc}
  c_rc: {node: /abs/loc, node_publish_topic: c_rc}
  person: {node: person_sensor, node_publish_topic: person}
outputs: {}
""", "m.yaml")
    assert valuation_topics(mapping, ["a_rc", "b_rc", "c_rc", "person"], "kitchen") == {
        "/kitchen/localization/valuation": ["a_rc", "b_rc"]}
    assert valuation_topics(None, ["a_rc"], "kitchen") == {}


PEER = """[INPUT]
peer_in_hall
door_open
[OUTPUT]
enter
wait
[SYS_INIT]
!enter
[SYS_TRANS]
peer_in_hall' -> !enter'
wait' <-> !enter'
enter' -> door_open'
[ENV_LIVENESS]
!peer_in_hall & door_open
[SYS_LIVENESS]
enter
"""


def test_an_input_never_heard_of_is_unknown_only_when_passed_as_no_longer_waited_for():
    fresh = Freshness({"a": 1.0, "b": 0.0, "c": 2.0})
    assert fresh.stale(5.0) == []  # c never reported: the start waits for it
    assert fresh.stale(5.0, unheard=["b", "c"]) == ["c"]  # b has no bound: it goes on holding the start
    fresh.seen("c", 5.0)
    assert fresh.stale(5.5, unheard=["c"]) == []
    assert "c (/t/c, no message yet)" in unknown_text(["c"], {"c": "/t/c"}, Freshness({"c": 2.0}), 1.0)


def test_a_robot_starts_while_its_peer_is_silent_with_outputs_safe_for_every_value_then_runs_when_it_reports():
    controller = controller_of(PEER)
    reports = NodeReports(controller, "hold", True, {"peer_in_hall": "/peer/in_hall", "door_open": "/me/door"}, 10.0)
    controller.report("door_open", True)
    assert controller.missing_inputs() == ["peer_in_hall"]
    update = controller.set_unknown(["peer_in_hall"])
    # the peer may be in the hall: never enter; wait' <-> !enter' then asks for wait (not all false)
    assert update.outputs == {"enter": False, "wait": True} and not update.unkeepable and not update.started
    assert reports.current_mode() == "inputs_unknown"
    status = reports.unknown_report(update, "peer_in_hall (/peer/in_hall, no message yet)")
    assert status.level == WARN and "not starting until they report" in status.message
    assert reports.silent_inputs(10.0) is None  # the ready handshake no longer holds it: it is unknown
    assert [s.level for s in reports.health(10.0)] == [WARN, WARN]
    assert controller.report("door_open", False).outputs == {"enter": False, "wait": True}  # nothing started
    assert controller.state is None
    controller.report("peer_in_hall", False)
    started = controller.set_unknown([])  # it reported: start, from the outputs the robot already has
    assert started.started and controller.state is not None and started.unknown == []
    assert controller.state.outputs == {"enter": False, "wait": True}
    assert reports.unknown_report(started, "").message.startswith("every input has reported; started in state")
    controller.report("door_open", True)
    assert controller.current_outputs()["enter"]  # running normally


def test_a_silent_peer_with_no_output_safe_for_every_value_keeps_every_output_false_with_the_clauses():
    controller = controller_of(CMD_VEL)
    update = controller.set_unknown(["person"])
    assert update.outputs == {"move": False, "stop": False}
    assert {c.text for c in update.unkeepable} == {"move' <-> !person'", "stop' <-> person'"}
    reports = NodeReports(controller, "hold", True, {"person": "/r/inputs/person"}, 10.0)
    status = reports.unknown_report(update, "person")  # not started: every output was false already
    assert status.level == WARN and "no output valuation keeps the system safety" in status.message
    assert reports.mode_report().status.level == WARN
    controller.report("person", False)
    assert controller.set_unknown([]).outputs == {"move": True, "stop": False}
