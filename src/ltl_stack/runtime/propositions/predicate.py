"""Predicates over messages for detection sensors, ROS-free.

A detection (a fiducial tag, an object from a detector) arrives as a message, often an array of
elements. ``MessagePredicate`` says whether some element (or the message itself) meets every
condition, each written ``<field> <op> <value>``:

- ``id == 7``, ``label == cup``, ``confidence >= 0.8`` — the comparisons of ``topic_threshold_sensor``;
- ``pose.position within 1.5`` — the vector (x, y, z) at that field is at most 1.5 from the origin
  (the sensor's frame: the tag is closer than 1.5 m);
- ``ids contains 7`` — the array at that field holds the value.

Messages are read by attribute, so a genpy message or any object with the fields works.

Each condition is checked against the message definition before any message arrives
(``Condition.type_error`` with the ROS type of its field, e.g. ``geometry_msgs/Point``, ``int32[]``):
``within``/``beyond`` need a vector with numeric x, y and z (a Point or Vector3, not a Pose),
``contains`` an array, a comparison a number, a bool or a string (compared with a value of the same
kind). A condition that cannot be evaluated on one message (``detections[0].id == 7`` while the list
is empty) does not hold: the sensor never reports what it cannot know.
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ltl_stack.errors import InputError
from ltl_stack.inputs import parse_yaml
from ltl_stack.runtime.config.node_params import shown
from ltl_stack.runtime.propositions.sensing import COMPARISONS, extract_field, parse_field_path

#: Operators beyond the comparisons.
VECTOR_OPS = ("within", "beyond")
OPS = (*COMPARISONS, *VECTOR_OPS, "contains")
#: ROS primitive types a comparison may read, by the kind of value they hold
NUMBER_TYPES = frozenset({"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
                          "float32", "float64", "byte", "char"})
TEXT_TYPES = frozenset({"string"})
BOOL_TYPES = frozenset({"bool"})
VECTOR_AXES = ("x", "y", "z")


class Unknown(LookupError):
    """The message has no element at an index the condition reads (an empty or short array): the
    condition does not hold on that message."""


def is_array(type_name: str) -> bool:
    """``int32[]``, ``float64[3]``, ``pkg/Type[]``."""
    return type_name.endswith("]")


def element_type(type_name: str) -> str:
    """The type of an array's elements (``int32[]`` -> ``int32``)."""
    return type_name.split("[", 1)[0]


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
            raise ValueError(f"condition {shown(text)} is not '<field> <op> <value>' with op one of {' '.join(OPS)}")
        field, op, raw = parts
        try:
            value = parse_yaml(raw, "its value")
        except InputError as err:
            if "invalid YAML" not in str(err):  # nested too deep, too many aliases, too long a number
                raise ValueError(f"condition {shown(text)}: {err}") from None
            value = raw
        if op in VECTOR_OPS and not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
            raise ValueError(f"condition {text!r}: {op} needs a finite distance >= 0")
        return cls(str(text), tuple(parse_field_path(field)), op, value)

    @property
    def field(self) -> str:
        return self.text.split(None, 1)[0]

    def type_error(self, type_name: str, fields: Mapping[str, str] | None = None) -> str | None:
        """Why the condition cannot be evaluated on a field of ROS type ``type_name`` (``fields``: the
        field types of that type when it is a message), or None when it can."""
        where = f"condition {self.text!r}: field {self.field} is a {type_name}"
        if self.op in VECTOR_OPS:
            axes = fields or {}
            if is_array(type_name) or not all(axes.get(a) in NUMBER_TYPES for a in VECTOR_AXES):
                return f"{where}, not a vector with numeric x, y and z ({self.op} measures its length; " \
                       f"a Pose's is pose.position)"
            return None
        if self.op == "contains":
            if not is_array(type_name):
                return f"{where}, not an array ({self.op} looks for a value among its elements)"
            return _value_error(self, element_type(type_name))
        if is_array(type_name) or fields is not None:
            return f"{where}, not a number, bool or string (compare one of its fields)"
        return _value_error(self, type_name)

    def holds(self, element: Any) -> bool:
        """Does ``element`` meet the condition? ``Unknown`` when an index it reads is past the end
        of an array, LookupError when it lacks a field."""
        found = read_field(element, self.steps)
        if self.op in VECTOR_OPS:
            norm = math.sqrt(sum(float(getattr(found, axis, 0.0)) ** 2 for axis in ("x", "y", "z")))
            return norm <= self.value if self.op == "within" else norm > self.value
        if self.op == "contains":
            return self.value in list(found)
        try:
            return bool(COMPARISONS[self.op](found, self.value))
        except TypeError:
            return False


def _value_error(condition: Condition, type_name: str) -> str | None:
    """The condition's value is not of the kind the field (of primitive ``type_name``) holds."""
    value = condition.value
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if type_name in NUMBER_TYPES and (number or isinstance(value, bool)):
        return None
    if type_name in BOOL_TYPES and (isinstance(value, bool) or value in (0, 1)):
        return None
    if type_name in TEXT_TYPES and isinstance(value, str):
        return None
    if type_name not in NUMBER_TYPES | BOOL_TYPES | TEXT_TYPES:
        return f"condition {condition.text!r}: field {condition.field} is a {type_name}, not a number, bool or " \
               f"string (compare one of its fields)"
    hint = " (quote a text value: 'label == \"7\"')" if type_name in TEXT_TYPES else ""
    return f"condition {condition.text!r}: field {condition.field} is a {type_name}; {value!r} is not a " \
           f"value of that kind{hint}"


def read_field(msg: Any, steps: Sequence[str | int]) -> Any:
    """``extract_field``, but an index past the end of an array raises ``Unknown``."""
    value = msg
    for step in steps:
        if isinstance(step, int) and isinstance(value, (list, tuple, bytes)) and not -len(value) <= step < len(value):
            raise Unknown(f"element [{step}] of a {len(value)}-element array")
        value = extract_field(value, [step])
    return value


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
        """LookupError naming the field when the message does not have it; an element on which a
        condition cannot be evaluated (``Unknown``) does not meet it."""
        return any(self._meets(e) for e in self.elements(msg))

    def _meets(self, element: Any) -> bool:
        try:
            return all(c.holds(element) for c in self.conditions)
        except Unknown:
            return False
