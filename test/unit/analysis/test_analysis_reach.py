"""Publish/subscribe reachability with witness chains (thesis 3.5.2.1): cycles, actions, blocking."""
from __future__ import annotations

from analysis_data import graph_of
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.analysis.reach import PUBLISH, SUBSCRIBE, reach


def reached(graph, start, direction=PUBLISH, blocked=()):
    r = reach(graph, graph.node_index[start], direction, {graph.channel_vertex(b) for b in blocked})
    return r, sorted(graph.vertex_name(v) for v in r.channels), sorted(graph.vertex_name(v) for v in r.nodes)


PIPELINE = {
    "/prop": {"pub": ["/a"]},
    "/relay": {"sub": ["/a"], "pub": ["/b"]},
    "/sink": {"sub": ["/b"], "pub": ["/a"]},  # closes a cycle back to /a
    "/other": {"pub": ["/c"]},
}


def test_publish_reach_follows_messages_through_relays_and_stops_at_cycles():
    g = graph_of(PIPELINE)
    r, topics, nodes = reached(g, "/prop")
    assert topics == ["/a", "/b"], topics
    assert nodes == ["/relay", "/sink"], nodes
    assert r.chain_text(g.channel_vertex("/b")) == "(/prop) -> [/a] -> (/relay) -> [/b]"
    assert r.chain_text(g.node_index["/sink"]) == "(/prop) -> [/a] -> (/relay) -> [/b] -> (/sink)"


def test_subscribe_reach_goes_against_the_edges_and_chains_read_in_message_order():
    g = graph_of(PIPELINE)
    r, topics, nodes = reached(g, "/relay", SUBSCRIBE)
    assert topics == ["/a", "/b"], topics
    assert nodes == ["/prop", "/sink"], nodes
    assert r.chain_text(g.node_index["/prop"]) == "(/prop) -> [/a] -> (/relay)"


def test_blocked_topics_are_not_crossed():
    g = graph_of(PIPELINE)
    _, topics, nodes = reached(g, "/prop", blocked=["/b"])
    assert (topics, nodes) == (["/a"], ["/relay"])


ACTIONS = {
    "/pickup": {"clients": ["/move_group"]},
    "/drop": {"clients": ["/move_group"], "pub": ["/drop_cmd"]},
    "/move_group": {"servers": ["/move_group"], "clients": ["/arm"]},
    "/arm": {"servers": ["/arm"], "pub": ["/joint_states"]},
    "/watcher": {"sub": ["/arm/result"], "pub": ["/arm_done"]},
}


def test_goal_goes_client_to_server_and_replies_only_to_listeners():
    g = graph_of(ACTIONS)
    r, topics, nodes = reached(g, "/pickup")
    assert topics == ["/arm_done", "/joint_states", "arm/action_topics", "move_group/action_topics"], topics
    assert "/drop" not in nodes and "/drop_cmd" not in topics, "replies do not flow on to other clients"
    assert nodes == ["/arm", "/move_group", "/watcher"], nodes
    assert r.chain_text(g.node_index["/watcher"]) == \
        "(/pickup) -> (move_group/action_topics) -> (/move_group) -> (arm/action_topics) -> (/arm) " \
        "-> (arm/action_topics) -> (/watcher)"


def test_subscribe_reach_through_an_action_is_the_reverse():
    g = graph_of(ACTIONS)
    _, topics, nodes = reached(g, "/watcher", SUBSCRIBE)
    assert nodes == ["/arm", "/drop", "/move_group", "/pickup"], nodes
    _, _, nodes = reached(g, "/pickup", SUBSCRIBE)
    assert nodes == [], "a client is not influenced through the replies to its own goals"


def test_a_server_reached_by_a_topic_does_not_push_into_its_clients():
    g = graph_of({"/stop": {"pub": ["/cmd_vel"]}, "/base": {"sub": ["/cmd_vel"], "servers": ["/nav"]},
                  "/region": {"clients": ["/nav"], "pub": ["/goal_marker"]}})
    _, topics, nodes = reached(g, "/stop")
    assert (topics, nodes) == (["/cmd_vel", "nav/action_topics"], ["/base"]), (topics, nodes)


# --- property: the traversal reaches exactly the closure, and every chain is a path of the graph

node_names = [f"/n{i}" for i in range(6)]
topic_names = [f"/t{i}" for i in range(4)]
graphs = st.dictionaries(
    st.sampled_from(node_names),
    st.fixed_dictionaries({"pub": st.lists(st.sampled_from(topic_names), unique=True, max_size=3),
                           "sub": st.lists(st.sampled_from(topic_names), unique=True, max_size=3),
                           "clients": st.lists(st.sampled_from(["/act"]), max_size=1),
                           "servers": st.lists(st.sampled_from(["/act"]), max_size=1)}),
    min_size=1)


def closure(g, start, direction):
    """Fixpoint over explicit (vertex, vertex) edges: a reference independent of the BFS."""
    n = len(g.nodes)
    edges = set()
    for lane in range(len(g.lane_channel)):
        pubs, subs = g.lane_publishers[lane], g.lane_subscribers[lane]
        if direction == SUBSCRIBE:
            pubs, subs = subs, pubs
        edges |= {(p, ("lane", lane)) for p in pubs} | {(("lane", lane), s) for s in subs}
    seen = {start}
    changed = True
    while changed:
        changed = False
        for a, b in edges:
            if a in seen and b not in seen:
                seen.add(b)
                changed = True
    chans = {n + g.lane_channel[x[1]] for x in seen if isinstance(x, tuple)}
    return chans, {x for x in seen if isinstance(x, int) and x != start}


@settings(max_examples=150, deadline=None)
@given(graphs, st.sampled_from([PUBLISH, SUBSCRIBE]))
def test_reach_equals_closure_and_chains_are_paths(nodes, direction):
    g = graph_of(nodes)
    start = 0
    r = reach(g, start, direction)
    chans, others = closure(g, start, direction)
    assert set(r.channels) == chans
    assert set(r.nodes) == others
    n = len(g.nodes)
    for target in [*r.channels, *r.nodes]:
        chain = r.chain(target)
        assert chain[0 if direction == PUBLISH else -1] == start and target in (chain[0], chain[-1])
        assert len(set(chain)) == len(chain) or any(v >= n for v in chain), "no node repeats on a chain"
        for a, b in zip(chain, chain[1:]):  # chains read in message order
            if a < n:
                assert any(g.lane_channel[lane] == b - n for lane in g.node_publishes[a]), g.format_chain(chain)
            else:
                assert any(g.lane_channel[lane] == a - n for lane in g.node_subscribes[b]), g.format_chain(chain)
