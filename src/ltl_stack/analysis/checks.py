"""One run of the graph checks (thesis §3.5.2): reachability for every mapped proposition node, then
every check of ``graph_checks`` (E1, E2, E3, C1, C2, P1: one module each, which says what it finds).

Every finding carries one witness chain per proposition (or node) in the thesis' notation.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

from ltl_stack.analysis import graph_checks
from ltl_stack.analysis.graph import DEFAULT_MERGERS, ComputationGraph, relay_nodes
from ltl_stack.analysis.graph_checks.base import Context
from ltl_stack.analysis.graph_checks.e1_output_to_input import (
    ACTION_FEEDBACK,
    DECLARED_FEEDBACK,
    REGION_FEEDBACK,
    E1Finding,
    expected_feedback,
    expected_pairs,
    feedback_reason,
)
from ltl_stack.analysis.graph_checks.e2_shared_channel import e2_groups
from ltl_stack.analysis.graph_checks.robot_topics import split_robot_topic, suffix_ignored
from ltl_stack.analysis.reach import PUBLISH, SUBSCRIBE, reach
from ltl_stack.analysis.result import Analysis, MissingNode, Witness
from ltl_stack.runtime.config.mapping import INPUT, OUTPUT, Mapping, resolve_node_name, resolve_topics


def analyze(graph: ComputationGraph, mapping: Mapping, inputs: Sequence[str], outputs: Sequence[str], *,
            robots: Sequence[str] = (), robot_topics_to_ignore: Sequence[str] = (),
            progress: Callable[[str], None] | None = None, mergers: Sequence[str] = DEFAULT_MERGERS) -> Analysis:
    """Run reachability for every mapped proposition node, then every check that applies (the robot
    checks only with ``robots``); ``Analysis.findings`` has an entry for every check.

    ``inputs``/``outputs`` are the spec's propositions in spec order (findings follow that order);
    mapping entries for other names are left out (``runtime.config.mapping.check_mapping`` reports them).
    E2/E3 follow competitions through relays, except nodes matching ``mergers`` (``graph.relay_nodes``).
    """
    namespace = mapping.scenario_namespace() or ""
    in_topics, out_topics = resolve_topics(mapping, inputs, outputs, namespace)
    boundary = sorted({*in_topics.values(), *(t for ts in out_topics.values() for t in ts)})
    blocked = {v for v in (graph.channel_vertex(t) for t in boundary) if v is not None}
    result = Analysis(graph, list(inputs), list(outputs), {}, [], [], boundary, {}, {},
                      robots=list(robots), namespace=namespace, robot_topics_ignored=list(robot_topics_to_ignore))
    for kind, props, section in ((INPUT, inputs, mapping.inputs), (OUTPUT, outputs, mapping.outputs)):
        for prop in props:
            named = [e for e in section.get(prop) or [] if e.node is not None]
            if not named:
                result.unmapped.append(prop)
                continue
            present = []
            for entry in named:
                node = resolve_node_name(entry.node, namespace)
                if node in graph.node_index:
                    if node not in present:
                        present.append(node)
                else:
                    result.missing.append(MissingNode(prop, kind, node, entry.line))
            result.nodes[prop] = present
    todo = [(p, n) for p in (*inputs, *outputs) for n in result.nodes.get(p, [])]
    for i, (prop, node) in enumerate(todo):
        if progress and i % 50 == 0:
            progress(f"reachability {i}/{len(todo)} proposition nodes")
        start = graph.node_index[node]
        result.pub[(prop, node)] = reach(graph, start, PUBLISH, blocked)
        result.sub[(prop, node)] = reach(graph, start, SUBSCRIBE, blocked)
    result.declared_feedback = list(mapping.expected_feedback)
    relays = relay_nodes(graph, mergers)
    result.relays = sorted(graph.nodes[i] for i in relays)
    context = Context(mapping, in_topics, blocked, relays)
    for check in graph_checks.CHECKS:
        result.findings[check.code] = check.find(result, context) if check.applies(result) else []
    result.feedback = expected_pairs(result, context)
    return result


def reach_listing(a: Analysis, prop: str, direction: str = PUBLISH) -> list[dict]:
    """T^a and N^a of each node of ``prop`` with one witness chain each (for ``--reach`` reports)."""
    rows = []
    table = a.pub if direction == PUBLISH else a.sub
    for node in a.nodes.get(prop, []):
        r = table[(prop, node)]
        rows.append({
            "node": node,
            "topics": {a.graph.vertex_name(v): r.chain_text(v) for v in r.channels},
            "nodes": {a.graph.vertex_name(v): r.chain_text(v) for v in r.nodes},
        })
    return rows


__all__ = ["ACTION_FEEDBACK", "DECLARED_FEEDBACK", "PUBLISH", "REGION_FEEDBACK", "SUBSCRIBE", "Analysis",
           "E1Finding", "Witness", "analyze", "e2_groups", "expected_feedback", "feedback_reason", "reach_listing",
           "split_robot_topic", "suffix_ignored"]
