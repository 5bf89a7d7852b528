"""The clean-and-patrol mapping names only nodes its launch files start (no analysis warning
"node … is not in the graph" on our own scenario), read from the launch XML without a ROS master.

The completion inputs pickup_ac / drop_ac are published by the pickup / drop output nodes
(action_proposition's ~completion_topic), so the mapping names those nodes for them; a live check of
the same scenario is in test/integration (analyze_graph --live).
"""
from __future__ import annotations

import posixpath
import xml.etree.ElementTree as ET
from pathlib import Path

from ltl_stack.runtime.config.mapping import INPUT, load_mapping, resolve_name, resolve_node_name

REPO = Path(__file__).resolve().parents[3]
LAUNCH = REPO / "launch"
CONFIG = REPO / "config" / "clean_and_patrol"


def launched(path: Path, ns: str = "/") -> dict[str, dict[str, str]]:
    """{global node name: {param name: value}} of every node in a launch file and its includes
    from this package (``$(find ltl_stack)/launch/x.launch``)."""
    nodes: dict[str, dict[str, str]] = {}

    def visit(element: ET.Element, ns: str) -> None:
        for child in element:
            if child.tag == "group":
                visit(child, posixpath.join(ns, child.get("ns", "")))
            elif child.tag == "node":
                params = {p.get("name"): p.get("value", "") for p in child if p.tag == "param"}
                params.update({f"remap:{r.get('from')}": r.get("to") for r in child if r.tag == "remap"})
                nodes[posixpath.join(ns, child.get("name"))] = params
            elif child.tag == "include":
                nodes.update(launched(LAUNCH / Path(child.get("file")).name, ns))

    visit(ET.parse(path).getroot(), ns)
    return nodes


def test_every_mapped_node_is_started_by_the_scenario_launch():
    mapping = load_mapping(CONFIG / "clean_and_patrol.yaml")
    nodes = launched(LAUNCH / "clean_and_patrol.launch")
    namespace = mapping.scenario_namespace()
    assert namespace == "clean_and_patrol"
    for section in (mapping.inputs, mapping.outputs):
        for prop, entries in section.items():
            for entry in entries:
                assert resolve_node_name(entry.node, namespace) in nodes, (prop, entry.node, sorted(nodes))


def test_completion_inputs_name_the_nodes_that_publish_them():
    mapping = load_mapping(CONFIG / "clean_and_patrol.yaml")
    nodes = launched(LAUNCH / "clean_and_patrol.launch")
    namespace = mapping.scenario_namespace()
    for action in ("pickup", "drop"):
        (entry,) = mapping.inputs[f"{action}_ac"]
        publisher = nodes[resolve_node_name(entry.node, namespace)]
        topic = resolve_name(entry.topic, namespace, INPUT)
        node_ns = posixpath.dirname(resolve_node_name(entry.node, namespace))
        assert posixpath.join(node_ns, publisher["completion_topic"]) == topic, (action, publisher, topic)
