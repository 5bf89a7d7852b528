"""C2 (thesis §3.5.2.6, Fig. 3.15): a robot of the user's list whose topics no output reaches at all."""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.analysis.graph_checks.base import WARNING, Context, GraphCheck
from ltl_stack.analysis.graph_checks.robot_topics import robot_topics
from ltl_stack.analysis.result import Analysis


@dataclass(frozen=True)
class C2Finding:
    """``robot`` has no topic reached by any output; ``suffixes`` are what the other robots get."""

    robot: str
    suffixes: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"robot": self.robot, "suffixes_of_other_robots": list(self.suffixes)}


def find(a: Analysis, context: Context) -> list[C2Finding]:
    """Robots of the list that no output proposition reaches through any robot topic (computed once
    per ``context``: C1 leaves these robots out)."""
    return context.once("C2", lambda: _uncontrolled(a))


def _uncontrolled(a: Analysis) -> list[C2Finding]:
    reached: dict[str, set[str]] = {r: set() for r in a.robots}
    for y in a.outputs:
        for suffix, by_robot in robot_topics(a, y).items():
            for r in by_robot:
                reached[r].add(suffix)
    others = sorted(set().union(*reached.values())) if reached else []
    return [C2Finding(r, tuple(others)) for r in a.robots if not reached[r]]


def rows(f: C2Finding, markdown: bool) -> list[list[str]]:
    return [[f.robot, ", ".join(f.suffixes) if markdown else ", ".join(f.suffixes) or "—"]]


def lines(f: C2Finding) -> list[str]:
    return [f"{f.robot}: no output reaches any of its topics"
            + (f" (the other robots get {', '.join(f.suffixes)})" if f.suffixes else "")]


CHECK = GraphCheck(
    code="C2", title="Robots that no output proposition controls (thesis 3.5.2.6)", severity=WARNING,
    explanation="A robot of the list that no output reaches: its nodes are not connected to the controller "
                "(a namespace or remapping mistake, or a robot the specification forgot).",
    find=find, columns=("Robot", "Topics the other robots get"), rows=rows, lines=lines, order=50,
    needs_robots=True)
