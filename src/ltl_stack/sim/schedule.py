"""Schedules of scripted environment events, read from YAML. ROS-free.

A schedule file says what the environment does and when, so a scenario replays the same way every
time::

    loop: false          # optional (true or false); true replays the events every `period` seconds
    period: 10.0         # optional; default: the time of the last event; a loop's at least 0.01 s
    events:
      - at: 1.0                      # seconds after the start
        topic: /env/person           # where to publish (latched)
        value: true                  # a std_msgs/Bool unless `type` says otherwise
        name: a person shows up      # optional, for logs and the ~fired topic
      - at: 2.5
        topic: /env/object_distance
        type: std_msgs/Float64
        value: {data: 0.3}           # message fields, as for rostopic pub

Events at the same time fire in file order. A scalar ``value`` means ``{data: value}``.

An event with ``when:`` is timed from a moment the world decides instead of from the start: its
``at`` counts from the ``count``-th time (default 1) a message on the ``when`` topic changes to one
matching ``value`` (the fields given must be equal; a message that matches after one that did not, or
as the first message, is one time)::

      - when: {topic: inputs/bottomLane_rc, value: true, count: 2}   # the robot's second time there
        at: 0.5
        topic: camera/object_distance
        type: std_msgs/Float64
        value: 0.4

Triggered events fire once each (a looping schedule cannot have them).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ltl_stack.errors import InputError, UserError
from ltl_stack.inputs import construct_yaml, parse_yaml_node, read_text

DEFAULT_TYPE = "std_msgs/Bool"
#: the shortest period of a looping schedule: 1 ns or 1e-300 s would replay the whole schedule at
#: every check of the node (a core spinning); 10 ms is shorter than any scenario needs
MIN_LOOP_PERIOD = 0.01
#: missed cycles of a looping schedule replayed at once at most (older ones are skipped)
MAX_CATCH_UP = 100
#: the longest time in a schedule (18 digits, as every number a user gives)
MAX_SECONDS = 1e18
#: a legal ROS graph name, as rosgraph.names.is_legal_name checks it (this module stays ROS-free)
_TOPIC = re.compile(r"^[~/A-Za-z][\w/]*$")


class ScheduleError(UserError, ValueError):
    """A schedule file is wrong; the message names the file, the line and the event."""


@dataclass(frozen=True)
class Trigger:
    """The ``count``-th time a message on ``topic`` (of ``type``) changes to one matching ``fields``."""

    topic: str
    type: str
    fields: dict[str, Any]
    count: int = 1


@dataclass(frozen=True)
class Event:
    at: float
    topic: str
    type: str
    fields: dict[str, Any]
    name: str
    line: int = 0
    when: Trigger | None = None


@dataclass
class Schedule:
    events: list[Event]
    loop: bool = False
    period: float = 0.0
    source: str = "<schedule>"

    def topics(self) -> dict[str, str]:
        """{topic: message type} of every topic the schedule publishes on."""
        return {e.topic: e.type for e in self.events}

    def triggers(self) -> list[Trigger]:
        """The distinct ``when:`` conditions, in file order."""
        out: list[Trigger] = []
        for e in self.events:
            if e.when is not None and e.when not in out:
                out.append(e.when)
        return out


def matches(message: Any, fields: dict[str, Any]) -> bool:
    """True when every field given (nested dicts for nested messages) equals the message's."""
    for key, want in fields.items():
        got = message.get(key) if isinstance(message, dict) else getattr(message, key, None)
        if isinstance(want, dict):
            if got is None or not matches(got, want):
                return False
        elif got != want:
            return False
    return True


def _event_lines(root: yaml.Node | None) -> list[int]:
    """The line of each item of the ``events:`` list (empty when there is no such list)."""
    if isinstance(root, yaml.MappingNode):
        for key, value in root.value:
            if key.value == "events" and isinstance(value, yaml.SequenceNode):
                return [item.start_mark.line + 1 for item in value.value]
    return []


def _seconds(value: Any) -> float | None:
    """A non-negative number of seconds, or None. Accepts ``1e-3`` (YAML 1.1 reads it as text)."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        return None
    return number if 0 <= number < MAX_SECONDS else None  # also refuses nan and inf


def parse_schedule(text: str, source: str = "<schedule>") -> Schedule:
    """Read a schedule from YAML text; ScheduleError naming ``source``, line and event if wrong."""
    try:
        root = parse_yaml_node(text, source)
        data = construct_yaml(root, source)
    except InputError as error:  # invalid YAML, non-string keys, nesting, aliases, long integers
        raise ScheduleError(str(error)) from None
    if not isinstance(data, dict) or not isinstance(data.get("events"), list):
        raise ScheduleError(f"{source}: expected a mapping with an 'events:' list")
    unknown = set(data) - {"events", "loop", "period"}
    if unknown:
        raise ScheduleError(f"{source}: unknown key(s) {', '.join(sorted(unknown))} "
                            "(expected events, loop, period)")
    events: list[Event] = []
    types: dict[str, tuple[str, int]] = {}
    lines = _event_lines(root)
    for index, item in enumerate(data["events"]):
        line = lines[index] if index < len(lines) else 0
        where = f"{source}:{line}: event #{index}" if line else f"{source}: event #{index}"
        if not isinstance(item, dict):
            raise ScheduleError(f"{where}: expected a mapping with at, topic and value")
        extra = set(item) - {"at", "topic", "type", "value", "name", "when"}
        if extra:
            raise ScheduleError(f"{where}: unknown key(s) {', '.join(sorted(extra))}")
        for key in ("at", "topic", "value"):
            if key not in item:
                raise ScheduleError(f"{where}: missing '{key}'")
        at = _seconds(item["at"])
        if at is None:
            raise ScheduleError(f"{where}: 'at' must be a number of seconds >= 0, got {item['at']!r}")
        topic = _topic(item["topic"], where, "topic")
        msg_type = str(item.get("type", DEFAULT_TYPE))
        if topic in types and types[topic][0] != msg_type:
            raise ScheduleError(f"{where}: topic {topic} was given type {types[topic][0]} at line "
                                f"{types[topic][1]}, now {msg_type}")
        types.setdefault(topic, (msg_type, line))
        value = item["value"]
        fields = value if isinstance(value, dict) else {"data": value}
        name = str(item.get("name") or f"{topic} := {value}")
        when = _trigger(item["when"], where) if "when" in item else None
        events.append(Event(at, topic, msg_type, fields, name, line, when))
    events.sort(key=lambda e: e.at)  # stable: equal times keep file order
    loop = data.get("loop", False)
    if not isinstance(loop, bool):
        raise ScheduleError(f"{source}: 'loop' must be true or false (unquoted), got {loop!r}")
    if loop and any(e.when is not None for e in events):
        raise ScheduleError(f"{source}: 'loop: true' cannot replay events with 'when:'")
    timed = [e for e in events if e.when is None]
    period = _seconds(data.get("period", timed[-1].at if timed else 0.0))
    if period is None:
        raise ScheduleError(f"{source}: 'period' must be a number of seconds >= 0, got {data['period']!r}")
    if loop and (not events or period < MIN_LOOP_PERIOD):
        raise ScheduleError(f"{source}: 'loop: true' needs events and a period of at least {MIN_LOOP_PERIOD} s "
                            f"(got {period:g}); a shorter one would replay the events as fast as the node runs")
    if timed and period < timed[-1].at:
        raise ScheduleError(f"{source}: period {period} is shorter than the last event time {timed[-1].at}")
    return Schedule(events, loop, period, source)


def _topic(topic: Any, where: str, key: str) -> str:
    if not isinstance(topic, str) or not _TOPIC.match(topic) or "//" in topic:
        raise ScheduleError(f"{where}: '{key}' must be a ROS topic name (letters, digits, _ and /), "
                            f"got {topic!r}")
    return topic


def _trigger(when: Any, where: str) -> Trigger:
    """The ``when:`` mapping of an event: topic, value, optional type and count."""
    if not isinstance(when, dict):
        raise ScheduleError(f"{where}: 'when' must be a mapping with topic and value")
    extra = set(when) - {"topic", "type", "value", "count"}
    if extra:
        raise ScheduleError(f"{where}: unknown key(s) in 'when': {', '.join(sorted(extra))}")
    for key in ("topic", "value"):
        if key not in when:
            raise ScheduleError(f"{where}: 'when' is missing '{key}'")
    count = when.get("count", 1)
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 1_000_000:
        raise ScheduleError(f"{where}: 'when: count' must be a whole number from 1, got {count!r}")
    value = when["value"]
    return Trigger(_topic(when["topic"], where, "when: topic"), str(when.get("type", DEFAULT_TYPE)),
                   value if isinstance(value, dict) else {"data": value}, count)


def load_schedule(path: str | Path) -> Schedule:
    """Read a schedule file; ``ScheduleError`` naming file and line for anything wrong with it
    (also a missing, binary or non-UTF-8 file)."""
    try:
        text = read_text(path, "schedule")
    except InputError as error:
        raise ScheduleError(str(error)) from None
    return parse_schedule(text, str(path))


@dataclass
class Scheduler:
    """Hands out the events that are due as time passes (replaying them when the schedule loops);
    ``observe`` tells it the messages on the ``when:`` topics."""

    schedule: Schedule
    _next: int = 0
    _cycle: int = 0
    fired: list[Event] = field(default_factory=list)
    #: per trigger (index in ``schedule.triggers()``): times matched so far, last message matched, and
    #: the elapsed time it happened (None until the count is reached)
    _seen: list[int] = field(default_factory=list)
    _was: list[bool] = field(default_factory=list)
    _at: list[float | None] = field(default_factory=list)
    _waiting: list[Event] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._triggers = self.schedule.triggers()
        self._timed = [e for e in self.schedule.events if e.when is None]
        self._waiting = [e for e in self.schedule.events if e.when is not None]
        n = len(self._triggers)
        self._seen, self._was, self._at = [0] * n, [False] * n, [None] * n

    def observe(self, topic: str, message: Any, elapsed: float) -> list[Trigger]:
        """A message arrived on ``topic``; the triggers whose count it completes (now timed from
        ``elapsed``)."""
        done = []
        for i, trigger in enumerate(self._triggers):
            if trigger.topic != topic or self._at[i] is not None:
                continue
            now = matches(message, trigger.fields)
            if now and not self._was[i]:
                self._seen[i] += 1
                if self._seen[i] >= trigger.count:
                    self._at[i] = elapsed
                    done.append(trigger)
            self._was[i] = now
        return done

    def due(self, elapsed: float) -> list[Event]:
        """Events whose time has come by ``elapsed`` seconds after the start, in order, each once."""
        out = self._due_timed(elapsed)
        ready = []
        for event in self._waiting:
            start = self._at[self._triggers.index(event.when)]
            if start is not None and start + event.at <= elapsed:
                ready.append((start + event.at, event))
        if ready:
            self._waiting = [e for e in self._waiting if all(e is not r for _, r in ready)]
            ready.sort(key=lambda pair: pair[0])  # stable: file order for ties
            out += [event for _, event in ready]
            self.fired.extend(event for _, event in ready)
        return out

    def _due_timed(self, elapsed: float) -> list[Event]:
        out: list[Event] = []
        events = self._timed
        while events:
            if self._next >= len(events):
                if not self.schedule.loop:
                    break
                # a stalled node catches up at most MAX_CATCH_UP cycles; older ones (a long stall, a
                # large ~time_scale) are skipped rather than replayed one after another
                self._next = 0
                self._cycle = max(self._cycle + 1, int(elapsed // self.schedule.period) - MAX_CATCH_UP)
            event = events[self._next]
            if self._cycle * self.schedule.period + event.at > elapsed:
                break
            out.append(event)
            self._next += 1
        self.fired.extend(out)
        return out

    def finished(self) -> bool:
        return not self.schedule.loop and self._next >= len(self._timed) and not self._waiting
