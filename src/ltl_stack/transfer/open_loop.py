"""Open-loop motion under B.2 speed scaling (thesis §2.5.2).

A program that drives for a fixed time (``rospy.Rate``, ``rospy.sleep``, ``time.sleep``,
``rospy.Duration``) covers speed × duration. When B.2 scales its speeds by r, every such distance or
angle changes by r too (a 0.4 m square side becomes 1.0 m): the report says so. With ``keep_distances``
every speed command is scaled by one factor r* — the smallest of the B.2 factors, so every command stays
within the target's limits — and every duration by 1/r* (``Rate`` frequencies by r*), so distances and
angles stay what the source program drove.

Durations that are timeouts (``wait_for_server(rospy.Duration(5))``, ``timeout=``) and trajectory
times (``time_from_start``) are not motion times and are left alone.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass

from .source_ast import SourceFile, Span, call_argument, number_value

#: callee (qualified) -> (position, keyword) of its time argument, and whether it is a frequency
TIME_CALLS = {"rospy.Rate": ((0, "hz"), True), "rospy.sleep": ((0, "duration"), False),
              "time.sleep": ((0, "secs"), False), "rospy.Duration": ((0, "secs"), False),
              "rospy.Duration.from_sec": ((0, "float_secs"), False)}
#: calls whose Duration arguments are timeouts or trajectory times, not motion times
NOT_MOTION = ("wait_for_server", "wait_for_result", "wait_for_service", "wait_for_message", "waitForTransform",
              "lookupTransform", "lookup_transform", "can_transform", "JointTrajectoryPoint", "send_goal_and_wait")


@dataclass
class TimeLiteral:
    """A literal that sets how long the program drives: a duration in seconds or a frequency in Hz."""

    span: Span
    value: float
    frequency: bool
    line: int
    text: str


def _is_timeout(src: SourceFile, node: ast.AST) -> bool:
    child, parent = node, src.parents.get(node)
    while parent is not None and not isinstance(parent, ast.stmt):
        if isinstance(parent, ast.keyword) and parent.arg in ("timeout", "time_from_start"):
            return True
        if isinstance(parent, ast.Call) and child is not parent.func:
            name = src.qualname(parent.func) or getattr(parent.func, "attr", "")
            if name.split(".")[-1] in NOT_MOTION:
                return True
        child, parent = parent, src.parents.get(parent)
    return isinstance(parent, ast.Assign) and any(isinstance(t, ast.Attribute) and t.attr == "time_from_start"
                                                  for t in parent.targets)


def find_time_literals(src: SourceFile) -> list[TimeLiteral]:
    """Durations and rates the program drives by (literals, or variables bound only to literals)."""
    found: dict[Span, TimeLiteral] = {}
    for node in ast.walk(src.tree):
        if not isinstance(node, ast.Call):
            continue
        callee = src.qualname(node.func) or ""
        if callee not in TIME_CALLS or _is_timeout(src, node):
            continue
        (position, keyword), frequency = TIME_CALLS[callee]
        arg = call_argument(node, position, keyword)
        values = [arg] if arg is not None and number_value(arg) is not None else \
            [v for v in src.bindings(arg) if number_value(v) is not None] if isinstance(arg, ast.Name) else []
        for value in values:
            span = src.span(value)
            found.setdefault(span, TimeLiteral(span, number_value(value), frequency, node.lineno, callee))
    return sorted(found.values(), key=lambda t: t.span.start)


def describe_change(factors: dict[str, list[float]], times: list[TimeLiteral]) -> str:
    """The report's note: which speeds changed by which factor, and the timing that makes it matter."""
    parts = []
    for field, ratios in sorted(factors.items()):
        low, high = min(ratios), max(ratios)
        parts.append(f"{field} x{low:.3g}" if abs(high - low) < 1e-9 else f"{field} x{low:.3g}..x{high:.3g}")
    timing = ", ".join(f"{t.text}({t.value:g}) at line {t.line}" for t in times[:4]) + (" …" if len(times) > 4 else "")
    return (f"open loop: B.2 scaled the speeds ({', '.join(parts)}) of a program that drives for fixed times "
            f"({timing}); every distance (linear) and angle (angular) it drives changes by the same factor. "
            "--keep-distances scales all speeds by one factor and the durations by its inverse instead")
