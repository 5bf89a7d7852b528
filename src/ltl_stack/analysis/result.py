"""What one run of the graph checks holds (``checks.analyze``): the mapped nodes, the reachability
of each proposition node, and the findings of each registered check (``graph_checks``), each with
its witness chains in the thesis' notation (§3.5.2)."""
from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from ltl_stack.analysis.graph import ACTION, ComputationGraph
from ltl_stack.analysis.reach import PUBLISH, Reach


@dataclass(frozen=True)
class Witness:
    """One way a proposition's node reaches something: the chain of vertices, first to last."""

    proposition: str
    node: str
    path: tuple[tuple[str, str], ...]  # (kind, name), kind in node / topic / action

    @property
    def text(self) -> str:
        return " -> ".join(f"[{name}]" if kind == "topic" else f"({name})" for kind, name in self.path)

    def to_dict(self) -> dict:
        return {"proposition": self.proposition, "node": self.node, "chain": self.text,
                "path": [{"kind": k, "name": n} for k, n in self.path]}


@dataclass(frozen=True)
class MissingNode:
    """A mapped node that is not in the graph (not launched, or a typo in the mapping)."""

    proposition: str
    kind: str
    node: str
    line: int


@dataclass
class Analysis:
    """Everything one run of the checks found; ``pub``/``sub`` keep the reachability per (prop, node).

    ``findings`` maps each check's code to its findings (every registered check has an entry, empty
    when it did not apply); ``a.e1`` is ``a.findings["E1"]``, and so for every code."""

    graph: ComputationGraph
    inputs: list[str]
    outputs: list[str]
    nodes: dict[str, list[str]]  # proposition -> its nodes present in the graph
    missing: list[MissingNode]
    unmapped: list[str]
    boundary: list[str]  # proposition topics the traversal does not cross
    pub: dict[tuple[str, str], Reach]
    sub: dict[tuple[str, str], Reach]
    robots: list[str] = field(default_factory=list)
    namespace: str = ""  # the scenario namespace of the mapping (robots may be named relative to it)
    robot_topics_ignored: list[str] = field(default_factory=list)
    findings: dict[str, list[Any]] = field(default_factory=dict)
    feedback: list[Any] = field(default_factory=list)  # E1 pairs that are expected feedback
    relays: list[str] = field(default_factory=list)  # nodes E2/E3 followed as relays (not known mergers)
    declared_feedback: list[tuple[str, str, int]] = field(default_factory=list)  # the mapping's expected_feedback

    def __getattr__(self, name: str) -> list[Any]:
        findings = self.__dict__.get("findings") or {}
        if name.upper() in findings and name.islower():
            return findings[name.upper()]
        raise AttributeError(name)

    @property
    def finding_count(self) -> int:
        return sum(len(found) for found in self.findings.values())

    def witness(self, prop: str, node: str, target: int, direction: str = PUBLISH) -> Witness:
        r = (self.pub if direction == PUBLISH else self.sub)[(prop, node)]
        return make_witness(self.graph, prop, node, r.chain(target))


def make_witness(graph: ComputationGraph, prop: str, node: str, chain: Iterable[int]) -> Witness:
    path = []
    for v in chain:
        if graph.is_node(v):
            path.append(("node", graph.nodes[v]))
        else:
            ch = graph.channel_of_vertex(v)
            path.append(("action" if ch.kind == ACTION else "topic", ch.name))
    return Witness(prop, node, tuple(path))


def channel_text(channel: str, kind: str) -> str:
    """``(action)`` or ``[topic]``, as the thesis draws them."""
    return f"({channel})" if kind == ACTION else f"[{channel}]"


__all__ = ["Analysis", "MissingNode", "Witness", "channel_text", "make_witness"]
