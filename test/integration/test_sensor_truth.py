"""Sensors never report what they cannot know, through the real nodes on a real master:
topic_predicate_sensor's conditions are checked against the message definition at start-up (one
[FATAL] line naming the field and its type, exit 2), and a condition that cannot be evaluated on a
message (an index past the end of an empty array) makes the proposition false, not the last value."""
from __future__ import annotations

from pathlib import Path

import pytest
from helpers import wait_for
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits


@pytest.fixture
def ros(request):
    return make_session(request)


#: (array, conditions, the [FATAL] line's fragment)
BAD_CONDITIONS = [
    ("detections", "['pose within 1.5']",
     "ltl_stack/TagDetection: condition 'pose within 1.5': field pose is a geometry_msgs/Pose, not a vector"),
    ("detections", "['id contains 7']", "condition 'id contains 7': field id is a int32, not an array"),
    ("detections", "['pose.position == 1']", "field pose.position is a geometry_msgs/Point, not a number"),
    ("", "['detections within 2']", "field detections is a ltl_stack/TagDetection[], not a vector"),
    ("header", "['id == 7']", "field header is a std_msgs/Header, not an array"),
]


@pytest.mark.parametrize("array, conditions, fragment", BAD_CONDITIONS, ids=[row[1] for row in BAD_CONDITIONS])
def test_a_condition_its_field_cannot_answer_is_one_fatal_line(ros, array, conditions, fragment):
    row = BAD_CONDITIONS.index((array, conditions, fragment))  # the test names share a node name's first 60 chars
    node = ros.run("topic_predicate_sensor", f"_topic:={ros.topic('tags')}", "_type:=ltl_stack/TagDetectionArray",
                   *([f"_array:={array}"] if array else []), f"_conditions:={conditions}", name=f"sensor_{row}")
    wait_for(lambda: not node.running(), 90, "the node to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert fragment in out, out
    assert "[FATAL]" in out and "Traceback" not in out, out


def test_an_element_that_is_gone_makes_the_proposition_false(ros):
    from std_msgs.msg import Bool

    from ltl_stack.msg import TagDetection, TagDetectionArray

    seen = ros.record(ros.topic("inputs/first7"), Bool)
    ros.run("topic_predicate_sensor", f"_topic:={ros.topic('tags')}", "_type:=ltl_stack/TagDetectionArray",
            "_conditions:=['detections[0].id == 7']", f"proposition:={ros.topic('inputs/first7')}")
    seen.wait_last(lambda b: b.data is False, what="false before any detection")
    ros.publish(ros.topic("tags"), TagDetectionArray(detections=[TagDetection(id=7)]))
    seen.wait_last(lambda b: b.data is True, what="tag 7 first")
    ros.publish(ros.topic("tags"), TagDetectionArray())
    seen.wait_last(lambda b: b.data is False, what="no detection: false, not the last value")


def map_file(tmp_path, *regions: tuple[str, list], name: str = "m.regions"):
    import json

    items = [{"name": n, "type": "poly", "position": [0, 0], "points": points} for n, points in regions]
    path = tmp_path / name
    path.write_text("Regions: # JSON\n" + json.dumps(items) + "\n")
    return path


ROOM = ("room", [[0, 0], [10, 0], [10, 10], [0, 10]])
DESK = ("desk", [[4, 4], [6, 4], [6, 6], [4, 6]])
HALL = ("hall", [[10, 0], [20, 0], [20, 10], [10, 10]])
#: (the map's regions, the [FATAL] line's fragment), the same for every node that reads a map
BAD_MAPS = [
    ([ROOM, HALL, ("room", [[30, 0], [40, 0], [40, 10]])], "region 'room' appears twice"),
    ([ROOM, HALL, ("line", [[0, 20], [5, 20], [10, 20]])], "region 'line' has zero area"),
    ([ROOM, HALL, ("bowtie", [[30, 0], [40, 10], [40, 0], [30, 10]])], "region 'bowtie': its outline crosses itself"),
]


@pytest.mark.parametrize("regions, fragment", BAD_MAPS, ids=[row[1] for row in BAD_MAPS])
@pytest.mark.parametrize("script", ["region_localization", "map_markers", "region_sensor"])
def test_every_map_reader_refuses_a_bad_map_in_one_fatal_line(ros, tmp_path, script, regions, fragment):
    path = map_file(tmp_path, *regions)
    row = BAD_MAPS.index((regions, fragment))
    node = ros.run(script, f"_regions_file:={path}", "_region:=hall", "_source:=topic", name=f"{script}_{row}")
    wait_for(lambda: not node.running(), 90, f"{script} to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert fragment in out and str(path) in out, out
    assert "[FATAL]" in out and "Traceback" not in out, out


def test_localization_reports_a_nested_region_from_one_timer(ros, tmp_path):
    """300 regions and a desk in a room: the desk is reported when the robot stands in it, and the
    node's threads do not grow with the regions (one republishing timer, not one per region)."""
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import String

    grid = [(f"cell{i}", [[100 + i, 0], [101 + i, 0], [101 + i, 1], [100 + i, 1]]) for i in range(300)]
    path = map_file(tmp_path, ROOM, DESK, HALL, *grid)
    region = ros.record(ros.topic("localized_region"), String)
    node = ros.run("region_localization", f"_regions_file:={path}", "_source:=topic",
                   f"_pose_topic:={ros.topic('pose')}", "_pose_type:=geometry_msgs/PoseStamped", "_hysteresis:=0.1",
                   f"_region_topic:={ros.topic('localized_region')}", f"_prefix:={ros.topic('inputs')}/")

    def pose(x: float, y: float) -> PoseStamped:
        msg = PoseStamped()
        msg.pose.position.x, msg.pose.position.y, msg.pose.orientation.w = x, y, 1.0
        return msg

    ros.publish(ros.topic("pose"), pose(1, 1))
    region.wait_last(lambda s: s.data == "room", what="room")
    ros.publish(ros.topic("pose"), pose(5, 5))
    region.wait_last(lambda s: s.data == "desk", what="the desk inside the room")
    threads = len(list(Path(f"/proc/{node.popen.pid}/task").iterdir()))
    assert threads < 100, threads  # one timer thread per region made it 300 and more
    assert "region desk lies inside region room" in node.output()


def test_map_markers_survive_a_controller_state_they_cannot_read(ros, tmp_path):
    from visualization_msgs.msg import MarkerArray

    from ltl_stack.msg import ControllerState, PropositionValuation

    path = map_file(tmp_path, ROOM, HALL)
    markers = ros.record(ros.topic("markers"), MarkerArray)
    node = ros.run("map_markers", f"_regions_file:={path}", f"__ns:={ros.ns}")
    markers.wait_last(lambda m: "waiting for the controller" in m.markers[-1].text, what="markers before a state")
    bad = ControllerState(state_id=5, inputs=PropositionValuation(keys=["a", "b"], values=[True]))
    ros.publish(ros.topic("controller_executor/state"), bad)
    wait_for(lambda: "cannot be read" in node.output(), 60, "the bad state logged")
    good = ControllerState(state_id=7, mode="normal", inputs=PropositionValuation(keys=["hall_rc"], values=[True]))
    ros.publish(ros.topic("controller_executor/state"), good)
    last = markers.wait_last(lambda m: "state 7" in m.markers[-1].text, what="the next good state")
    assert node.running() and "Traceback" not in node.output()
    assert [m.text for m in last.markers if m.ns == "highlight" and m.action == m.ADD] == ["hall"]


def test_a_threshold_sensor_whose_field_cannot_be_read_publishes_its_stale_value(ros):
    """``data[3] > 1``: true on [0, 0, 0, 5]; then a shorter array and a NaN are no readings: false
    (~stale_value), not the last value."""
    from std_msgs.msg import Bool, Float64MultiArray

    seen = ros.record(ros.topic("inputs/far"), Bool)
    ros.run("topic_threshold_sensor", f"_topic:={ros.topic('ranges')}", "_type:=std_msgs/Float64MultiArray",
            "_field:=data[3]", "_comparison:=gt", "_threshold:=1.0", f"proposition:={ros.topic('inputs/far')}")
    seen.wait_last(lambda b: b.data is False, what="false before any reading")
    ros.publish(ros.topic("ranges"), Float64MultiArray(data=[0.0, 0.0, 0.0, 5.0]))
    seen.wait_last(lambda b: b.data is True, what="5 > 1")
    ros.publish(ros.topic("ranges"), Float64MultiArray(data=[0.0]))
    seen.wait_last(lambda b: b.data is False, what="no element 3: the stale value")
    ros.publish(ros.topic("ranges"), Float64MultiArray(data=[0.0, 0.0, 0.0, 5.0]))
    seen.wait_last(lambda b: b.data is True, what="5 > 1 again")
    ros.publish(ros.topic("ranges"), Float64MultiArray(data=[0.0, 0.0, 0.0, float("nan")]))
    seen.wait_last(lambda b: b.data is False, what="NaN: the stale value")


def test_region_sensor_of_a_room_is_false_at_the_desk_inside_it(ros, tmp_path):
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import Bool

    path = map_file(tmp_path, ROOM, DESK, HALL)
    room = ros.record(ros.topic("inputs/room_rc"), Bool)
    ros.run("region_sensor", f"_regions_file:={path}", "_region:=room", f"_pose_topic:={ros.topic('pose')}",
            "_pose_type:=geometry_msgs/PoseStamped", f"proposition:={ros.topic('inputs/room_rc')}")
    pose = PoseStamped()
    pose.pose.position.x, pose.pose.position.y, pose.pose.orientation.w = 1.0, 1.0, 1.0
    ros.publish(ros.topic("pose"), pose)
    room.wait_last(lambda b: b.data is True, what="in the room")
    pose.pose.position.x, pose.pose.position.y = 5.0, 5.0
    ros.publish(ros.topic("pose"), pose)
    room.wait_last(lambda b: b.data is False, what="at the desk: in the desk, not the room")
