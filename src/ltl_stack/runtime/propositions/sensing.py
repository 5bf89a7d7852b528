"""Sensing, ROS-free: field paths into messages, thresholds with hysteresis, positions of poses.

The input proposition nodes (``ltl_stack.ros.sensors``) turn messages into Booleans with these;
messages are read by attribute, so any object with the same fields (a genpy message, a test double)
works.
"""
from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable
from typing import Any

COMPARISONS: dict[str, Callable[[float, float], bool]] = {
    ">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le,
    "==": operator.eq, "!=": operator.ne,
    "gt": operator.gt, "ge": operator.ge, "lt": operator.lt, "le": operator.le,
    "eq": operator.eq, "ne": operator.ne,
}

_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)?((?:\[-?\d+\])*)$")


def parse_field_path(path: str) -> list[str | int]:
    """Split ``pose.position.x`` or ``ranges[3]`` or ``data`` into attribute names and indices."""
    steps: list[str | int] = []
    if not path.strip():
        raise ValueError("the field path is empty")
    for part in path.strip().split("."):
        match = _STEP.match(part)
        if not match or (not match.group(1) and not match.group(2)):
            raise ValueError(f"bad field path {path!r} at {part!r}")
        if match.group(1):
            steps.append(match.group(1))
        steps.extend(int(i) for i in re.findall(r"-?\d+", match.group(2)))
    return steps


def extract_field(msg: Any, steps: list[str | int]) -> Any:
    """Follow attribute names and indices into ``msg``; raise LookupError naming the missing step."""
    value = msg
    for step in steps:
        try:
            value = value[step] if isinstance(step, int) else getattr(value, step)
        except (AttributeError, IndexError, TypeError):
            raise LookupError(f"message has no field {step!r}") from None
    return value


class ThresholdComparator:
    """``value <op> threshold`` with hysteresis: once true, it turns false only past the threshold
    by ``hysteresis`` (and the other way round), so a noisy reading does not make it flicker."""

    def __init__(self, comparison: str, threshold: float, hysteresis: float = 0.0) -> None:
        if comparison not in COMPARISONS:
            raise ValueError(f"unknown comparison {comparison!r} (one of {' '.join(COMPARISONS)})")
        self.op = COMPARISONS[comparison]
        self.comparison = comparison
        self.threshold = float(threshold)
        self.hysteresis = abs(float(hysteresis))
        self.state: bool | None = None

    def update(self, value: float) -> bool:
        value = float(value)
        if math.isnan(value):
            return bool(self.state)
        if self.hysteresis == 0.0 or self.state is None or self.comparison in ("==", "!=", "eq", "ne"):
            self.state = self.op(value, self.threshold)
            return self.state
        # Moving the threshold away from the current state makes leaving it harder.
        larger = self.op(1.0, 0.0)  # true for > and >=
        shift = self.hysteresis if self.state != larger else -self.hysteresis
        self.state = self.op(value, self.threshold + shift)
        return self.state


def check_field_path(sample: Any, steps: list[str | int], type_name: str = "the message") -> None:
    """Check that ``steps`` lead from ``sample`` (a default-constructed message) to a number.

    Raise LookupError naming the step that does not exist. An index into a variable-length array
    (empty in the sample) cannot be checked further and is accepted.
    """
    value = sample
    for position, step in enumerate(steps):
        if isinstance(step, int):
            if not isinstance(value, (list, tuple, bytes)):
                raise LookupError(f"{type_name} field {field_path_text(steps[:position])} is not an array")
            if not value:
                return
            value = value[0]
            continue
        slots = getattr(value, "__slots__", None)
        if (slots is not None and step not in slots) or not hasattr(value, step):
            known = ", ".join(getattr(value, "__slots__", ())) or "none"
            raise LookupError(f"{type_name} has no field {field_path_text(steps[:position + 1])} "
                              f"(fields there: {known})")
        value = getattr(value, step)
    if isinstance(value, (bool, int, float)):
        return
    raise LookupError(f"{type_name} field {field_path_text(steps)} is a {type(value).__name__}, not a number")


def field_path_text(steps: list[str | int]) -> str:
    """``pose.position.x``, ``ranges[3]`` from parsed steps."""
    text = ""
    for step in steps:
        text += f"[{step}]" if isinstance(step, int) else (f".{step}" if text else step)
    return text or "(the message)"


def pose_xy(msg: Any) -> tuple[float, float]:
    """(x, y) of an Odometry, PoseStamped, PoseWithCovarianceStamped, Pose, Pose2D or Point."""
    for path in ("pose.pose.position", "pose.position", "position", ""):
        obj = msg
        try:
            for step in path.split(".") if path else []:
                obj = getattr(obj, step)
            return (float(obj.x), float(obj.y))
        except AttributeError:
            continue
    raise LookupError(f"cannot read a position from a {type(msg).__name__}")
