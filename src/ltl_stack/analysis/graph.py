"""The ROS computation graph G = {N, E} of thesis Def. 3.4.1, ready for reachability.

Built from a ``Snapshot``: nodes and *channels* form a bipartite directed graph, node -> channel
for a publisher and channel -> node for a subscriber. A channel is a topic, or an action whose
``goal/cancel/status/feedback/result`` topics are collapsed into one vertex named as in the thesis
figures (``move_base/action_topics``). An action vertex carries requests from clients to servers
(goal, cancel) and replies from servers (status, feedback, result). Replies are delivered to the
nodes that only *listen* to the action (monitors), not back to its clients: a client acts on the
replies to the goals it sent itself, so following them would let a goal sent by one client flow
on to every other client of the same server, and from there to everything they command - false
conflicts between every pair of propositions that share a planner.

Generic topics that every node uses (``/rosout``, ``/diagnostics``, ``/clock``, ``/tf``, parameter updates,
...) are
left out, so that they do not make every node reach every other one (false conflicts).
"""
from __future__ import annotations

import re
from collections.abc import Collection, Iterable
from dataclasses import dataclass
from fnmatch import translate
from functools import lru_cache

from ltl_stack.analysis.snapshot import Snapshot

DEFAULT_IGNORED_TOPICS: tuple[str, ...] = (
    "/rosout",
    "/rosout_agg",
    "/diagnostics",
    "/diagnostics_agg",
    "/clock",
    "/tf",
    "/tf_static",
    "*/parameter_updates",
    "*/parameter_descriptions",
)

#: nodes that merge commands by design (a competition does not flow through them): shell patterns on the
#: node name, extended with ``analyze_graph --add-mergers`` (``*`` crosses ``/``)
DEFAULT_MERGERS: tuple[str, ...] = ("*mux*", "*multiplexer*", "*arbiter*", "*arbitrator*")

ACTION_REQUEST_TOPICS = ("goal", "cancel")
ACTION_REPLY_TOPICS = ("status", "feedback", "result")
ACTION_STATUS_TYPE = "actionlib_msgs/GoalStatusArray"

TOPIC = "topic"
ACTION = "action"


def action_vertex_name(namespace: str) -> str:
    """``/move_base`` -> ``move_base/action_topics`` (the thesis figures' spelling)."""
    stripped = namespace.strip("/")
    return f"{stripped}/action_topics" if stripped else "action_topics"


def matches_any(name: str, patterns: Iterable[str]) -> bool:
    """True if ``name`` matches one of the shell-style ``patterns`` (``*`` crosses ``/``)."""
    return _pattern_regex(tuple(patterns)).match(name) is not None


@lru_cache(maxsize=64)
def _pattern_regex(patterns: tuple[str, ...]) -> re.Pattern:
    return re.compile("|".join(f"(?:{translate(p)})" for p in patterns) or r"(?!)")


@dataclass(frozen=True)
class Channel:
    """A topic or a collapsed action, as shown to the user."""

    name: str
    kind: str  # TOPIC or ACTION
    type: str  # message type of a topic; action type ("pkg/FooAction") of an action, '' if unknown
    topics: tuple[str, ...]  # the ROS topics it stands for


class ComputationGraph:
    """Integer-indexed bipartite graph of nodes and channels.

    Vertex ids used by ``reach``: node ``i`` is ``i``; channel ``c`` is ``len(nodes) + c``.
    Internally each topic has one *lane* and each action two (request, reply); a lane is what
    edges attach to, and ``lane_channel[l]`` is the channel it belongs to.
    """

    def __init__(self, snapshot: Snapshot, ignored_topics: Iterable[str] = DEFAULT_IGNORED_TOPICS):
        self.ignore_patterns: tuple[str, ...] = tuple(ignored_topics)
        self.services = {k: list(v) for k, v in snapshot.services.items()}
        self.nodes: list[str] = sorted(set(snapshot.nodes))
        self.node_index: dict[str, int] = {n: i for i, n in enumerate(self.nodes)}
        self.channels: list[Channel] = []
        self.channel_index: dict[str, int] = {}
        self.topic_channel: dict[str, int] = {}  # ROS topic name -> channel id
        self.ignored: list[str] = []  # channel names left out because of ignore_patterns
        self.lane_channel: list[int] = []
        self.lane_publishers: list[list[int]] = []
        self.lane_subscribers: list[list[int]] = []
        self.node_publishes: list[list[int]] = [[] for _ in self.nodes]
        self.node_subscribes: list[list[int]] = [[] for _ in self.nodes]
        self._build(snapshot)

    # -- construction -------------------------------------------------------------------------
    def _build(self, snapshot: Snapshot) -> None:
        topics = snapshot.topics
        for name in snapshot.nodes:
            self._node(name)
        for t in topics.values():
            for n in (*t.publishers, *t.subscribers):
                self._node(n)
        actions = find_actions(snapshot)
        in_action = {f"{ns}/{s}" for ns in actions for s in (*ACTION_REQUEST_TOPICS, *ACTION_REPLY_TOPICS)}
        for ns in sorted(actions):
            name = action_vertex_name(ns)
            members = tuple(f"{ns}/{s}" for s in (*ACTION_REQUEST_TOPICS, *ACTION_REPLY_TOPICS))
            if matches_any(name, self.ignore_patterns) or matches_any(ns, self.ignore_patterns):
                self.ignored.append(name)
                continue
            goal_type = topics[f"{ns}/goal"].type
            action_type = goal_type[: -len("Goal")] if goal_type.endswith("ActionGoal") else ""
            cid = self._channel(Channel(name, ACTION, action_type, members))
            request, reply = self._lane(cid), self._lane(cid)
            self._attach(request, [topics[f"{ns}/{s}"] for s in ACTION_REQUEST_TOPICS])
            clients = set(self.lane_publishers[request])
            self._attach(reply, [topics[f"{ns}/{s}"] for s in ACTION_REPLY_TOPICS], skip_subscribers=clients)
            for topic in members:
                self.topic_channel[topic] = cid
        for name in sorted(topics):
            if name in in_action:
                continue
            if matches_any(name, self.ignore_patterns):
                self.ignored.append(name)
                continue
            cid = self._channel(Channel(name, TOPIC, topics[name].type, (name,)))
            self.topic_channel[name] = cid
            self._attach(self._lane(cid), [topics[name]])

    def _node(self, name: str) -> int:
        i = self.node_index.get(name)
        if i is None:
            i = self.node_index[name] = len(self.nodes)
            self.nodes.append(name)
            self.node_publishes.append([])
            self.node_subscribes.append([])
        return i

    def _channel(self, channel: Channel) -> int:
        cid = self.channel_index[channel.name] = len(self.channels)
        self.channels.append(channel)
        return cid

    def _lane(self, cid: int) -> int:
        self.lane_channel.append(cid)
        self.lane_publishers.append([])
        self.lane_subscribers.append([])
        return len(self.lane_channel) - 1

    def _attach(self, lane: int, topics: Iterable, skip_subscribers: Collection[int] = ()) -> None:
        pubs: dict[int, None] = {}
        subs: dict[int, None] = {}
        for topic in topics:
            pubs.update((self.node_index[n], None) for n in topic.publishers)
            subs.update((i, None) for i in (self.node_index[n] for n in topic.subscribers) if i not in skip_subscribers)
        self.lane_publishers[lane] = list(pubs)
        self.lane_subscribers[lane] = list(subs)
        for i in pubs:
            self.node_publishes[i].append(lane)
        for i in subs:
            self.node_subscribes[i].append(lane)

    # -- lookups ------------------------------------------------------------------------------
    @property
    def edge_count(self) -> int:
        """Number of publisher and subscriber edges (node->lane and lane->node)."""
        return sum(len(p) + len(s) for p, s in zip(self.lane_publishers, self.lane_subscribers))

    def vertex_name(self, v: int) -> str:
        n = len(self.nodes)
        return self.nodes[v] if v < n else self.channels[v - n].name

    def is_node(self, v: int) -> bool:
        return v < len(self.nodes)

    def channel_of_vertex(self, v: int) -> Channel:
        return self.channels[v - len(self.nodes)]

    def channel_vertex(self, name: str) -> int | None:
        """Vertex id of a channel given its name, or of the channel holding ROS topic ``name``."""
        cid = self.channel_index.get(name)
        if cid is None:
            cid = self.topic_channel.get(name)
        return None if cid is None else len(self.nodes) + cid

    def format_vertex(self, v: int) -> str:
        """Thesis notation: ``(node)``, ``[topic]``, and ``(ns/action_topics)`` for an action."""
        if self.is_node(v):
            return f"({self.nodes[v]})"
        ch = self.channel_of_vertex(v)
        return f"({ch.name})" if ch.kind == ACTION else f"[{ch.name}]"

    def format_chain(self, chain: Iterable[int]) -> str:
        return " -> ".join(self.format_vertex(v) for v in chain)


def find_actions(snapshot: Snapshot) -> set[str]:
    """Namespaces whose five actionlib topics all exist (and whose status type, if known, is actionlib's)."""
    topics = snapshot.topics
    found = set()
    for name in topics:
        if not name.endswith("/goal"):
            continue
        ns = name[: -len("/goal")]
        if not all(f"{ns}/{s}" in topics for s in (*ACTION_REQUEST_TOPICS, *ACTION_REPLY_TOPICS)):
            continue
        status_type = topics[f"{ns}/status"].type
        if status_type and status_type != ACTION_STATUS_TYPE:
            continue
        found.add(ns)
    return found


def relay_nodes(graph: ComputationGraph, mergers: Iterable[str] = DEFAULT_MERGERS) -> set[int]:
    """Nodes that only forward messages: they subscribe to topics and publish only topics of types they
    subscribe to (a ``topic_tools relay``, a forwarding script), and are not known mergers (``mergers``:
    patterns on the node name). A driver (``cmd_vel`` in, ``odom`` out) is no relay."""
    found = set()
    for i, name in enumerate(graph.nodes):
        outs, ins = graph.node_publishes[i], graph.node_subscribes[i]
        if not outs or not ins or matches_any(name, tuple(mergers)):
            continue
        in_types = {graph.channels[graph.lane_channel[lane]].type for lane in ins
                    if graph.channels[graph.lane_channel[lane]].kind == TOPIC}
        out_channels = [graph.channels[graph.lane_channel[lane]] for lane in outs]
        if all(c.kind == TOPIC and c.type and c.type in in_types for c in out_channels):
            found.add(i)
    return found
