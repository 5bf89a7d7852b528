"""Schedules of scripted environment events, read from YAML. ROS-free.

A schedule file says what the environment does and when, so a scenario replays the same way every
time::

    loop: false          # optional; true replays the events every `period` seconds
    period: 10.0         # optional; default: the time of the last event
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
#: a legal ROS graph name, as rosgraph.names.is_legal_name checks it (this module stays ROS-free)
_TOPIC = re.compile(r"^[~/A-Za-z][\w/]*$")


class ScheduleError(UserError, ValueError):
    """A schedule file is wrong; the message names the file, the line and the event."""


@dataclass(frozen=True)
class Event:
    at: float
    topic: str
    type: str
    fields: dict[str, Any]
    name: str
    line: int = 0


@dataclass
class Schedule:
    events: list[Event]
    loop: bool = False
    period: float = 0.0
    source: str = "<schedule>"

    def topics(self) -> dict[str, str]:
        """{topic: message type} of every topic the schedule publishes on."""
        return {e.topic: e.type for e in self.events}


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
    return number if number >= 0 and number == number and number != float("inf") else None


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
        extra = set(item) - {"at", "topic", "type", "value", "name"}
        if extra:
            raise ScheduleError(f"{where}: unknown key(s) {', '.join(sorted(extra))}")
        for key in ("at", "topic", "value"):
            if key not in item:
                raise ScheduleError(f"{where}: missing '{key}'")
        at = _seconds(item["at"])
        if at is None:
            raise ScheduleError(f"{where}: 'at' must be a number of seconds >= 0, got {item['at']!r}")
        topic = item["topic"]
        if not isinstance(topic, str) or not _TOPIC.match(topic) or "//" in topic:
            raise ScheduleError(f"{where}: 'topic' must be a ROS topic name (letters, digits, _ and /), "
                                f"got {topic!r}")
        msg_type = str(item.get("type", DEFAULT_TYPE))
        if topic in types and types[topic][0] != msg_type:
            raise ScheduleError(f"{where}: topic {topic} was given type {types[topic][0]} at line "
                                f"{types[topic][1]}, now {msg_type}")
        types.setdefault(topic, (msg_type, line))
        value = item["value"]
        fields = value if isinstance(value, dict) else {"data": value}
        name = str(item.get("name") or f"{topic} := {value}")
        events.append(Event(at, topic, msg_type, fields, name, line))
    events.sort(key=lambda e: e.at)  # stable: equal times keep file order
    loop = bool(data.get("loop", False))
    period = _seconds(data.get("period", events[-1].at if events else 0.0))
    if period is None:
        raise ScheduleError(f"{source}: 'period' must be a number of seconds >= 0, got {data['period']!r}")
    if loop and (not events or period <= 0):
        raise ScheduleError(f"{source}: 'loop: true' needs events and a positive period")
    if events and period < events[-1].at:
        raise ScheduleError(f"{source}: period {period} is shorter than the last event time {events[-1].at}")
    return Schedule(events, loop, period, source)


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
    """Hands out the events that are due as time passes (replaying them when the schedule loops)."""

    schedule: Schedule
    _next: int = 0
    _cycle: int = 0
    fired: list[Event] = field(default_factory=list)

    def due(self, elapsed: float) -> list[Event]:
        """Events whose time has come by ``elapsed`` seconds after the start, in order, each once."""
        out: list[Event] = []
        events = self.schedule.events
        while events:
            if self._next >= len(events):
                if not self.schedule.loop:
                    break
                self._next, self._cycle = 0, self._cycle + 1
            event = events[self._next]
            if self._cycle * self.schedule.period + event.at > elapsed:
                break
            out.append(event)
            self._next += 1
        self.fired.extend(out)
        return out

    def finished(self) -> bool:
        return not self.schedule.loop and self._next >= len(self.schedule.events)
