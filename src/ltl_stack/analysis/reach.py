"""Publish- and subscribe-reachability from one proposition node (thesis section 3.5.2.1).

From a node n, *publish* reachability follows messages: n -> topics it publishes -> nodes that
subscribe -> topics they publish -> ... ; *subscribe* reachability goes against the edges. The
traversal is breadth-first and iterative (no recursion, so graph size is no limit), visits every
vertex at most once ("the algorithm also ignores nodes that are revisited"), and remembers for each
vertex the vertex it was first reached from. Those parents give one witness chain per reached
topic or node: the dictionary C^pub_n of the thesis, from which T^pub_n and N^pub_n are read.

Actions: a client's goal reaches the server through the action's request lane; the server's
replies reach the action's listeners through the reply lane (not its clients, see
``ltl_stack.analysis.graph``). Each lane is crossed at most once; the action is reported as one
vertex, with the chain of the lane that reached it first.

``blocked`` channels (the controller's proposition topics) are not crossed: reaching an input
node must not continue through the controller node to every output node.
"""
from __future__ import annotations

from collections import deque
from collections.abc import Collection
from dataclasses import dataclass

from ltl_stack.analysis.graph import ComputationGraph

PUBLISH = "pub"
SUBSCRIBE = "sub"


@dataclass
class Reach:
    """What one node reaches in one direction.

    ``parent`` maps each reached node id, and each reached lane (as ``lane_base + lane``), to the
    vertex it was first reached from; ``entered`` maps a reached channel's vertex id to the first
    lane key through which it was entered (an action has two lanes).
    """

    graph: ComputationGraph
    start: int
    direction: str
    parent: dict[int, int]
    entered: dict[int, int]
    lane_base: int

    @property
    def channels(self) -> list[int]:
        """Vertex ids of the reached topics and actions (T^a_n), in the order they were reached."""
        return list(self.entered)

    @property
    def nodes(self) -> list[int]:
        """Vertex ids of the reached nodes other than the start (N^a_n)."""
        n = len(self.graph.nodes)
        return [v for v in self.parent if v < n and v != self.start]

    def __contains__(self, v: int) -> bool:
        return v in self.entered if v >= len(self.graph.nodes) else v in self.parent

    def chain(self, target: int) -> list[int]:
        """A witness path (vertex ids) between the start and ``target``, in the direction messages flow.

        Publish: start ... target. Subscribe: target ... start.
        """
        if target not in self:
            raise KeyError(f"{self.graph.vertex_name(target)} is not reached from {self.graph.nodes[self.start]}")
        n, base = len(self.graph.nodes), self.lane_base
        key = self.entered[target] if target >= n else target
        path = []
        while key != -1:
            path.append(key if key < n else n + self.graph.lane_channel[key - base])
            key = self.parent[key]
        if self.direction == PUBLISH:
            path.reverse()
        return path

    def chain_text(self, target: int) -> str:
        return self.graph.format_chain(self.chain(target))


def reach(graph: ComputationGraph, start: int, direction: str = PUBLISH,
          blocked: Collection[int] = ()) -> Reach:
    """Breadth-first reachability from node vertex ``start``; ``blocked`` are channel vertex ids."""
    if direction == PUBLISH:
        out_lanes, lane_next = graph.node_publishes, graph.lane_subscribers
    elif direction == SUBSCRIBE:
        out_lanes, lane_next = graph.node_subscribes, graph.lane_publishers
    else:
        raise ValueError(f"direction must be {PUBLISH!r} or {SUBSCRIBE!r}, not {direction!r}")
    n = len(graph.nodes)
    base = n + len(graph.channels)
    lane_channel = graph.lane_channel
    parent: dict[int, int] = {start: -1}
    entered: dict[int, int] = {}
    queue = deque([start])
    # Queue items and parent keys: a node id (< n), or base + lane id for a lane.
    while queue:
        item = queue.popleft()
        if item < n:
            for lane in out_lanes[item]:
                key = base + lane
                if key in parent:
                    continue
                v = n + lane_channel[lane]
                if v in blocked:
                    continue
                parent[key] = item
                entered.setdefault(v, key)
                queue.append(key)
        else:
            for m in lane_next[item - base]:
                if m not in parent:
                    parent[m] = item
                    queue.append(m)
    return Reach(graph, start, direction, parent, entered, base)
