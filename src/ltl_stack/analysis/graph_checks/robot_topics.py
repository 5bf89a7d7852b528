"""Which robot topics each output reaches, for the robot checks C1 and C2 (thesis §3.5.2.5-6)."""
from __future__ import annotations

from collections.abc import Iterable
from fnmatch import fnmatchcase

from ltl_stack.analysis.result import Analysis


def split_robot_topic(name: str, robots: Iterable[str], namespace: str = "") -> tuple[str, str] | None:
    """``/sphero_wpw/cmd_vel`` -> (``sphero_wpw``, ``/cmd_vel``) when the name lies under a listed robot.

    A robot is a namespace: ``sphero_wpw`` (the thesis' robots at the root), or one with several
    segments (``spheros/sphero_wpw``). Inside the scenario namespace ``namespace`` robots may also be
    named relative to it, as the mapping names its nodes: with ``namespace`` ``spheros``,
    ``/spheros/sphero_wpw/cmd_vel`` belongs to robot ``sphero_wpw``. The longest robot name wins.
    """
    full = "/" + name.strip("/")
    candidates = [full]
    ns = namespace.strip("/")
    if ns and full.startswith(f"/{ns}/"):
        candidates.insert(0, full[len(ns) + 1:])
    ordered = sorted(robots, key=lambda r: len(r.strip("/")), reverse=True)
    for candidate in candidates:
        for robot in ordered:
            prefix = "/" + robot.strip("/")
            if prefix != "/" and candidate.startswith(prefix + "/"):
                return robot, candidate[len(prefix):]
    return None


def suffix_ignored(suffix: str, patterns: Iterable[str]) -> bool:
    """A robot-topic suffix is ignored if a pattern equals it, is a parent of it, or glob-matches it."""
    for p in patterns:
        p = "/" + p.strip().strip("/")
        if suffix == p or suffix.startswith(p + "/") or fnmatchcase(suffix, p):
            return True
    return False


def robot_topics(a: Analysis, y: str) -> dict[str, dict[str, tuple[str, int]]]:
    """For output y: suffix -> robot -> (node, channel vertex) of the first witness."""
    robots = set(a.robots)
    out: dict[str, dict[str, tuple[str, int]]] = {}
    for node in a.nodes.get(y, []):
        for v in a.pub[(y, node)].channels:
            split = split_robot_topic(a.graph.vertex_name(v), robots, a.namespace)
            if split is None or suffix_ignored(split[1], a.robot_topics_ignored):
                continue
            robot, suffix = split
            out.setdefault(suffix, {}).setdefault(robot, (node, v))
    return out


__all__ = ["robot_topics", "split_robot_topic", "suffix_ignored"]
