"""Predicates over messages for detection sensors, ROS-free.

A detection (a fiducial tag, an object from a detector) arrives as a message, often an array of
elements. ``MessagePredicate`` says whether some element (or the message itself) meets every
condition, each written ``<field> <op> <value>``:

- ``id == 7``, ``label == cup``, ``confidence >= 0.8`` — the comparisons of ``topic_threshold_sensor``;
- ``pose.position within 1.5`` — the vector (x, y, z) at that field is at most 1.5 from the origin
  (the sensor's frame: the tag is closer than 1.5 m);
- ``ids contains 7`` — the array at that field holds the value.

Messages are read by attribute, so a genpy message or any object with the fields works.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import yaml

from ltl_stack.runtime.sensing import COMPARISONS, extract_field, parse_field_path

#: Operators beyond the comparisons.
VECTOR_OPS = ("within", "beyond")
OPS = (*COMPARISONS, *VECTOR_OPS, "contains")


@dataclass(frozen=True)
class Condition:
    """One ``<field> <op> <value>`` condition."""

    text: str
    steps: tuple[str | int, ...]
    op: str
    value: Any

    @classmethod
    def parse(cls, text: str) -> Condition:
        """ValueError naming the condition when it is not ``<field> <op> <value>``."""
        parts = str(text).split(None, 2)
        if len(parts) != 3 or parts[1] not in OPS:
            raise ValueError(f"condition {text!r} is not '<field> <op> <value>' with op one of {' '.join(OPS)}")
        field, op, raw = parts
        try:
            value = yaml.safe_load(raw)
        except yaml.YAMLError:
            value = raw
        if op in VECTOR_OPS and not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise ValueError(f"condition {text!r}: {op} needs a finite distance >= 0")
        return cls(str(text), tuple(parse_field_path(field)), op, value)

    def holds(self, element: Any) -> bool:
        """Does ``element`` meet the condition? LookupError when it lacks the field."""
        found = extract_field(element, list(self.steps))
        if self.op in VECTOR_OPS:
            norm = math.sqrt(sum(float(getattr(found, axis, 0.0)) ** 2 for axis in ("x", "y", "z")))
            return norm <= self.value if self.op == "within" else norm > self.value
        if self.op == "contains":
            return self.value in list(found)
        try:
            return bool(COMPARISONS[self.op](found, self.value))
        except TypeError:
            return False


class MessagePredicate:
    """True when an element of the array at ``array`` (or, without it, the message) meets every
    condition."""

    def __init__(self, conditions: Sequence[str], array: str = "") -> None:
        if not conditions:
            raise ValueError("give at least one condition")
        self.conditions = [Condition.parse(text) for text in conditions]
        self.array = tuple(parse_field_path(array)) if array.strip() else ()

    def elements(self, msg: Any) -> list[Any]:
        return list(extract_field(msg, list(self.array))) if self.array else [msg]

    def evaluate(self, msg: Any) -> bool:
        """LookupError naming the field when the message does not have it."""
        return any(all(c.holds(e) for c in self.conditions) for e in self.elements(msg))
