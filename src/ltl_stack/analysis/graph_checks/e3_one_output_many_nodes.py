"""E3 (thesis §3.5.2.4, Fig. 3.9): one output proposition's nodes publish-reach the same topic through
several nodes (with E2's refinement: they must compete there)."""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.analysis.graph_checks.base import WARNING, Context, GraphCheck
from ltl_stack.analysis.graph_checks.competition import competitions
from ltl_stack.analysis.result import Analysis, Witness, channel_text


@dataclass(frozen=True)
class E3Finding:
    """Several nodes of one output proposition reach one channel: one witness per node."""

    output: str
    channel: str
    kind: str
    witnesses: tuple[Witness, ...]

    def to_dict(self) -> dict:
        return {"output": self.output, "topic": self.channel, "kind": self.kind,
                "nodes": [w.node for w in self.witnesses], "chains": [w.to_dict() for w in self.witnesses]}


def find(a: Analysis, context: Context) -> list[E3Finding]:
    rank = {y: i for i, y in enumerate(a.outputs)}
    found = []
    for c in competitions(a, context):
        ch = a.graph.channel_of_vertex(c.vertex)
        for y, nodes in c.same.items():
            ordered = [node for node in a.nodes[y] if node in nodes]
            found.append(E3Finding(y, ch.name, ch.kind, tuple(a.witness(y, node, c.vertex) for node in ordered)))
    found.sort(key=lambda f: (rank[f.output], f.channel))
    return found


def rows(f: E3Finding, markdown: bool) -> list[list[str]]:
    channel = f.channel if markdown else channel_text(f.channel, f.kind)
    return [[f.output if i == 0 else "", channel if i == 0 else "", w.node, f"`{w.text}`" if markdown else w.text]
            for i, w in enumerate(f.witnesses)]


def lines(f: E3Finding) -> list[str]:
    return [f"{f.output} reaches {channel_text(f.channel, f.kind)} through {len(f.witnesses)} nodes:",
            *(f"  {w.node}: {w.text}" for w in f.witnesses)]


def witnesses(f: E3Finding) -> tuple[list[Witness], set[str]]:
    return list(f.witnesses), {f.channel}


CHECK = GraphCheck(
    code="E3", title="One output proposition reaching a topic through several of its nodes (thesis 3.5.2.4)",
    severity=WARNING,
    explanation="The nodes of one output command the same topic or action: when they disagree, the last "
                "message wins.",
    find=find, columns=("Output", "Topic", "Node", "One existing chain"), rows=rows, lines=lines, order=30,
    witnesses=witnesses)
