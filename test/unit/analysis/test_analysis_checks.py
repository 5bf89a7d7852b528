"""Checks E1, E2, E3, C1, C2 on hand-built graphs and on the thesis examples' graphs."""
from __future__ import annotations

import pytest
import yaml
from analysis_data import DATA, analyze_simple, graph_of, mapping_of, scenarios
from helpers import require_shared
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.analysis.checks import (
    ACTION_FEEDBACK,
    DECLARED_FEEDBACK,
    REGION_FEEDBACK,
    analyze,
    expected_feedback,
    split_robot_topic,
    suffix_ignored,
)
from ltl_stack.analysis.graph import DEFAULT_IGNORED_TOPICS, DEFAULT_MERGERS, ComputationGraph
from ltl_stack.analysis.suggest import mutual_exclusions
from ltl_stack.runtime.config.mapping import load_mapping, parse_mapping

MGMB = "/move_group_and_move_base"
REGIONS = ["rightLane", "leftLane", "topLane", "leftGround", "bottomLane", "rightGround"]


# --- hand-built graphs --------------------------------------------------------------------------

def test_e1_output_reaching_an_input_node_with_its_chain():
    a = analyze_simple({"/cam_off": {"pub": ["/camera/enable"]}, "/camera": {"sub": ["/camera/enable"], "pub": ["/image"]},
                        "/person": {"sub": ["/image"]}, "/move": {"pub": ["/cmd_vel"]}},
                       inputs={"person": "/person"}, outputs={"disableCamera": "/cam_off", "move": "/move"})
    assert [(f.output, f.input) for f in a.e1] == [("disableCamera", "person")]
    assert a.e1[0].witness.text == "(/cam_off) -> [/camera/enable] -> (/camera) -> [/image] -> (/person)"


def test_e1_one_row_per_pair_with_every_chain_folded_under_it():
    # two nodes of disableCamera (one per robot) both reach the person detector: one finding, two chains
    nodes = {"/r1/cam_off": {"pub": ["/r1/camera/enable"]}, "/r2/cam_off": {"pub": ["/r2/camera/enable"]},
             "/person": {"sub": ["/r1/camera/enable", "/r2/camera/enable"]}}
    a = analyze_simple(nodes, inputs={"person": "/person"},
                       outputs={"disableCamera": ["/r1/cam_off", "/r2/cam_off"]})
    assert [(f.output, f.input) for f in a.e1] == [("disableCamera", "person")]
    assert [w.text for w in a.e1[0].witnesses] == ["(/r1/cam_off) -> [/r1/camera/enable] -> (/person)",
                                                   "(/r2/cam_off) -> [/r2/camera/enable] -> (/person)"]
    assert a.e1[0].input_nodes == ("/person", "/person") and a.finding_count == 1
    assert [c["output_node"] for c in a.e1[0].to_dict()["chains"]] == ["/r1/cam_off", "/r2/cam_off"]


def navigation_graph(extra: dict | None = None) -> dict:
    """Two regions driven through one planner to the base, whose location the region sensors read;
    ``stop`` commands the base directly; ``pick`` reports its own completion."""
    nodes = {"/nav_a": {"clients": ["/navigate"]}, "/nav_b": {"clients": ["/navigate"]},
             "/navigation": {"servers": ["/navigate"], "pub": ["/cmd_vel"]},
             "/stop": {"pub": ["/cmd_vel"]}, "/base": {"sub": ["/cmd_vel"], "pub": ["/current_region"]},
             "/a_rc": {"sub": ["/current_region"]}, "/b_rc": {"sub": ["/current_region"]},
             "/pick": {"pub": ["/pick_done"]}, "/pick_ac": {"sub": ["/pick_done"]}}
    nodes.update(extra or {})
    return nodes


def test_activation_completion_pairs_are_expected_feedback_not_findings():
    a = analyze_simple(navigation_graph(), inputs={"a_rc": "/a_rc", "b_rc": "/b_rc", "pick_ac": "/pick_ac"},
                       outputs={"a": "/nav_a", "b": "/nav_b", "stop": "/stop", "pick": "/pick"})
    assert [(f.output, f.input, f.expected) for f in a.feedback] == [
        ("a", "a_rc", REGION_FEEDBACK), ("b", "b_rc", REGION_FEEDBACK), ("pick", "pick_ac", ACTION_FEEDBACK)]
    assert a.feedback[0].witness.text == ("(/nav_a) -> (navigate/action_topics) -> (/navigation) -> [/cmd_vel] "
                                          "-> (/base) -> [/current_region] -> (/a_rc)")
    # exactly the thesis' pairs: a motion output reaching another region's sensor is a finding
    assert [(f.output, f.input) for f in a.e1] == [("a", "b_rc"), ("b", "a_rc"), ("stop", "a_rc"), ("stop", "b_rc")]
    assert a.finding_count == len(a.e2) + 4


def test_the_mapping_declares_more_expected_feedback():
    mapping = mapping_of({"a_rc": "/a_rc", "b_rc": "/b_rc", "pick_ac": "/pick_ac"},
                         {"a": "/nav_a", "b": "/nav_b", "stop": "/stop", "pick": "/pick"})
    mapping.expected_feedback = [("stop", "*_rc", 3), ("a", "b_rc", 4)]
    a = analyze(graph_of(navigation_graph()), mapping, ["a_rc", "b_rc", "pick_ac"], ["a", "b", "stop", "pick"])
    assert [(f.output, f.input) for f in a.e1] == [("b", "a_rc")]
    assert [(f.output, f.input, f.expected) for f in a.feedback if f.expected == DECLARED_FEEDBACK] == [
        ("a", "b_rc", DECLARED_FEEDBACK), ("stop", "a_rc", DECLARED_FEEDBACK), ("stop", "b_rc", DECLARED_FEEDBACK)]


def test_feedback_is_only_what_the_paradigm_designs():
    # an output that reaches the location sensing by switching off the localisation camera is a finding;
    # so is a region reaching an input that is no completion, and an action reaching another action's
    # completion
    extra = {"/cam_off": {"pub": ["/camera/enable"]}, "/locate": {"sub": ["/camera/enable"], "pub": ["/current_region"]},
             "/bump": {"sub": ["/current_region"]}, "/pick": {"pub": ["/pick_done", "/place_done"]},
             "/place_ac": {"sub": ["/place_done"]}, "/place": {}}
    a = analyze_simple(navigation_graph(extra),
                       inputs={"a_rc": "/a_rc", "b_rc": "/b_rc", "pick_ac": "/pick_ac", "bumped": "/bump",
                               "place_ac": "/place_ac"},
                       outputs={"a": "/nav_a", "b": "/nav_b", "stop": "/stop", "pick": "/pick",
                                "disableCamera": "/cam_off", "place": "/place"})
    assert ("pick", "place_ac") in [(f.output, f.input) for f in a.e1]
    assert ("disableCamera", "a_rc") in [(f.output, f.input) for f in a.e1]
    assert {(f.output, f.input) for f in a.feedback} == {("a", "a_rc"), ("b", "b_rc"), ("pick", "pick_ac")}


@given(st.sampled_from(["x", "x_ac", "x_rc", "y_ac", "y_rc", "person", "x_ac_rc"]),
       st.sampled_from(["x", "y", "x_ac", "stop"]),
       st.lists(st.tuples(st.sampled_from(["x", "stop", "*"]), st.sampled_from(["y_rc", "*_rc", "person"])),
                max_size=3))
def test_expected_feedback_is_a_completion_pair_or_declared(input, output, declared):
    kind = expected_feedback(output, input, [(o, i, 1) for o, i in declared])
    if kind == ACTION_FEEDBACK:
        assert input == output + "_ac"
    elif kind == REGION_FEEDBACK:
        assert input == output + "_rc"
    elif kind == DECLARED_FEEDBACK:
        assert any((o in (output, "*")) and (i == input or (i == "*_rc" and input.endswith("_rc")))
                   for o, i in declared)
    else:
        assert kind == "" and input not in (output + "_ac", output + "_rc")


def test_e2_groups_outputs_by_topic_with_one_chain_each():
    a = analyze_simple({"/move": {"pub": ["/cmd_vel"]}, "/stop": {"pub": ["/cmd_vel"]}, "/wave": {"pub": ["/arm"]}},
                       inputs={}, outputs={"move": "/move", "stop": "/stop", "wave": "/wave"})
    assert [(g.channel, g.outputs) for g in a.e2] == [("/cmd_vel", ("move", "stop"))]
    assert [w.text for w in a.e2[0].witnesses] == ["(/move) -> [/cmd_vel]", "(/stop) -> [/cmd_vel]"]


def test_generic_topics_do_not_create_conflicts():
    nodes = {n: {"pub": ["/rosout", "/tf", "/clock", f"{n}/parameter_updates"], "sub": ["/clock", "/tf"]}
             for n in ("/a", "/b")}
    a = analyze_simple(nodes, inputs={}, outputs={"a": "/a", "b": "/b"})
    assert a.e2 == [] and a.e1 == [], (a.e1, a.e2)
    a = analyze_simple(nodes, inputs={}, outputs={"a": "/a", "b": "/b"}, ignored=())
    assert {g.channel for g in a.e2} >= {"/rosout", "/tf"}, "without the ignore list they would conflict"


def test_proposition_topics_are_a_boundary_through_the_controller():
    # output a's node feeds input x's node; the controller turns x into every output: must not leak.
    nodes = {"/a": {"pub": ["/a_status"]}, "/x": {"sub": ["/a_status"], "pub": ["/t/inputs/x"]},
             "/executor": {"sub": ["/t/inputs/x"], "pub": ["/t/outputs/a", "/t/outputs/b"]},
             "/b": {"sub": ["/t/outputs/b"], "pub": ["/cmd_vel"]}, "/c": {"sub": ["/t/outputs/a"], "pub": ["/cmd_vel"]}}
    a = analyze_simple(nodes, inputs={"x": "/x"}, outputs={"a": "/a", "b": "/b"})
    assert [(f.output, f.input) for f in a.e1] == [("a", "x")]
    assert a.e2 == [], a.e2


def test_e2_through_a_shared_action_server():
    nodes = {"/r1": {"clients": ["/move_base"]}, "/r2": {"clients": ["/move_base"]},
             "/move_base": {"servers": ["/move_base"], "pub": ["/cmd_vel"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"r1": "/r1", "r2": "/r2"})
    assert [(g.channel, g.kind, g.outputs) for g in a.e2] == [
        ("/cmd_vel", "topic", ("r1", "r2")), ("move_base/action_topics", "action", ("r1", "r2"))]
    assert a.e2[0].witnesses[0].text == "(/r1) -> (move_base/action_topics) -> (/move_base) -> [/cmd_vel]"


def test_feedback_loop_through_odometry_and_how_the_ignore_list_removes_it():
    nodes = {"/stop": {"pub": ["/cmd_vel"]}, "/base": {"sub": ["/cmd_vel"], "pub": ["/odom"]},
             "/planner": {"sub": ["/odom"], "pub": ["/arm_cmd"]}, "/grab": {"pub": ["/arm_cmd"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"stop": "/stop", "grab": "/grab"})
    assert [g.channel for g in a.e2] == ["/arm_cmd"], "structural reachability follows the odometry loop"
    a = analyze_simple(nodes, inputs={}, outputs={"stop": "/stop", "grab": "/grab"},
                       ignored=(*DEFAULT_IGNORED_TOPICS, "/odom"))
    assert a.e2 == []


def test_e3_one_output_two_nodes_same_topic_and_not_for_distinct_topics():
    nodes = {"/pickup": {"pub": ["/gripper"]}, "/drop": {"pub": ["/gripper"]},
             "/r1": {"pub": ["/r1/cmd_vel"]}, "/r2": {"pub": ["/r2/cmd_vel"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"pickup": ["/pickup", "/drop"], "move": ["/r1", "/r2"]})
    assert [(f.output, f.channel, [w.node for w in f.witnesses]) for f in a.e3] == [
        ("pickup", "/gripper", ["/pickup", "/drop"])]
    assert a.e2 == [], "one output's own nodes are E3, not E2"


def test_missing_and_unmapped_nodes_are_reported_not_fatal():
    a = analyze_simple({"/a": {"pub": ["/t"]}}, inputs={}, outputs={"a": "/a", "ghost": "/not_running"})
    assert [(m.proposition, m.node) for m in a.missing] == [("ghost", "/not_running")]
    assert a.nodes == {"a": ["/a"], "ghost": []}


SPHERO_NODES = {f"/{r}/{o}": {"pub": [f"/{r}/{t}"]} for r in ("r1", "r2", "r3") for o, t in
                (("left", "cmd_vel"), ("yellow", "set_color"))}
SPHERO_NODES.update({f"/{r}/drv": {"sub": [f"/{r}/cmd_vel", f"/{r}/set_color"], "pub": [f"/{r}/odom"]}
                     for r in ("r1", "r2", "r3")})


def test_c1_and_c2_with_namespaced_robots_and_ignored_robot_topics():
    outputs = {"left": ["/r1/left", "/r2/left"], "yellow": ["/r1/yellow", "/r2/yellow", "/r3/yellow"]}
    a = analyze_simple(SPHERO_NODES, inputs={}, outputs=outputs, robots=["r1", "r2", "r3", "r4"],
                       robot_topics_to_ignore=["/odom"])
    assert [(f.output, f.suffix, f.missing, [r for r, _ in f.present]) for f in a.c1] == [
        ("left", "/cmd_vel", ("r3",), ["r1", "r2"])], a.c1
    assert a.c1[0].present[0][1].text == "(/r1/left) -> [/r1/cmd_vel]"
    assert [(f.robot, f.suffixes) for f in a.c2] == [("r4", ("/cmd_vel", "/set_color"))]
    a = analyze_simple(SPHERO_NODES, inputs={}, outputs=outputs, robots=["r1", "r2", "r3"])
    assert ("left", "/odom") in [(f.output, f.suffix) for f in a.c1], "odom counts unless ignored"


def test_robot_topic_helpers():
    assert split_robot_topic("/r1/cmd_vel", {"r1"}) == ("r1", "/cmd_vel")
    assert split_robot_topic("r1/move/action_topics", {"r1"}) == ("r1", "/move/action_topics")
    assert split_robot_topic("/r10/cmd_vel", {"r1"}) is None
    assert split_robot_topic("/r1", {"r1"}) is None
    # robots of a scenario namespace, named relative to it or in full, and robots of several segments
    assert split_robot_topic("/spheros/r1/cmd_vel", {"r1"}, "spheros") == ("r1", "/cmd_vel")
    assert split_robot_topic("spheros/r1/move/action_topics", {"r1"}, "/spheros/") == ("r1", "/move/action_topics")
    assert split_robot_topic("/spheros/r1/cmd_vel", {"r1"}) is None
    assert split_robot_topic("/r1/cmd_vel", {"r1"}, "spheros") == ("r1", "/cmd_vel")
    assert split_robot_topic("/spheros/r1/cmd_vel", {"spheros/r1"}) == ("spheros/r1", "/cmd_vel")
    assert split_robot_topic("/a/b/cmd_vel", {"a", "a/b"}) == ("a/b", "/cmd_vel")
    assert suffix_ignored("/odom", ["/odom"]) and suffix_ignored("/imu/data", ["imu"])
    assert suffix_ignored("/camera/depth", ["/camera/*"]) and not suffix_ignored("/odometry", ["/odom"])


# --- the thesis examples -----------------------------------------------------------------------

@pytest.fixture(scope="module")
def clean_and_patrol():
    path = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.yaml")
    graph = ComputationGraph(scenarios.scenario_snapshot(DATA / "clean_and_patrol.yaml"))
    return graph, path


def run(graph, mapping):
    return analyze(graph, mapping, list(mapping.inputs), list(mapping.outputs))


def test_clean_and_patrol_reproduces_figs_3_6_to_3_8(clean_and_patrol):
    graph, path = clean_and_patrol
    a = run(graph, load_mapping(path))
    assert a.e1 == []  # Fig. 3.6 is the designed completion feedback: shown apart, not a finding
    assert [(f.output, f.input, f.expected, f.witness.text) for f in a.feedback] == [
        ("pickup", "pickup_ac", ACTION_FEEDBACK, f"(/pickup) -> [{MGMB}/outputs/pickup_status] -> (/pickup_ac)"),
        ("drop", "drop_ac", ACTION_FEEDBACK, f"(/drop) -> [{MGMB}/outputs/drop_status] -> (/drop_ac)")]
    groups = {g.channel: g for g in a.e2}
    assert set(groups["/cmd_vel"].outputs) == {"pickup", "stop", *REGIONS}  # Fig. 3.7
    chains = {w.proposition: w.text for w in groups["/cmd_vel"].witnesses}
    assert chains["topLane"] == f"({MGMB}/outputs/topLane) -> (move_base/action_topics) -> (/move_base) -> [/cmd_vel]"
    assert chains["pickup"] == "(/pickup) -> [/cmd_vel]"
    arm = groups["arm_1/arm_controller/follow_joint_trajectory/action_topics"]  # Fig. 3.8
    assert arm.outputs == ("pickup", "drop")
    assert arm.witnesses[1].text == ("(/drop) -> (move_group/action_topics) -> (/move_group) -> "
                                     "(arm_1/arm_controller/follow_joint_trajectory/action_topics)")
    assert a.e3 == []
    suggestions = mutual_exclusions([(g.channel, g.outputs) for g in a.e2], list(load_mapping(path).outputs))
    assert [set(s.propositions) for s in suggestions] == [{"pickup", "stop", *REGIONS}, {"pickup", "drop"}]


def test_clean_and_patrol_drop_node_wrongly_mapped_to_pickup_is_e3(clean_and_patrol):
    graph, path = clean_and_patrol
    data = yaml.safe_load(path.read_text())
    data["outputs"]["pickup"] = [data["outputs"]["pickup"], dict(data["outputs"]["drop"],
                                 node_subscribe_topic=f"{MGMB}/outputs/pickup")]
    a = run(graph, parse_mapping(yaml.safe_dump(data), "wrong.yaml"))
    gripper = [f for f in a.e3 if f.channel == "/arm_1/gripper_controller/position_command"]  # Fig. 3.9
    assert [(f.output, [w.node for w in f.witnesses], [w.text for w in f.witnesses]) for f in gripper] == [
        ("pickup", ["/pickup", "/drop"], ["(/pickup) -> [/arm_1/gripper_controller/position_command]",
                                          "(/drop) -> [/arm_1/gripper_controller/position_command]"])]


@pytest.fixture(scope="module")
def spheros():
    graph = ComputationGraph(scenarios.scenario_snapshot(DATA / "spheros.yaml"))
    return graph, load_mapping(DATA / "spheros_mapping.yaml")


ROBOTS = ["sphero_wpw", "sphero_ggw", "sphero_rgw", "sphero_wpp"]
SENSORS = ["/collision", "/diagnostics", "/imu", "/odom"]


def test_spheros_fig_3_14_move_down_leaves_one_robot_behind(spheros):
    graph, mapping = spheros
    a = analyze(graph, mapping, [], list(mapping.outputs), robots=ROBOTS, robot_topics_to_ignore=SENSORS)
    assert [(f.output, f.suffix, f.missing) for f in a.c1] == [("move_down", "/cmd_vel", ("sphero_wpw",))]
    assert [r for r, _ in a.c1[0].present] == ["sphero_ggw", "sphero_rgw", "sphero_wpp"]
    assert a.c1[0].present[0][1].text == "(/spheros/outputs/sphero_ggw/move_down) -> [/sphero_ggw/cmd_vel]"
    assert a.c2 == []
    assert [(g.channel, g.outputs) for g in a.e2 if g.channel == "/sphero_rgw/cmd_vel"] == [
        ("/sphero_rgw/cmd_vel", ("move_left", "move_down"))]  # Fig. 3.13


def test_spheros_fig_3_15_fifth_robot_not_controlled(spheros):
    graph, mapping = spheros
    a = analyze(graph, mapping, [], list(mapping.outputs), robots=[*ROBOTS, "sphero_wrb"],
                robot_topics_to_ignore=SENSORS)
    assert [(f.robot, f.suffixes) for f in a.c2] == [("sphero_wrb", ("/cmd_vel", "/set_color"))]
    assert [(f.output, f.suffix, f.missing) for f in a.c1] == [("move_down", "/cmd_vel", ("sphero_wpw",))], \
        "the uncontrolled robot is reported once, by C2"


# --- refinement: competing on a channel, not merely reaching it ------------------------------------

def test_a_driver_merging_two_commands_is_not_a_conflict_on_its_outputs():
    nodes = {"/left": {"pub": ["/r/cmd_vel"]}, "/yellow": {"pub": ["/r/set_color"]},
             "/driver": {"sub": ["/r/cmd_vel", "/r/set_color"], "pub": ["/r/odom"]}}
    types = {"/r/cmd_vel": "geometry_msgs/Twist", "/r/set_color": "std_msgs/ColorRGBA", "/r/odom": "nav_msgs/Odometry"}
    a = analyze_simple(nodes, inputs={}, outputs={"left": "/left", "yellow": "/yellow"}, topic_types=types)
    assert a.e2 == [] and a.relays == [], (a.e2, a.relays)


def test_a_conflict_flows_downstream_through_a_shared_relay():
    nodes = {"/a": {"pub": ["/cmd"]}, "/b": {"pub": ["/cmd"]},
             "/relay": {"sub": ["/cmd"], "pub": ["/hw"]}, "/c": {"pub": ["/other"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"a": "/a", "b": "/b", "c": "/c"})
    assert [(g.channel, g.outputs) for g in a.e2] == [("/cmd", ("a", "b")), ("/hw", ("a", "b"))]


def test_mux_merged_outputs_are_not_made_exclusive_with_each_other():
    nodes = {"/nav": {"pub": ["/nav_vel"]}, "/teleop": {"pub": ["/teleop_vel"]},
             "/mux": {"sub": ["/nav_vel", "/teleop_vel"], "pub": ["/cmd_vel"]}, "/stop": {"pub": ["/cmd_vel"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"nav": "/nav", "teleop": "/teleop", "stop": "/stop"})
    [group] = a.e2
    assert (group.channel, group.outputs, group.pairs, group.complete) == (
        "/cmd_vel", ("nav", "teleop", "stop"), (("nav", "stop"), ("teleop", "stop")), False)
    got = mutual_exclusions([(g.channel, g.pairs) for g in a.e2], ["nav", "teleop", "stop"])
    assert sorted(s.propositions for s in got) == [("nav", "stop"), ("teleop", "stop")]


def test_clients_of_one_relay_do_not_compete_on_the_relays_action_but_do_on_its_input():
    nodes = {"/p": {"pub": ["/req"]}, "/q": {"pub": ["/req"]},
             "/relay": {"sub": ["/req"], "clients": ["/arm"]}, "/arm": {"servers": ["/arm"]}}
    a = analyze_simple(nodes, inputs={}, outputs={"p": "/p", "q": "/q"})
    assert [g.channel for g in a.e2] == ["/req", "arm/action_topics"], "flows downstream from /req"
    nodes["/q"] = {"pub": ["/req2"]}
    nodes["/relay"]["sub"] = ["/req", "/req2"]
    a = analyze_simple(nodes, inputs={}, outputs={"p": "/p", "q": "/q"})
    assert a.e2 == [], "one client (the relay) sends every goal: nobody competes on the action"


TWIST = "geometry_msgs/Twist"


def relay_graph(relay: str) -> dict:
    """move and stop each feed a node that forwards their velocity commands to /cmd_vel."""
    return {"/move": {"pub": ["/move_vel"]}, "/stop": {"pub": ["/stop_vel"]},
            relay: {"sub": ["/move_vel", "/stop_vel"], "pub": ["/cmd_vel"]}, "/base": {"sub": ["/cmd_vel"]}}


RELAY_TYPES = {"/move_vel": TWIST, "/stop_vel": TWIST, "/cmd_vel": TWIST}


def test_a_plain_relay_is_followed_for_e2():
    a = analyze_simple(relay_graph("/forward"), inputs={}, outputs={"move": "/move", "stop": "/stop"},
                       topic_types=RELAY_TYPES)
    assert [(g.channel, g.outputs) for g in a.e2] == [("/cmd_vel", ("move", "stop"))], a.e2
    assert a.relays == ["/forward"]


def test_a_relay_chain_is_followed_and_e3_sees_through_it():
    nodes = {"/move_a": {"pub": ["/a"]}, "/move_b": {"pub": ["/b"]},
             "/r1": {"sub": ["/a"], "pub": ["/a2"]}, "/r2": {"sub": ["/a2", "/b"], "pub": ["/cmd_vel"]}}
    types = {"/a": TWIST, "/b": TWIST, "/a2": TWIST, "/cmd_vel": TWIST}
    a = analyze_simple(nodes, inputs={}, outputs={"move": ["/move_a", "/move_b"]}, topic_types=types)
    assert [(f.output, f.channel) for f in a.e3] == [("move", "/cmd_vel")], a.e3


@pytest.mark.parametrize("name, mergers", [("/cmd_vel_mux", DEFAULT_MERGERS), ("/yocs_twist_mux", DEFAULT_MERGERS),
                                           ("/safety", (*DEFAULT_MERGERS, "/safety"))])
def test_a_known_merger_is_not_followed(name, mergers):
    a = analyze_simple(relay_graph(name), inputs={}, outputs={"move": "/move", "stop": "/stop"},
                       topic_types=RELAY_TYPES, mergers=mergers)
    assert a.e2 == [] and a.relays == [], (a.e2, a.relays)


def test_a_second_publisher_on_an_input_topic_is_a_finding():
    nodes = {"/person": {"pub": ["/t/inputs/person"]}, "/tester": {"pub": ["/t/inputs/person"]},
             "/move": {"pub": ["/cmd_vel"]}}
    a = analyze_simple(nodes, inputs={"person": "/person"}, outputs={"move": "/move"})
    assert [(f.input, f.topic, f.others, f.nodes) for f in a.p1] == [
        ("person", "/t/inputs/person", ("/tester",), ("/person",))]
    assert a.finding_count == 1
    alone = analyze_simple({"/person": {"pub": ["/t/inputs/person"]}}, inputs={"person": "/person"}, outputs={})
    assert alone.p1 == [] and alone.finding_count == 0
