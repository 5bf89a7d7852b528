"""The computation graph: actions collapsed into one vertex, generic topics left out, lanes."""
from __future__ import annotations

from analysis_data import graph_of

from ltl_stack.analysis.graph import ACTION, DEFAULT_IGNORED_TOPICS, TOPIC, action_vertex_name
from ltl_stack.analysis.snapshot import Snapshot


def names(graph, vertex_ids):
    return sorted(graph.vertex_name(v) for v in vertex_ids)


def test_action_topics_collapse_into_one_vertex_named_like_the_thesis():
    g = graph_of({"/client": {"clients": ["/move_base"]}, "/server": {"servers": ["/move_base"]}})
    assert [c.name for c in g.channels if c.kind == ACTION] == ["move_base/action_topics"]
    action = g.channels[g.channel_index["move_base/action_topics"]]
    assert action.type == "ltl_stack/PropositionAction", action
    assert set(action.topics) == {f"/move_base/{s}" for s in ("goal", "cancel", "status", "feedback", "result")}
    assert not any(c.kind == TOPIC and c.name.startswith("/move_base/") for c in g.channels)
    assert g.channel_vertex("/move_base/feedback") == g.channel_vertex("move_base/action_topics")


def test_action_name_spelling():
    assert action_vertex_name("/arm_1/arm_controller/follow_joint_trajectory") == \
        "arm_1/arm_controller/follow_joint_trajectory/action_topics"
    assert action_vertex_name("/") == "action_topics"


def test_action_lanes_run_client_to_server_and_server_to_listeners_only():
    g = graph_of({"/client": {"clients": ["/act"]}, "/server": {"servers": ["/act"]},
                  "/monitor": {"sub": ["/act/status"]}})
    cid = g.channel_index["act/action_topics"]
    request, reply = [lane for lane, c in enumerate(g.lane_channel) if c == cid]
    idx = g.node_index
    assert (g.lane_publishers[request], g.lane_subscribers[request]) == ([idx["/client"]], [idx["/server"]])
    assert g.lane_publishers[reply] == [idx["/server"]]
    assert g.lane_subscribers[reply] == [idx["/monitor"]], "a client is not a listener of the replies"


def test_five_topics_with_a_foreign_status_type_are_not_an_action():
    snap = Snapshot.from_system_state(
        [[f"/x/{s}", ["/a"]] for s in ("goal", "cancel", "status", "feedback", "result")], [], [],
        [["/x/status", "std_msgs/String"]])
    g = graph_of({})
    g = type(g)(snap)
    assert sorted(c.name for c in g.channels) == [f"/x/{s}" for s in ("cancel", "feedback", "goal", "result", "status")]


def test_incomplete_action_stays_topics():
    g = graph_of({"/a": {"pub": ["/x/goal", "/x/cancel"], "sub": ["/x/status"]}})
    assert sorted(c.name for c in g.channels) == ["/x/cancel", "/x/goal", "/x/status"]


def test_default_ignore_list_drops_generic_topics_and_reports_them():
    g = graph_of({"/a": {"pub": ["/rosout", "/clock", "/tf", "/tf_static", "/rosout_agg", "/a/parameter_updates",
                                 "/a/parameter_descriptions", "/diagnostics", "/cmd_vel"]},
                  "/b": {"sub": ["/clock", "/tf", "/cmd_vel"]},
                  "/c": {"pub": ["/diagnostics", "/cmd_vel"]}})
    assert [c.name for c in g.channels] == ["/cmd_vel"]
    assert sorted(g.ignored) == sorted(["/rosout", "/clock", "/tf", "/tf_static", "/rosout_agg",
                                        "/a/parameter_updates", "/a/parameter_descriptions", "/diagnostics"])
    assert set(DEFAULT_IGNORED_TOPICS) >= {"/rosout", "/clock", "/tf"}


def test_user_ignore_list_replaces_the_default_and_can_hide_an_action():
    nodes = {"/a": {"pub": ["/rosout", "/odom"], "clients": ["/nav"]}, "/b": {"servers": ["/nav"]}}
    g = graph_of(nodes, ignored=["/odom", "nav/action_topics"])
    assert sorted(c.name for c in g.channels) == ["/rosout"]
    assert sorted(g.ignored) == ["/odom", "nav/action_topics"]
    g2 = graph_of(nodes, ignored=["/nav"])
    assert "nav/action_topics" not in g2.channel_index, "an action can be ignored by its namespace too"


def test_format_uses_thesis_notation():
    g = graph_of({"/a": {"pub": ["/t"], "clients": ["/act"]}})
    assert g.format_chain([g.node_index["/a"], g.channel_vertex("/t")]) == "(/a) -> [/t]"
    assert g.format_vertex(g.channel_vertex("act/action_topics")) == "(act/action_topics)"


def test_edge_count_counts_each_publisher_and_subscriber_once():
    g = graph_of({"/a": {"pub": ["/t", "/u"]}, "/b": {"sub": ["/t"]}, "/c": {"clients": ["/act"]}})
    # /t: 1 pub + 1 sub; /u: 1 pub; /rosout ignored; action request lane: 1 publisher (client)
    assert g.edge_count == 4, g.edge_count
