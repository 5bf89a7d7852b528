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

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

DEFAULT_TYPE = "std_msgs/Bool"


class ScheduleError(ValueError):
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


class _LineLoader(yaml.SafeLoader):
    """A SafeLoader that records each mapping's line number under the key ``__line__``."""


def _construct_mapping(loader: _LineLoader, node: yaml.MappingNode) -> dict:
    mapping = loader.construct_mapping(node, deep=True)
    mapping["__line__"] = node.start_mark.line + 1
    return mapping


_LineLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def _strip_lines(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _strip_lines(v) for k, v in value.items() if k != "__line__"}
    if isinstance(value, list):
        return [_strip_lines(v) for v in value]
    return value


def _seconds(value: Any) -> float | None:
    """A non-negative number of seconds, or None. Accepts ``1e-3`` (YAML 1.1 reads it as text)."""
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if number >= 0 and number == number and number != float("inf") else None


def parse_schedule(text: str, source: str = "<schedule>") -> Schedule:
    """Read a schedule from YAML text; ScheduleError naming ``source``, line and event if wrong."""
    try:
        data = yaml.load(text, Loader=_LineLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark else source
        raise ScheduleError(f"{where}: not valid YAML: {getattr(error, 'problem', error)}") from None
    if not isinstance(data, dict) or not isinstance(data.get("events"), list):
        raise ScheduleError(f"{source}: expected a mapping with an 'events:' list")
    unknown = set(data) - {"events", "loop", "period", "__line__"}
    if unknown:
        raise ScheduleError(f"{source}: unknown key(s) {', '.join(sorted(unknown))} "
                            "(expected events, loop, period)")
    events: list[Event] = []
    types: dict[str, tuple[str, int]] = {}
    for index, item in enumerate(data["events"]):
        line = item.get("__line__", 0) if isinstance(item, dict) else 0
        where = f"{source}:{line}: event #{index}" if line else f"{source}: event #{index}"
        if not isinstance(item, dict):
            raise ScheduleError(f"{where}: expected a mapping with at, topic and value")
        extra = set(item) - {"at", "topic", "type", "value", "name", "__line__"}
        if extra:
            raise ScheduleError(f"{where}: unknown key(s) {', '.join(sorted(extra))}")
        for key in ("at", "topic", "value"):
            if key not in item:
                raise ScheduleError(f"{where}: missing '{key}'")
        at = _seconds(item["at"])
        if at is None:
            raise ScheduleError(f"{where}: 'at' must be a number of seconds >= 0, got {item['at']!r}")
        topic = item["topic"]
        if not isinstance(topic, str) or not topic.strip():
            raise ScheduleError(f"{where}: 'topic' must be a topic name")
        msg_type = str(item.get("type", DEFAULT_TYPE))
        if topic in types and types[topic][0] != msg_type:
            raise ScheduleError(f"{where}: topic {topic} was given type {types[topic][0]} at line "
                                f"{types[topic][1]}, now {msg_type}")
        types.setdefault(topic, (msg_type, line))
        value = _strip_lines(item["value"])
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
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as error:
        raise ScheduleError(f"{path}: cannot read schedule: {error.strerror}") from None
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
