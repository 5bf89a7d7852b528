"""Scripted environment schedules (ROS-free)."""
from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.sim.schedule import (
    MAX_CATCH_UP,
    Schedule,
    ScheduleError,
    Scheduler,
    load_schedule,
    parse_schedule,
)

TEXT = """
events:
  - at: 2.0
    topic: /env/person
    value: false
  - at: 0.5
    topic: /env/person
    value: true
    name: a person shows up
  - at: 0.5
    topic: /env/object_distance
    type: std_msgs/Float64
    value: {data: 0.3}
"""


def test_parse_sorts_by_time_keeping_file_order_for_ties():
    schedule = parse_schedule(TEXT, "s.yaml")
    got = [(e.at, e.topic, e.fields, e.name) for e in schedule.events]
    assert got == [
        (0.5, "/env/person", {"data": True}, "a person shows up"),
        (0.5, "/env/object_distance", {"data": 0.3}, "/env/object_distance := {'data': 0.3}"),
        (2.0, "/env/person", {"data": False}, "/env/person := False"),
    ], got
    assert schedule.topics() == {"/env/person": "std_msgs/Bool", "/env/object_distance": "std_msgs/Float64"}
    assert (schedule.loop, schedule.period) == (False, 2.0)


def test_scheduler_hands_out_due_events_once():
    scheduler = Scheduler(parse_schedule(TEXT))
    assert [e.at for e in scheduler.due(0.1)] == []
    assert [e.at for e in scheduler.due(0.6)] == [0.5, 0.5]
    assert [e.at for e in scheduler.due(0.7)] == []
    assert not scheduler.finished()
    assert [e.at for e in scheduler.due(5.0)] == [2.0]
    assert scheduler.finished()


def test_looping_schedule_replays_every_period():
    scheduler = Scheduler(parse_schedule("loop: true\nperiod: 3\nevents:\n- {at: 1, topic: a, value: 1}\n"))
    assert len(scheduler.due(0.5)) == 0
    assert len(scheduler.due(7.5)) == 3  # t = 1, 4, 7
    assert not scheduler.finished()


def test_a_looping_schedule_far_behind_catches_up_a_bounded_number_of_cycles():
    """A stall (or a huge ~time_scale) does not replay every missed cycle (1e14 of them here)."""
    scheduler = Scheduler(parse_schedule("loop: true\nperiod: 0.01\nevents:\n- {at: 0, topic: a, value: 1}\n"))
    assert len(scheduler.due(1e12)) <= MAX_CATCH_UP + 5  # a few more where float rounding lands
    assert len(scheduler.due(1e12 + 0.05)) <= 6 and not scheduler.finished()


@given(st.lists(st.floats(0, 100), min_size=1, max_size=20), st.lists(st.floats(0, 200), max_size=20))
def test_every_event_fires_once_in_time_order_whatever_the_polling(times, polls):
    events = "\n".join(f"- {{at: {t!r}, topic: /t{i}, value: true}}" for i, t in enumerate(times))
    scheduler = Scheduler(parse_schedule("events:\n" + events))
    for poll in sorted(polls):
        for event in scheduler.due(poll):
            assert event.at <= poll
    scheduler.due(1000.0)
    fired = [e.at for e in scheduler.fired]
    assert fired == sorted(times), fired


@pytest.mark.parametrize("text, message", [
    ("events: [", "s.yaml:2: invalid YAML"),
    ("events:\n  - {at: 1, topic: /a, value: 1}\n5: x\n", "s.yaml:3: key '5' is not a string"),
    ("events:\n  - {at: 1, topic: /a, value: {yes: 1}}\n", "s.yaml:2: key 'yes' is not a string"),
    ("~: 1\nevents: []\n", "s.yaml:1: key '~' is not a string"),
    ("events: " + "[" * 100000 + "\n", "s.yaml:1: nested more than 100 levels deep"),
    ("events:\n  - {at: " + "1" * 5000 + ", topic: /a, value: 1}\n", "s.yaml:2: integer of 5000 digits"),
    ("events:\n  - {at: 1" + "0" * 400 + ", topic: /a, value: 1}\n", "s.yaml:2: event #0: 'at' must be a number"),
    ("events:\n  - {at: 1, topic: 'bad topic!', value: 1}\n", "s.yaml:2: event #0: 'topic' must be a ROS topic"),
    ("[1, 2]", "s.yaml: expected a mapping with an 'events:' list"),
    ("events: []\nrepeat: true\n", "unknown key(s) repeat"),
    ("events:\n  - at: 1\n    topic: /a\n", "s.yaml:2: event #0: missing 'value'"),
    ("events:\n  - {at: -1, topic: /a, value: 1}\n", "s.yaml:2: event #0: 'at' must be a number of seconds >= 0"),
    ("events:\n  - {at: 1, topic: /a, value: 1, colour: red}\n", "event #0: unknown key(s) colour"),
    ("events:\n  - {at: 1, topic: /a, value: 1}\n  - {at: 2, topic: /a, type: std_msgs/Int32, value: 1}\n",
     "s.yaml:3: event #1: topic /a was given type std_msgs/Bool at line 2, now std_msgs/Int32"),
    ("loop: true\nevents: []\n", "'loop: true' needs events and a period of at least 0.01 s"),
    # a string is not a Boolean; a period that would spin a core; times of more than 18 digits
    ("loop: 'false'\nevents:\n  - {at: 1, topic: /a, value: 1}\n", "'loop' must be true or false (unquoted), got 'false'"),
    ("loop: 'no'\nevents:\n  - {at: 1, topic: /a, value: 1}\n", "'loop' must be true or false"),
    ("loop: 1\nevents:\n  - {at: 0, topic: /a, value: 1}\n", "'loop' must be true or false"),
    ("loop: true\nperiod: 1e-9\nevents:\n  - {at: 0, topic: /a, value: 1}\n", "a period of at least 0.01 s (got 1e-09)"),
    ("loop: true\nperiod: 1e-300\nevents:\n  - {at: 0, topic: /a, value: 1}\n", "a period of at least 0.01 s"),
    ("events:\n  - {at: 1e18, topic: /a, value: 1}\n", "s.yaml:2: event #0: 'at' must be a number of seconds"),
    ("period: 1\nevents:\n  - {at: 2, topic: /a, value: 1}\n", "period 1.0 is shorter than the last event time 2.0"),
])
def test_bad_schedules_give_one_clear_error(text, message):
    with pytest.raises(ScheduleError) as err:
        parse_schedule(text, "s.yaml")
    assert message in str(err.value), str(err.value)


def test_missing_file_names_it(tmp_path):
    with pytest.raises(ScheduleError, match="nothere.yaml: no such file"):
        load_schedule(tmp_path / "nothere.yaml")
    binary = tmp_path / "b.yaml"
    binary.write_bytes(b"events:\n  - {at: 1, topic: /caf\xe9, value: 1}\n")
    with pytest.raises(ScheduleError) as err:
        load_schedule(binary)
    assert str(err.value).startswith(f"{binary}:2: not a text schedule: not UTF-8"), err.value
    assert err.value.code == 2


def test_empty_schedule_is_finished_at_once():
    assert Scheduler(Schedule([])).finished()


TRIGGERED = """
events:
  - {at: 0.0, topic: /camera, type: std_msgs/Float64, value: 10.0}
  - when: {topic: /in_region, value: true, count: 2}
    at: 0.5
    topic: /camera
    type: std_msgs/Float64
    value: 0.4
    name: object
  - when: {topic: /pickup, value: true}
    at: 0.0
    topic: /camera
    type: std_msgs/Float64
    value: 10.0
    name: gone
"""


def test_when_events_are_timed_from_the_count_th_change_to_a_matching_message():
    scheduler = Scheduler(parse_schedule(TRIGGERED, "t.yaml"))
    assert [e.name for e in scheduler.due(0.0)] == ["/camera := 10.0"]
    assert not scheduler.finished()
    # a topic republished periodically: only changes to a matching message count
    for t, value in [(1.0, False), (2.0, True), (2.1, True), (2.2, True), (3.0, False), (4.0, False)]:
        assert scheduler.observe("/in_region", {"data": value}, t) == []
        assert scheduler.due(t + 0.6) == []
    assert [t.topic for t in scheduler.observe("/in_region", {"data": True}, 5.0)] == ["/in_region"]
    assert scheduler.due(5.4) == []
    assert [e.name for e in scheduler.due(5.5)] == ["object"]
    assert scheduler.observe("/in_region", {"data": False}, 6.0) == []
    assert scheduler.observe("/in_region", {"data": True}, 7.0) == []  # fired once; later times ignored
    assert scheduler.due(100.0) == [] and not scheduler.finished()
    assert scheduler.observe("/other", {"data": True}, 8.0) == []
    scheduler.observe("/pickup", {"data": True}, 9.0)
    assert [e.name for e in scheduler.due(9.0)] == ["gone"]
    assert scheduler.finished()


def test_when_value_compares_nested_fields_and_attributes():
    class Msg:
        def __init__(self, **kw):
            self.__dict__.update(kw)
    text = ("events:\n  - when: {topic: /odom, type: nav_msgs/Odometry, value: {header: {frame_id: map}}}\n"
            "    at: 1\n    topic: /a\n    value: true\n")
    scheduler = Scheduler(parse_schedule(text))
    assert scheduler.observe("/odom", Msg(header=Msg(frame_id="odom")), 0.0) == []
    assert len(scheduler.observe("/odom", Msg(header=Msg(frame_id="map")), 0.5)) == 1
    assert [e.topic for e in scheduler.due(1.5)] == ["/a"]


@pytest.mark.parametrize("when, message", [
    ("[a]", "'when' must be a mapping with topic and value"),
    ("{topic: /a}", "'when' is missing 'value'"),
    ("{value: 1}", "'when' is missing 'topic'"),
    ("{topic: /a, value: 1, count: 0}", "'when: count' must be a whole number from 1, got 0"),
    ("{topic: /a, value: 1, count: true}", "'when: count' must be a whole number from 1, got True"),
    ("{topic: 'a b', value: 1}", "'when: topic' must be a ROS topic name"),
    ("{topic: /a, value: 1, colour: red}", "unknown key(s) in 'when': colour"),
])
def test_bad_when_gives_one_clear_error_with_the_line(when, message):
    with pytest.raises(ScheduleError) as err:
        parse_schedule(f"events:\n  - {{at: 1, topic: /b, value: 1, when: {when}}}\n", "s.yaml")
    assert str(err.value).startswith("s.yaml:2: event #0: ") and message in str(err.value), str(err.value)


def test_a_looping_schedule_cannot_have_when_events():
    with pytest.raises(ScheduleError, match="cannot replay events with 'when:'"):
        parse_schedule("loop: true\nperiod: 2\nevents:\n  - {at: 1, topic: /b, value: 1, when: {topic: /a, value: 1}}\n")


@given(st.lists(st.booleans(), max_size=30), st.integers(1, 5), st.floats(0, 3))
def test_a_when_event_fires_once_at_the_count_th_rising_edge_plus_at(values, count, delay):
    """Whatever the messages, the event is due exactly from (time of the count-th change to true) + at."""
    text = (f"events:\n  - when: {{topic: /r, value: true, count: {count}}}\n"
            f"    at: {delay!r}\n    topic: /out\n    value: true\n")
    scheduler = Scheduler(parse_schedule(text))
    edges, before = [], False
    for t, value in enumerate(values):
        scheduler.observe("/r", {"data": value}, float(t))
        if value and not before:
            edges.append(float(t))
        before = value
    fired = scheduler.due(1000.0)
    if len(edges) >= count:
        start = edges[count - 1]
        assert len(fired) == 1 and scheduler.finished()
        late = Scheduler(parse_schedule(text))  # the same messages, polled just before and at the time
        for t, value in enumerate(values):
            late.observe("/r", {"data": value}, float(t))
        if delay > 1e-6:
            assert late.due(start + delay - 1e-6) == []
        assert len(late.due(start + delay)) == 1
    else:
        assert fired == [] and not scheduler.finished()
