"""The real-robot proposition nodes on a real master: move_base_region against the simulated move_base
server (goal, arrival, cancel, abort and retry), region_localization from tf and from a pose topic."""
from __future__ import annotations

from pathlib import Path

import pytest
from helpers import wait_for
from test_nodes_probe import make_session

from ltl_stack.runtime.propositions.regions import RegionMap, shared_border

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits

REGIONS = Path(__file__).resolve().parents[2] / "config" / "clean_and_patrol" / "clean_and_patrol.regions"
MAP = RegionMap.load(REGIONS)
ACTIVE, PREEMPTED = 1, 2


@pytest.fixture
def ros(request):
    return make_session(request)


def robot(ros, *extra: str) -> list[str]:
    """Start the simulated base (tf and odometry) and its move_base server in the test's namespace."""
    tf = [f"/tf:={ros.topic('tf')}", f"/tf_static:={ros.topic('tf_static')}"]
    x, y = MAP.find("topLane").interior_point()
    ros.run("sim_robot", "_mode:=holonomic", f"_x:={x}", f"_y:={y}", "_time_scale:=4", f"_regions_file:={REGIONS}",
            f"__ns:={ros.ns}", *tf)
    ros.run("sim_navigation_server", "_mode:=holonomic", "_action:=move_base", "_action_type:=move_base_msgs/MoveBase",
            "_max_linear:=2.0", f"_regions_file:={REGIONS}", f"__ns:={ros.ns}", *extra)
    return tf


def changes(values: list) -> list:
    return [v for i, v in enumerate(values) if i == 0 or v != values[i - 1]]


def test_move_base_region_drives_there_completes_and_localization_from_tf_follows(ros):
    from move_base_msgs.msg import MoveBaseActionGoal
    from std_msgs.msg import Bool, String

    goals = ros.record(ros.topic("move_base/goal"), MoveBaseActionGoal)
    completion = ros.record(ros.topic("inputs/rightLane_done"), Bool)
    region = ros.record(ros.topic("localized_region"), String)
    inputs = {r: ros.record(ros.topic(f"inputs/{r}_rc"), Bool) for r in MAP.names()}
    tf = robot(ros)
    ros.run("region_localization", f"_regions_file:={REGIONS}", "_hysteresis:=0.1", f"__ns:={ros.ns}", *tf)
    ros.run("move_base_region", "_region:=rightLane", f"_regions_file:={REGIONS}", f"__ns:={ros.ns}",
            f"proposition:={ros.topic('outputs/rightLane')}", f"completion:={ros.topic('inputs/rightLane_done')}")
    region.wait_last(lambda s: s.data == "topLane", what="localization: topLane from tf")
    ros.master.wait_for_subscriber(ros.topic("move_base/result"))
    goals.wait_connected()  # the goal is published once, not latched: hear it
    ros.set_bool(ros.topic("outputs/rightLane"), True)
    completion.wait_last(lambda b: b.data is True, timeout=90, what="move_base goal reached")
    region.wait_last(lambda s: s.data == "rightLane", what="localization: rightLane")
    goal = goals.last().goal.target_pose
    assert goal.header.frame_id == "map"
    assert (goal.pose.position.x, goal.pose.position.y) == pytest.approx(MAP.find("rightLane").interior_point())
    assert changes([s.data for s in region.snapshot()]) == ["topLane", "rightLane"]  # no chatter on the border
    wait_for(lambda: all(rec.last() is not None and rec.last().data == (r == "rightLane")
                         for r, rec in inputs.items()), 60, "exactly rightLane_rc true")
    ros.set_bool(ros.topic("outputs/rightLane"), False)
    completion.wait_last(lambda b: b.data is False, what="completion reset on the falling edge")


def test_move_base_region_cancels_on_deactivation(ros):
    from actionlib_msgs.msg import GoalStatusArray

    status = ros.record(ros.topic("move_base/status"), GoalStatusArray)
    robot(ros)
    ros.run("move_base_region", "_region:=bottomLane", f"_regions_file:={REGIONS}", f"__ns:={ros.ns}",
            f"proposition:={ros.topic('outputs/bottomLane')}", f"completion:={ros.topic('inputs/bottomLane_done')}")
    ros.master.wait_for_subscriber(ros.topic("move_base/result"))
    ros.set_bool(ros.topic("outputs/bottomLane"), True)
    status.wait_last(lambda m: [s.status for s in m.status_list] == [ACTIVE], what="the goal running")
    ros.set_bool(ros.topic("outputs/bottomLane"), False)
    status.wait_last(lambda m: [s.status for s in m.status_list] == [PREEMPTED], what="the goal preempted")


def test_move_base_region_resends_an_aborted_goal_until_it_arrives(ros):
    from move_base_msgs.msg import MoveBaseActionGoal
    from std_msgs.msg import Bool

    goals = ros.record(ros.topic("move_base/goal"), MoveBaseActionGoal)
    completion = ros.record(ros.topic("inputs/leftGround_done"), Bool)
    robot(ros, "_abort_first:=2")
    ros.run("move_base_region", "_region:=leftGround", "_pose:=[1.5, 2.0, 1.57]", "_retry_delay:=0.2",
            f"_regions_file:={REGIONS}", f"__ns:={ros.ns}", f"proposition:={ros.topic('outputs/leftGround')}",
            f"completion:={ros.topic('inputs/leftGround_done')}")
    ros.master.wait_for_subscriber(ros.topic("move_base/result"))
    goals.wait_connected()  # else the first goal can go out before the recorder hears it (seen: 2 of 3)
    ros.set_bool(ros.topic("outputs/leftGround"), True)
    completion.wait_last(lambda b: b.data is True, timeout=90, what="arrival after two aborts")
    sent = goals.snapshot()
    assert len(sent) == 3 and len({g.goal_id.id for g in sent}) == 3, sent  # two aborted, one reached
    pose = sent[-1].goal.target_pose.pose
    assert (pose.position.x, pose.position.y) == pytest.approx((1.5, 2.0))  # the mapping's pose
    assert pose.orientation.z == pytest.approx(0.7068, abs=1e-3)


def test_region_localization_from_amcl_pose_does_not_chatter_on_a_border(ros):
    from geometry_msgs.msg import PoseWithCovarianceStamped
    from std_msgs.msg import Bool, String

    from ltl_stack.msg import PropositionValuation

    region = ros.record(ros.topic("localized_region"), String)
    top = ros.record(ros.topic("inputs/topLane_rc"), Bool)
    whole = ros.record(f"{ros.ns}/{ros.ns.strip('/')}_region_localization/valuation", PropositionValuation)
    ros.run("region_localization", f"_regions_file:={REGIONS}", "_source:=topic", "_hysteresis:=0.2",
            "_pose_type:=geometry_msgs/PoseWithCovarianceStamped", f"__ns:={ros.ns}")
    whole.wait_connected()  # latched: one connecting late would hear only the last valuation
    (x1, y1), (x2, y2) = shared_border(MAP.find("topLane"), MAP.find("rightLane"))
    mx, my = (x1 + x2) / 2, (y1 + y2) / 2
    length = ((x2 - x1) ** 2 + (y2 - y1) ** 2) ** 0.5
    nx, ny = -(y2 - y1) / length, (x2 - x1) / length
    if not MAP.find("topLane").contains(mx + 0.15 * nx, my + 0.15 * ny):
        nx, ny = -nx, -ny  # (nx, ny) points into topLane

    def pose(d: float) -> PoseWithCovarianceStamped:
        msg = PoseWithCovarianceStamped()
        msg.header.frame_id = "map"
        msg.pose.pose.position.x, msg.pose.pose.position.y = mx + d * nx, my + d * ny
        msg.pose.pose.orientation.w = 1.0
        return msg

    ros.publish(ros.topic("amcl_pose"), pose(0.5), latch=False)
    region.wait_last(lambda s: s.data == "topLane", what="topLane")
    for i in range(40):  # localization noise of 0.15 m across the border, then the robot drives on
        ros.publish(ros.topic("amcl_pose"), pose(0.15 if i % 2 else -0.15), latch=False)
    wait_for(lambda: (ros.publish(ros.topic("amcl_pose"), pose(-0.5), latch=False),
                      region.last().data == "rightLane")[1], 60, "rightLane after the crossing")
    assert changes([s.data for s in region.snapshot()]) == ["topLane", "rightLane"]
    top.wait_last(lambda b: b.data is False, what="topLane_rc false")
    # the region change as one message too: every region proposition, keyed by its topic
    whole.wait(lambda ms: len(ms) >= 2, what="two valuations on ~valuation")
    last = dict(zip(whole.last().keys, whole.last().values))  # noqa: B905
    assert last[ros.topic("inputs/rightLane_rc")] is True and sum(last.values()) == 1, last


def test_topic_predicate_sensor_sees_tag_7_within_1_5_m(ros):
    from geometry_msgs.msg import Pose
    from std_msgs.msg import Bool

    from ltl_stack.msg import TagDetection, TagDetectionArray

    seen = ros.record(ros.topic("inputs/seeTag7"), Bool)
    ros.run("topic_predicate_sensor", f"_topic:={ros.topic('camera/tags')}", "_type:=ltl_stack/TagDetectionArray",
            "_array:=detections", "_conditions:=['id == 7', 'pose.position within 1.5']",
            f"proposition:={ros.topic('inputs/seeTag7')}")

    def tags(*seen_tags: tuple[int, float]) -> TagDetectionArray:
        msg = TagDetectionArray()
        msg.header.frame_id = "camera"
        for tag_id, z in seen_tags:
            pose = Pose()
            pose.position.z, pose.orientation.w = z, 1.0
            msg.detections.append(TagDetection(id=tag_id, size=0.16, pose=pose))
        return msg

    seen.wait_last(lambda b: b.data is False, what="false before any detection")
    ros.publish(ros.topic("camera/tags"), tags((3, 1.0), (7, 2.5)))  # tag 7 too far, tag 3 near
    ros.publish(ros.topic("camera/tags"), tags((3, 1.0), (7, 1.2)))
    seen.wait_last(lambda b: b.data is True, what="tag 7 at 1.2 m")
    ros.publish(ros.topic("camera/tags"), tags((3, 0.5)))
    seen.wait_last(lambda b: b.data is False, what="tag 7 gone")
    values = changes([b.data for b in seen.snapshot()])
    assert values == [False, True, False], values


def test_topic_predicate_sensor_refuses_a_field_the_message_lacks(ros):
    node = ros.run("topic_predicate_sensor", "_topic:=/tags", "_type:=ltl_stack/TagDetectionArray",
                   "_array:=detections", "_conditions:=['distance < 1.5']")
    wait_for(lambda: not node.running(), 90, "the node to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert "ltl_stack/TagDetection has no field distance (fields there: id, size, pose)" in out, out
    assert "Traceback" not in out, out


@pytest.mark.parametrize("content, fragment", [
    (None, "no such bag file"),
    (b"#ROSBAG V2.0\nnot really a bag", "cannot read the bag"),
    (b"", "cannot read the bag"),
])
def test_check_run_refuses_a_bad_bag_in_one_line(tmp_path, content, fragment):
    from helpers import run_script

    config = REGIONS.parent
    bag = tmp_path / "run.bag"
    if content is not None:
        bag.write_bytes(content)
    done = run_script(["rosrun", "ltl_stack", "check_run", str(config / "clean_and_patrol.structuredslugs"),
                       str(config / "clean_and_patrol.yaml"), str(bag)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 2, done.stderr
    assert done.stderr.startswith(f"check_run: error: {bag}: {fragment}"), done.stderr
    assert len(done.stderr.splitlines()) == 1 and done.stdout == "", done.stderr


def test_map_markers_colour_the_robots_region_and_show_the_propositions(ros):
    from visualization_msgs.msg import MarkerArray

    from ltl_stack.msg import ControllerState
    from ltl_stack.ros.valuation import valuation_to_msg
    from ltl_stack.runtime.runs.map_view import CURRENT, HEADING

    markers = ros.record(ros.topic("markers"), MarkerArray)
    regions = ros.record(ros.topic("region_markers"), MarkerArray)
    ros.run("map_markers", f"_regions_file:={REGIONS}", f"__ns:={ros.ns}")
    markers.wait_last(lambda m: "waiting for the controller" in m.markers[-1].text, what="markers before a state")
    state = ControllerState(state_id=37, goal_index=4, running=True, mode="normal")
    state.inputs = valuation_to_msg({"object": False, "bottomLane_rc": True, "rightGround_rc": False})
    state.outputs = valuation_to_msg({"holdingObject": True, "rightGround": True})
    ros.publish(ros.topic("controller_executor/state"), state)
    last = markers.wait_last(lambda m: "sensing: bottomLane_rc" in m.markers[-1].text, what="the state shown")
    colour = {m.text: (m.color.r, m.color.g, m.color.b, m.color.a) for m in last.markers
              if m.ns == "highlight" and m.action == m.ADD}
    assert colour["bottomLane"] == pytest.approx(CURRENT) and colour["rightGround"] == pytest.approx(HEADING)
    assert set(colour) == {"bottomLane", "rightGround"}, colour  # the others are the static map's grey
    static = regions.wait_last(lambda m: True, what="the static map")
    labels = {m.text for m in static.markers if m.ns == "label"}
    assert labels == set(MAP.names()), labels
    assert "doing: holdingObject, rightGround" in last.markers[-1].text
    assert all(m.header.frame_id == "map" for m in last.markers)


def test_robots_with_prefixed_frames_have_their_own_tf_frames_on_one_tree(ros):
    """Two simulated robots with ~prefix_frames (multi-robot scenarios): odometry and tf
    under each robot's namespace, both below the one map frame; without the prefix both would be
    odom -> base_link."""
    from nav_msgs.msg import Odometry
    from tf2_msgs.msg import TFMessage

    tf = [f"/tf:={ros.topic('tf')}", f"/tf_static:={ros.topic('tf_static')}"]
    moving = ros.record(ros.topic("tf"), TFMessage)
    static = ros.record(ros.topic("tf_static"), TFMessage)
    odom = {r: ros.record(ros.topic(f"{r}/odom"), Odometry) for r in ("bot_a", "bot_b")}
    for r in odom:
        ros.run("sim_robot", "_mode:=holonomic", "_prefix_frames:=true", f"__ns:={ros.ns}/{r}", *tf,
                name=f"sim_robot_{r}")
    prefix = ros.ns.strip("/")
    for r, records in odom.items():
        last = records.wait_last(lambda m: True, what=f"{r}'s odometry")
        assert (last.header.frame_id, last.child_frame_id) == (f"{prefix}/{r}/odom", f"{prefix}/{r}/base_link")

    def edges(records):
        return {(t.header.frame_id, t.child_frame_id) for m in records.snapshot() for t in m.transforms}

    want = {(f"{prefix}/{r}/odom", f"{prefix}/{r}/base_link") for r in odom}
    wait_for(lambda: want <= edges(moving), 60, "each robot's odom -> base_link on tf")
    wait_for(lambda: {("map", f"{prefix}/{r}/odom") for r in odom} <= edges(static), 60, "map -> each odom")
    assert not {f for e in edges(moving) | edges(static) for f in e} & {"odom", "base_link"}


def test_map_markers_of_a_second_robot_show_only_its_labelled_text_on_its_own_row(ros):
    from visualization_msgs.msg import MarkerArray

    from ltl_stack.msg import ControllerState
    from ltl_stack.ros.valuation import valuation_to_msg
    from ltl_stack.runtime.runs.map_view import CURRENT

    first = ros.record(ros.topic("D/markers"), MarkerArray)
    second = ros.record(ros.topic("A/markers"), MarkerArray)
    ros.run("map_markers", f"_regions_file:={REGIONS}", "_label:=D", "_region_suffix:=_c", f"__ns:={ros.ns}/D",
            name="map_markers_D")
    ros.run("map_markers", f"_regions_file:={REGIONS}", "_label:=A", "_draw_regions:=false", "_text_row:=1",
            f"__ns:={ros.ns}/A", name="map_markers_A")
    state = ControllerState(state_id=3, goal_index=0, running=True, mode="normal")
    state.inputs = valuation_to_msg({"bottomLane_c": True})
    ros.publish(ros.topic("D/controller_executor/state"), state)
    d = first.wait_last(lambda m: m.markers[-1].text.startswith("D: state 3"), what="D's labelled text")
    a = second.wait_last(lambda m: m.markers[-1].text.startswith("A: waiting"), what="A's labelled text")
    assert len(a.markers) == 1 and a.markers[0].ns == "controller"  # no regions drawn twice
    assert a.markers[0].pose.position.y == pytest.approx(d.markers[-1].pose.position.y + 1.0)
    colour = {m.text: (m.color.r, m.color.g, m.color.b, m.color.a) for m in d.markers
              if m.ns == "highlight" and m.action == m.ADD}
    assert colour["bottomLane"] == pytest.approx(CURRENT)  # the region from its <region>_c input


def test_region_localization_publishes_its_valuation_before_it_knows_a_position(ros):
    """A listener of ~valuation that connects before the first position hears every region's initial
    value in one latched message: the executor holds the Bools of a connected ~valuation for it."""
    from ltl_stack.msg import PropositionValuation

    whole = ros.record(f"{ros.ns}/{ros.ns.strip('/')}_region_localization/valuation", PropositionValuation)
    ros.run("region_localization", f"_regions_file:={REGIONS}", "_source:=topic",
            "_pose_type:=geometry_msgs/PoseWithCovarianceStamped", f"__ns:={ros.ns}")  # no pose is ever sent
    whole.wait(lambda ms: ms and len(ms[-1].keys) == len(MAP.names()), what="every region in one valuation")
    last = dict(zip(whole.last().keys, whole.last().values))  # noqa: B905
    assert last[ros.topic("inputs/topLane_rc")] is False and not any(last.values()), last
