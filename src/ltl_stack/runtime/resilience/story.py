"""Scripted environments that react to the robot: the narratives of thesis Examples 10-12 (§4.10).

A *story* is what the environment and the user do in one example, written once in YAML and played
both in process (``ltl_stack.runtime.resilience.resilience_table``, through ``runtime.Controller`` and
``ResilientStrategy``) and on a real master (the ``story_environment`` node of a scenario launch)::

    regions: [company, road, storage]   # activation-completion (§4.5): output r = heading to r,
                                        # input r_c = in r
    inputs: {order: false, doorOpen: true, doorBroken: false}   # every other input, at the start
    pulse: [tap]                        # inputs a beat sets for one transition only
    stop: stop                          # optional output that keeps the robot where it is
    user: "doorOpen | doorBroken"       # the user's env liveness when the controller asks (Alg. 3)
    beats:                              # played in order, at most one per transition
      - name: Alice receives an order
        set: {order: true}
      - name: the order ends once Alice is in storage
        when: {at: storage}             # at / heading: a region; outputs: {name: bool}
        after: 2                        # at least 2 transitions after the previous beat
        set: {order: false}
      - name: done once Alice is back in company
        when: {at: company}

A *tick* is one controller transition: in process one step of the controller (with its settling),
on ROS one ``~state`` message of an executor stepping at a fixed ``--rate``. The story is
*complete* when every beat has fired; that is what "the mission completes" means in the §4.10.4
comparison. ROS-free.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from ltl_stack.errors import Exit, InputError, UserError
from ltl_stack.inputs import construct_yaml, parse_yaml_node, read_text
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import variables
from ltl_stack.spec.model import Spec
from ltl_stack.spec.structured import parse_structured

KEYS = {"regions", "inputs", "pulse", "stop", "user", "beats", "threshold", "notes"}
BEAT_KEYS = {"name", "when", "after", "set"}
WHEN_KEYS = {"at", "heading", "outputs"}


class StoryError(UserError):
    """A story file is wrong; the message names the file and the line."""

    def __init__(self, message: str) -> None:
        super().__init__(message, Exit.BAD_INPUT)


@dataclass(frozen=True)
class Beat:
    """One thing the environment does, once its condition holds."""

    name: str
    at: str | None = None
    heading: str | None = None
    outputs: Mapping[str, bool] = field(default_factory=dict)
    after: int = 0
    set: Mapping[str, bool] = field(default_factory=dict)
    line: int = 0


@dataclass(frozen=True)
class Story:
    regions: list[str]
    inputs: dict[str, bool]
    beats: list[Beat]
    pulse: list[str] = field(default_factory=list)
    stop: str | None = None
    user: str | None = None
    threshold: int | None = None  # the thesis' threshold in transitions (recovery + EC), if it gives one
    source: str = "<story>"

    def check(self, spec: Spec) -> None:
        """Every name the story uses must be a proposition of ``spec`` (StoryError naming it)."""
        where = f"{self.source}: against {spec.source}"
        for region in self.regions:
            if region not in spec.outputs or f"{region}_c" not in spec.inputs:
                raise StoryError(f"{where}: region {region!r} needs output {region} and input {region}_c")
        covered = {f"{r}_c" for r in self.regions} | set(self.inputs)
        missing = [n for n in spec.inputs if n not in covered]
        if missing:
            raise StoryError(f"{where}: inputs {', '.join(missing)} are neither regions nor in 'inputs:'")
        unknown = [n for n in self.inputs if n not in spec.inputs]
        if unknown:
            raise StoryError(f"{where}: 'inputs:' names {', '.join(unknown)}, not inputs of the spec")
        if self.stop is not None and self.stop not in spec.outputs:
            raise StoryError(f"{where}: 'stop: {self.stop}' is not an output of the spec")
        for beat in self.beats:
            for name in beat.outputs:
                if name not in spec.outputs:
                    raise StoryError(f"{self.source}:{beat.line}: beat {beat.name!r}: {name!r} is not an output")
        if self.user is not None:
            check_user_liveness(self.user, spec.inputs, spec.outputs, f"{where}: 'user'")


def check_user_liveness(text: str, inputs: list[str], outputs: list[str], where: str) -> None:
    """The user's env liveness (``user:``) must be one formula that parses over ``inputs`` and
    ``outputs`` and names at least one of them (Alg. 3 line 6 adds it as GF(text)); StoryError else."""
    if "\n" in text.strip() or "\r" in text:
        raise StoryError(f"{where}: must be one formula on one line")
    header = "[INPUT]\n" + "\n".join(inputs) + "\n[OUTPUT]\n" + "\n".join(outputs) + "\n[ENV_LIVENESS]\n"
    try:
        formula = parse_structured(header + text.strip() + "\n", "user").env_liveness[0].formula
    except (SpecError, IndexError) as err:
        detail = f"column {err.column}: {err.message}" if isinstance(err, SpecError) else "an empty formula"
        raise StoryError(f"{where}: {text!r} does not parse ({detail})") from None
    if not variables(formula):
        raise StoryError(f"{where}: {text!r} names no proposition (write one like: doorOpen | doorBroken)")


def _line(node: yaml.Node | None, key: str) -> dict[int, int]:
    """{index: line} of the items of the top-level list ``key``."""
    if isinstance(node, yaml.MappingNode):
        for k, v in node.value:
            if k.value == key and isinstance(v, yaml.SequenceNode):
                return {i: item.start_mark.line + 1 for i, item in enumerate(v.value)}
    return {}


def _bools(value: Any, where: str, what: str) -> dict[str, bool]:
    if value is None:
        return {}
    if not isinstance(value, dict) or not all(isinstance(v, bool) for v in value.values()):
        raise StoryError(f"{where}: '{what}' must map names to true/false, got {value!r}")
    return {str(k): v for k, v in value.items()}


def parse_story(text: str, source: str = "<story>") -> Story:
    """Read a story from YAML text; ``StoryError`` naming ``source`` and line for anything wrong."""
    try:
        root = parse_yaml_node(text, source)
        data = construct_yaml(root, source)
    except InputError as error:
        raise StoryError(str(error)) from None
    if not isinstance(data, dict) or not isinstance(data.get("beats"), list):
        raise StoryError(f"{source}: expected a mapping with a 'beats:' list")
    unknown = set(data) - KEYS
    if unknown:
        raise StoryError(f"{source}: unknown key(s) {', '.join(sorted(unknown))} (expected {', '.join(sorted(KEYS))})")
    regions = data.get("regions") or []
    if not isinstance(regions, list) or not all(isinstance(r, str) for r in regions):
        raise StoryError(f"{source}: 'regions' must be a list of region names")
    inputs = _bools(data.get("inputs"), source, "inputs")
    pulse = data.get("pulse") or []
    if not isinstance(pulse, list) or any(p not in inputs for p in pulse):
        raise StoryError(f"{source}: 'pulse' must list names given in 'inputs', got {pulse!r}")
    for key in ("stop", "user"):
        if data.get(key) is not None and not isinstance(data[key], str):
            raise StoryError(f"{source}: '{key}' must be a text, got {data[key]!r}")
    threshold = data.get("threshold")
    if threshold is not None and (isinstance(threshold, bool) or not isinstance(threshold, int) or threshold < 0):
        raise StoryError(f"{source}: 'threshold' must be a number of transitions >= 0, got {threshold!r}")
    lines = _line(root, "beats")
    beats = []
    for index, item in enumerate(data["beats"]):
        where = f"{source}:{lines.get(index, 0)}: beat #{index}"
        if not isinstance(item, dict) or not isinstance(item.get("name"), str):
            raise StoryError(f"{where}: expected a mapping with a 'name'")
        extra = set(item) - BEAT_KEYS
        if extra:
            raise StoryError(f"{where}: unknown key(s) {', '.join(sorted(extra))} (expected {', '.join(sorted(BEAT_KEYS))})")
        when = item.get("when") or {}
        if not isinstance(when, dict) or set(when) - WHEN_KEYS:
            raise StoryError(f"{where}: 'when' takes {', '.join(sorted(WHEN_KEYS))}, got {when!r}")
        for key in ("at", "heading"):
            if key in when and when[key] not in regions:
                raise StoryError(f"{where}: '{key}: {when[key]}' is not one of the regions {regions}")
        after = item.get("after", 0)
        if isinstance(after, bool) or not isinstance(after, int) or after < 0:
            raise StoryError(f"{where}: 'after' must be a number of transitions >= 0, got {after!r}")
        sets = _bools(item.get("set"), where, "set")
        strange = [n for n in sets if n not in inputs]
        if strange:
            raise StoryError(f"{where}: 'set' names {', '.join(strange)}, not in the story's 'inputs'")
        beats.append(Beat(item["name"], when.get("at"), when.get("heading"), _bools(when.get("outputs"), where,
                          "outputs"), after, sets, lines.get(index, 0)))
    if data.get("user") is not None:
        line = _key_line(root, "user")
        outputs = [*regions, *([data["stop"]] if data.get("stop") else [])]
        check_user_liveness(data["user"], [*inputs, *(f"{r}_c" for r in regions)], outputs,
                            f"{source}:{line}: 'user'" if line else f"{source}: 'user'")
    return Story(list(regions), inputs, beats, list(pulse), data.get("stop"), data.get("user"), threshold, source)


def _key_line(node: yaml.Node | None, key: str) -> int:
    """The line of the top-level ``key`` (0 when it is not there)."""
    if isinstance(node, yaml.MappingNode):
        for k, _ in node.value:
            if k.value == key:
                return k.start_mark.line + 1
    return 0


def load_story(path: str | Path) -> Story:
    """Read a story file (``StoryError`` for a missing, binary or wrong file)."""
    try:
        text = read_text(path, "story")
    except InputError as error:
        raise StoryError(str(error)) from None
    return parse_story(text, str(path))


def region_of(valuation: Mapping[str, bool], regions: list[str], suffix: str = "") -> str | None:
    """The one region whose proposition (``r`` + suffix) is true, else None."""
    found = [r for r in regions if valuation.get(r + suffix)]
    return found[0] if len(found) == 1 else None


@dataclass
class Fired:
    tick: int
    beat: Beat


class StoryPlayer:
    """Plays a story's beats against what the robot does (the same in process and on ROS).

    Call ``tick(at, outputs)`` once per controller transition with where the robot is and the
    controller's outputs; it fires the next beat when its condition holds and returns it. ``values``
    are the scripted inputs to present for the next transition; ``read()`` (after the controller
    has seen them) clears the pulses."""

    def __init__(self, story: Story) -> None:
        self.story = story
        self.values = dict(story.inputs)
        self.next = 0
        self.ticks = 0
        self.since = 0  # the tick of the last fired beat
        self.fired: list[Fired] = []
        self._pulsed: list[str] = []

    @property
    def complete(self) -> bool:
        return self.next >= len(self.story.beats)

    def due(self, at: str | None, outputs: Mapping[str, bool]) -> bool:
        """Whether the next beat's condition holds now."""
        if self.complete:
            return False
        beat = self.story.beats[self.next]
        heading = region_of(outputs, self.story.regions)
        return (self.ticks - self.since >= beat.after
                and (beat.at is None or beat.at == at)
                and (beat.heading is None or beat.heading == heading)
                and all(bool(outputs.get(k)) == v for k, v in beat.outputs.items()))

    def tick(self, at: str | None, outputs: Mapping[str, bool]) -> Beat | None:
        """One transition passed; fire the next beat if due (returns it)."""
        self.ticks += 1
        if not self.due(at, outputs):
            return None
        beat = self.story.beats[self.next]
        self.values.update(beat.set)
        self._pulsed = [p for p in self.story.pulse if beat.set.get(p)]
        self.next += 1
        self.since = self.ticks
        self.fired.append(Fired(self.ticks, beat))
        return beat

    def not_seen_yet(self, inputs: Mapping[str, bool]) -> None:
        """The controller stepped with ``inputs``: while they do not show the last beat's values yet (a
        message still on its way), that transition does not count towards the next beat's ``after``.
        In process the controller always steps with the current values, so this changes nothing there."""
        if not self.fired:
            return
        last = self.fired[-1].beat.set
        if any(name in inputs and bool(inputs[name]) != value for name, value in last.items()
               if name not in self.story.pulse or name in self._pulsed):
            self.since = self.ticks + 1

    def pending_pulses(self) -> list[str]:
        return list(self._pulsed)

    def read(self) -> None:
        """The controller has read the current values: pulses go back to false."""
        for name in self._pulsed:
            self.values[name] = False
        self._pulsed = []
