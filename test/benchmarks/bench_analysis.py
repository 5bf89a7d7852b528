"""Graph-analysis timing on a large synthetic ROS graph (on demand).

    python test/benchmarks/bench_analysis.py            (or: python -m pytest test/benchmarks/bench_analysis.py -q -s)

A seeded generator builds a ROS-like snapshot: 200 robots/subsystems ("clusters") of 50 nodes each (sensors,
perception, planners, some of them action servers, controllers sharing command topics, drivers
whose state feeds back into the planners), fleet-wide map servers, and every node on /rosout, /tf
and /clock, as rospy nodes are. About 10,000 nodes and 50,000 publisher/subscriber edges, with 200
mapped propositions (150 outputs, some with two nodes, and 50 inputs).

Measured (median of 5 runs): loading the snapshot (JSON and YAML), building the graph, and the
whole analysis (reachability both ways for every proposition node, E1, E2, E3, C1/C2 with 20
robots, suggestions). Peers in the same run: a plain dict-based traversal of the raw snapshot
(publish reachability only, the least any analysis must do) and the same analysis on the
generator's 20-cluster graph (1,000 nodes, 40 propositions). Figures go to docs/benchmarks/analysis.md; the goal is < 2 s for the analysis.
"""
from __future__ import annotations

import json
import platform
import random
import statistics
import sys
import tempfile
import time
from collections import deque
from pathlib import Path

from ltl_stack.analysis.checks import analyze, e2_groups
from ltl_stack.analysis.graph import ComputationGraph
from ltl_stack.analysis.snapshot import Snapshot
from ltl_stack.analysis.suggest import mutual_exclusions
from ltl_stack.runtime.config.mapping import parse_mapping

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "benchmarks" / "analysis.md"
GOAL_SECONDS = 2.0


def synthetic(clusters: int = 200, seed: int = 1) -> tuple[Snapshot, str, list[str], list[str]]:
    """(snapshot, mapping YAML, inputs, outputs) of a ROS-like graph with 50 nodes per cluster."""
    rng = random.Random(seed)
    pubs: dict[str, set[str]] = {}
    subs: dict[str, set[str]] = {}

    def pub(node, topic):
        pubs.setdefault(topic, set()).add(node)

    def sub(node, topic):
        subs.setdefault(topic, set()).add(node)

    def action_server(node, ns):
        for s in ("goal", "cancel"):
            sub(node, f"{ns}/{s}")
        for s in ("status", "feedback", "result"):
            pub(node, f"{ns}/{s}")

    def action_client(node, ns):
        for s in ("goal", "cancel"):
            pub(node, f"{ns}/{s}")
        for s in ("status", "feedback", "result"):
            sub(node, f"{ns}/{s}")

    inputs, outputs, mapping = [], [], {"inputs": {}, "outputs": {}}
    for c in range(clusters):
        ns = f"/robot{c}"
        fleet_map = f"/fleet{c // 10}/map"
        nodes = []
        sensors = [f"{ns}/sensor{i}" for i in range(5)]
        for i, n in enumerate(sensors):
            pub(n, f"{ns}/scan{i}")
        percepts = [f"{ns}/percept{i}" for i in range(10)]
        for i, n in enumerate(percepts):
            for k in rng.sample(range(5), 2):
                sub(n, f"{ns}/scan{k}")
            pub(n, f"{ns}/objects{i}")
        planners = [f"{ns}/planner{i}" for i in range(10)]
        for i, n in enumerate(planners):
            for k in rng.sample(range(10), 3):
                sub(n, f"{ns}/objects{k}")
            sub(n, f"{ns}/state{rng.randrange(3)}")
            sub(n, fleet_map)
            pub(n, f"{ns}/plan{i}")
            if i < 2:
                action_server(n, f"{ns}/plan_action{i}")
        controllers = [f"{ns}/controller{i}" for i in range(10)]
        for i, n in enumerate(controllers):
            sub(n, f"{ns}/plan{i}")
            pub(n, f"{ns}/cmd{i % 3}")
            pub(n, f"{ns}/diagnostics")
        drivers = [f"{ns}/driver{i}" for i in range(3)]
        for i, n in enumerate(drivers):
            sub(n, f"{ns}/cmd{i}")
            pub(n, f"{ns}/state{i}")
            pub(n, f"{ns}/diagnostics")
        misc = [f"{ns}/misc{i}" for i in range(9)]
        for i, n in enumerate(misc):
            sub(n, f"{ns}/state{i % 3}")
            sub(n, f"{ns}/objects{i}")
            pub(n, f"{ns}/log{i}")
        props = [f"{ns}/prop{i}" for i in range(3)]
        nodes += sensors + percepts + planners + controllers + drivers + misc + props
        if c % 10 == 0:
            pub(f"{ns}/map_server", fleet_map)
            nodes.append(f"{ns}/map_server")
        # propositions: clusters 0..74 carry two outputs (one through a planner action, one on a
        # command topic; every fifth also a second node), clusters 75..124 one input each
        if c < 75:
            a, b, extra = props
            action_client(a, f"{ns}/plan_action0")
            pub(b, f"{ns}/cmd0")
            pub(extra, f"{ns}/cmd1")
            for name, node_list in ((f"go{c}", [a]), (f"halt{c}", [b, extra] if c % 5 == 0 else [b])):
                outputs.append(name)
                mapping["outputs"][name] = [{"node": n, "node_subscribe_topic": f"/spec/outputs/{name}"}
                                            for n in node_list]
                for n in node_list:
                    sub(n, f"/spec/outputs/{name}")
        elif c < 125:
            name = f"sees{c}"
            sub(props[0], f"{ns}/objects0")
            sub(props[0], f"/robot{c - 75}/state{c % 3}")  # watches an output cluster's robot (E1)
            pub(props[0], f"/spec/inputs/{name}")
            inputs.append(name)
            mapping["inputs"][name] = {"node": props[0], "node_publish_topic": f"/spec/inputs/{name}"}
        for n in nodes:  # what every rospy node does
            pub(n, "/rosout")
            if rng.random() < 0.5:
                sub(n, "/tf")
            if rng.random() < 0.1:
                sub(n, "/clock")
    state = ([(t, sorted(ns)) for t, ns in pubs.items()], [(t, sorted(ns)) for t, ns in subs.items()])
    snap = Snapshot.from_system_state(*state, [], [(t, "std_msgs/Bool") for t in {*pubs, *subs}], master="synthetic")
    return snap, json.dumps(mapping), inputs, outputs


def edge_count(snap: Snapshot) -> int:
    return sum(len(t.publishers) + len(t.subscribers) for t in snap.topics.values())


def plain_publish_reach(snap: Snapshot, starts: list[str]) -> int:
    """Peer: dict-based breadth-first publish reachability of each start node on the raw snapshot."""
    publishes: dict[str, list[str]] = {}
    for name, t in snap.topics.items():
        for n in t.publishers:
            publishes.setdefault(n, []).append(name)
    total = 0
    for start in starts:
        seen = {start}
        queue = deque([start])
        while queue:
            node = queue.popleft()
            for topic in publishes.get(node, ()):
                if topic in seen or topic in ("/rosout", "/tf", "/clock"):
                    continue
                seen.add(topic)
                for m in snap.topics[topic].subscribers:
                    if m not in seen:
                        seen.add(m)
                        queue.append(m)
        total += len(seen)
    return total


def timed(fn, runs: int = 5) -> tuple[float, object]:
    times, result = [], None
    for _ in range(runs):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def run_analysis(snap: Snapshot, mapping_text: str, inputs, outputs, robots):
    mapping = parse_mapping(mapping_text, "synthetic.yaml")
    graph = ComputationGraph(snap)
    a = analyze(graph, mapping, inputs, outputs, robots=robots, robot_topics_to_ignore=["/diagnostics"])
    return a, mutual_exclusions(e2_groups(a), outputs)


def measure() -> dict:
    snap, mapping_text, inputs, outputs = synthetic()
    robots = [f"robot{c}" for c in range(20)]
    figures = {"nodes": len(snap.nodes), "edges": edge_count(snap), "topics": len(snap.topics),
               "propositions": len(inputs) + len(outputs), "inputs": len(inputs), "outputs": len(outputs)}
    with tempfile.TemporaryDirectory() as tmp:
        for suffix in ("json", "yaml"):
            path = Path(tmp) / f"graph.{suffix}"
            snap.save(path)
            figures[f"load_{suffix}_s"], loaded = timed(lambda p=path: Snapshot.load(p), runs=3)
            assert loaded == snap
            figures[f"{suffix}_bytes"] = path.stat().st_size
    figures["graph_build_s"], graph = timed(lambda: ComputationGraph(snap))
    figures["graph_edges_after_ignoring"] = graph.edge_count
    figures["analysis_s"], (a, suggestions) = timed(lambda: run_analysis(snap, mapping_text, inputs, outputs, robots))
    figures.update(E1=len(a.e1), E2=len(a.e2), E3=len(a.e3), C1=len(a.c1), C2=len(a.c2), suggestions=len(suggestions))
    starts = [n for ns in a.nodes.values() for n in ns]
    figures["peer_plain_publish_reach_s"], _ = timed(lambda: plain_publish_reach(snap, starts))
    small, small_mapping, small_in, small_out = synthetic(clusters=20)
    figures["small_nodes"], figures["small_edges"] = len(small.nodes), edge_count(small)
    figures["small_propositions"] = len(small_in) + len(small_out)
    figures["small_analysis_s"], _ = timed(lambda: run_analysis(small, small_mapping, small_in, small_out, robots[:2]))
    return figures


def write_doc(f: dict) -> None:
    load = "under load (2 shared cores, other developers' tests running)"
    text = f"""# Graph analysis benchmark

Command: `python test/benchmarks/bench_analysis.py` (medians of 5 runs, 3 for loading; {load};
Python {platform.python_version()}, {platform.machine()}).

Synthetic ROS-like snapshot (seeded; see the generator in `test/benchmarks/bench_analysis.py`):
{f['nodes']:,} nodes, {f['topics']:,} topics, {f['edges']:,} publisher/subscriber edges
({f['graph_edges_after_ignoring']:,} after leaving out /rosout, /tf, /clock), {f['propositions']} propositions
({f['outputs']} outputs, {f['inputs']} inputs), 20 robots for C1/C2.

| step | time |
|---|---|
| load snapshot, JSON ({f['json_bytes'] / 1e6:.1f} MB) | {f['load_json_s'] * 1000:.0f} ms |
| load snapshot, YAML ({f['yaml_bytes'] / 1e6:.1f} MB, libyaml) | {f['load_yaml_s'] * 1000:.0f} ms |
| build the graph (actions, ignore list, lanes) | {f['graph_build_s'] * 1000:.0f} ms |
| **whole analysis** (graph, reachability both ways for all proposition nodes, E1-E3, C1/C2, suggestions) | **{f['analysis_s'] * 1000:.0f} ms** (goal < {GOAL_SECONDS:.0f} s) |
| peer: plain dict BFS, publish reachability only, same start nodes | {f['peer_plain_publish_reach_s'] * 1000:.0f} ms |
| same generator, 20 clusters ({f['small_nodes']:,} nodes, {f['small_edges']:,} edges, {f['small_propositions']} propositions) | {f['small_analysis_s'] * 1000:.0f} ms |

Ratios: whole analysis / plain publish traversal = {f['analysis_s'] / f['peer_plain_publish_reach_s']:.1f};
large / small graph = {f['analysis_s'] / f['small_analysis_s']:.1f} (10x the nodes, 5x the propositions).
Findings on the synthetic graph: E1 {f['E1']}, E2 {f['E2']} channels, E3 {f['E3']}, C1 {f['C1']}, C2 {f['C2']};
{f['suggestions']} suggestions.
"""
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text(text)


def test_analysis_of_a_large_graph_is_fast():
    figures = measure()
    write_doc(figures)
    print(json.dumps(figures, indent=1))
    assert figures["nodes"] >= 10_000 and figures["edges"] >= 50_000, figures
    assert figures["propositions"] == 200
    assert figures["analysis_s"] < GOAL_SECONDS, figures


if __name__ == "__main__":
    test_analysis_of_a_large_graph_is_fast()
    sys.exit(0)
