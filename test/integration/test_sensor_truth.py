"""Sensors never report what they cannot know, through the real nodes on a real master:
topic_predicate_sensor's conditions are checked against the message definition at start-up (one
[FATAL] line naming the field and its type, exit 2), and a condition that cannot be evaluated on a
message (an index past the end of an empty array) makes the proposition false, not the last value."""
from __future__ import annotations

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
