"""Test data of the graph analysis: scenario graphs in test/data/analysis and small graph builders."""
from __future__ import annotations

import importlib.util
from pathlib import Path

from ltl_stack.analysis.checks import analyze
from ltl_stack.analysis.graph import DEFAULT_IGNORED_TOPICS, ComputationGraph
from ltl_stack.runtime.config.mapping import parse_mapping

DATA = Path(__file__).resolve().parents[2] / "data" / "analysis"


def _load_scenario_module():
    spec = importlib.util.spec_from_file_location("analysis_scenario_graph", DATA / "scenario_graph.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


scenarios = _load_scenario_module()


def graph_of(nodes: dict, ignored=DEFAULT_IGNORED_TOPICS, topic_types: dict | None = None) -> ComputationGraph:
    """A graph from ``{node: {pub: [...], sub: [...], clients: [...], servers: [...]}}``."""
    return ComputationGraph(scenarios.snapshot_of({"nodes": nodes, "topic_types": topic_types or {}}), ignored)


def mapping_of(inputs: dict[str, str | list[str]], outputs: dict[str, str | list[str]]):
    """A mapping whose propositions use the given nodes (topics /t/inputs/<p>, /t/outputs/<p>)."""
    lines = []
    for section, props, key in (("inputs", inputs, "node_publish_topic"), ("outputs", outputs, "node_subscribe_topic")):
        lines.append(f"{section}:")
        for prop, nodes in props.items():
            lines.append(f"  {prop}:")
            for node in [nodes] if isinstance(nodes, str) else nodes:
                lines += [f"    - node: '{node}'", f"      {key}: '/t/{section}/{prop}'"]
    return parse_mapping("\n".join(lines) + "\n", "test.yaml")


def analyze_simple(nodes: dict, inputs: dict, outputs: dict, **kwargs):
    ignored = kwargs.pop("ignored", DEFAULT_IGNORED_TOPICS)
    g = graph_of(nodes, ignored, kwargs.pop("topic_types", None))
    return analyze(g, mapping_of(inputs, outputs), list(inputs), list(outputs), **kwargs)
