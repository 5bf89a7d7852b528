"""Which output-proposition nodes can put conflicting messages on a topic (checks E2 and E3).

The thesis (3.5.2.3) flags two outputs as soon as their publish-reachable sets share a topic. On
real graphs that over-approximation flags every pair of outputs that command the same driver:
``move_left -> /cmd_vel -> (driver)`` and ``turn_yellow -> /set_color -> (driver)`` both "reach"
the driver's ``/odom``, yet they never compete there - the driver merges them by design (the same
holds for a ``twist_mux``). We keep the thesis' reachability and refine when a shared channel is a
conflict:

1. *Direct* conflict at channel c between nodes a and b: they reach c, and messages land on c
   through different publishers (a's through p, b's through q, p != q). If both land only through
   the same single publisher r, they do not compete on c itself. On an action only the goals
   (client to server) count: one server's replies do not compete. A relay (a node that only forwards
   topics, ``graph.relay_nodes``; known mergers such as a ``twist_mux`` excepted) is transparent:
   messages that land through it land through the publisher before it on the agent's chain.
2. A conflict flows downstream: once a and b compete on c, every channel reachable from c carries
   the mixed stream (Fig. 3.8: pickup and drop compete on ``move_group``'s action, and therefore on
   the arm controller's action that ``move_group`` drives).

A pair of nodes of different outputs is an E2 conflict; two nodes of the same output, an E3 one.
"""
from __future__ import annotations

from collections import deque
from collections.abc import Collection
from itertools import combinations
from typing import Tuple

from ltl_stack.analysis.graph import ComputationGraph
from ltl_stack.analysis.reach import Reach

Agent = Tuple[str, str]  # (output proposition, node)


def _origin(node: int, r: Reach, relays: Collection[int]) -> int:
    """The publisher an agent's messages really come from: back through relays along its chain."""
    seen = set()
    while node in relays and node != r.start and node not in seen:
        seen.add(node)
        lane_key = r.parent.get(node, -1)
        if lane_key == -1:
            break
        node = r.parent[lane_key]
    return node


def conflict_pairs(graph: ComputationGraph, reaches: dict[Agent, Reach],
                   blocked: Collection[int] = (), relays: Collection[int] = ()) -> dict[int, set[tuple[Agent, Agent]]]:
    """Channel vertex id -> the pairs of agents (output, node) that compete on it. Messages that land
    through a relay (``graph.relay_nodes``) count as landing through the publisher before it."""
    agents = list(reaches)
    by_channel: dict[int, list[int]] = {}
    for i, agent in enumerate(agents):
        for v in reaches[agent].channels:
            by_channel.setdefault(v, []).append(i)
    n = len(graph.nodes)
    lanes_of = channel_lanes(graph)
    direct: dict[int, frozenset[tuple[int, int]]] = {}
    for v, who in by_channel.items():
        if len(who) < 2:
            continue
        # the topic's lane, or an action's request lane: goals compete, replies do not
        publishers = graph.lane_publishers[lanes_of[v - n][0]]
        classes: dict[object, list[int]] = {}
        for i in who:
            parent = reaches[agents[i]].parent
            entry = [p for p in publishers if p in parent]
            if not entry:
                continue  # reaches an action only through its replies
            key = ("via", _origin(entry[0], reaches[agents[i]], relays)) if len(entry) == 1 else ("own", i)
            classes.setdefault(key, []).append(i)
        if len(classes) < 2:
            continue
        groups = list(classes.values())
        pairs = {(min(i, j), max(i, j)) for g1, g2 in combinations(groups, 2) for i in g1 for j in g2}
        direct[v] = frozenset(pairs)
    result: dict[int, set[tuple[int, int]]] = {}
    spread: set[tuple[frozenset, int]] = set()
    for v, pairs in direct.items():
        for t in downstream(graph, v, lanes_of, blocked):
            if (pairs, t) in spread:
                continue
            spread.add((pairs, t))
            result.setdefault(t, set()).update(pairs)
    return {t: {(agents[i], agents[j]) for i, j in pairs} for t, pairs in result.items()}


def channel_lanes(graph: ComputationGraph) -> list[list[int]]:
    lanes: list[list[int]] = [[] for _ in graph.channels]
    for lane, c in enumerate(graph.lane_channel):
        lanes[c].append(lane)
    return lanes


def downstream(graph: ComputationGraph, v: int, lanes_of: list[list[int]], blocked: Collection[int] = ()) -> list[int]:
    """Channel vertex ids reachable from channel ``v`` along the message flow, ``v`` first."""
    n = len(graph.nodes)
    seen_channels = {v}
    seen_nodes: set[int] = set()
    order = [v]
    queue = deque(lanes_of[v - n])
    seen_lanes = set(queue)
    while queue:
        lane = queue.popleft()
        for m in graph.lane_subscribers[lane]:
            if m in seen_nodes:
                continue
            seen_nodes.add(m)
            for out in graph.node_publishes[m]:
                if out in seen_lanes:
                    continue
                c = n + graph.lane_channel[out]
                if c in blocked:
                    continue
                seen_lanes.add(out)
                queue.append(out)
                if c not in seen_channels:
                    seen_channels.add(c)
                    order.append(c)
    return order


def maximal_cliques(pairs: Collection[tuple[str, str]]) -> list[frozenset[str]]:
    """Maximal sets of propositions in which every two are in conflict (Bron-Kerbosch with pivot)."""
    adjacent: dict[str, set[str]] = {}
    for a, b in pairs:
        if a != b:
            adjacent.setdefault(a, set()).add(b)
            adjacent.setdefault(b, set()).add(a)
    cliques: list[frozenset[str]] = []
    stack = [(frozenset(), set(adjacent), set())]
    while stack:
        r, p, x = stack.pop()
        if not p and not x:
            if len(r) >= 2:
                cliques.append(r)
            continue
        pivot = max(p | x, key=lambda u: len(adjacent[u] & p))
        for u in sorted(p - adjacent[pivot]):
            stack.append((r | {u}, p & adjacent[u], x & adjacent[u]))
            p = p - {u}
            x = x | {u}
    return cliques
