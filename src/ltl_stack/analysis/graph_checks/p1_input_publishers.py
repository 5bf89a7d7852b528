"""P1 (thesis §3.5.1): an input proposition topic that nodes other than the input's own publish on
(a second publisher the controller would listen to as well: an input topic takes exactly one node)."""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.analysis.conflicts import channel_lanes
from ltl_stack.analysis.graph_checks.base import ERROR, Context, GraphCheck
from ltl_stack.analysis.result import Analysis
from ltl_stack.runtime.config.mapping import resolve_node_name


@dataclass(frozen=True)
class InputPublisherFinding:
    """An input proposition topic published by nodes other than the input's own (thesis §3.5.1: an
    input topic takes exactly one node): the controller reads whichever spoke last."""

    input: str
    topic: str
    others: tuple[str, ...]   # the other publishers
    nodes: tuple[str, ...]    # the input's mapped nodes

    def to_dict(self) -> dict:
        return {"input": self.input, "topic": self.topic, "other_publishers": list(self.others),
                "mapped_nodes": list(self.nodes)}


def find(a: Analysis, context: Context) -> list[InputPublisherFinding]:
    """Input proposition topics that nodes other than the input's mapped node(s) publish on."""
    graph = a.graph
    lanes_of = channel_lanes(graph)
    found = []
    for x in a.inputs:
        topic = context.in_topics.get(x)
        v = graph.channel_vertex(topic) if topic else None
        if v is None:
            continue
        publishers = [graph.nodes[p] for lane in lanes_of[v - len(graph.nodes)] for p in graph.lane_publishers[lane]]
        own = tuple(resolve_node_name(e.node, a.namespace) for e in context.mapping.inputs.get(x) or [] if e.node)
        others = tuple(sorted(set(publishers) - set(own)))
        if others and own:
            found.append(InputPublisherFinding(x, topic, others, own))
    return found


def rows(f: InputPublisherFinding, markdown: bool) -> list[list[str]]:
    return [[f.input, f.topic, ", ".join(f.others), ", ".join(f.nodes)]]


def lines(f: InputPublisherFinding) -> list[str]:
    return [f"{f.input} [{f.topic}]: also published by {', '.join(f.others)} (the input's node: "
            f"{', '.join(f.nodes)})"]


CHECK = GraphCheck(
    code="P1", title="Input proposition topics with other publishers than the input's node (thesis 3.5.1)",
    severity=ERROR,
    explanation="The controller reads whichever publisher spoke last, so the input's value is not the "
                "sensor's; fix it before trusting the other findings.",
    find=find, columns=("Input", "Topic", "Other publishers", "Mapped node"), rows=rows, lines=lines, order=60)
