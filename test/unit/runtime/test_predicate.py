"""Message predicates of topic_predicate_sensor, on AprilTag-style detections (test doubles)."""
from __future__ import annotations

from types import SimpleNamespace as Msg

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.propositions.predicate import Condition, MessagePredicate


def tag(tag_id: int, x: float, y: float = 0.0, z: float = 0.0) -> Msg:
    return Msg(id=tag_id, size=0.1, pose=Msg(position=Msg(x=x, y=y, z=z)))


def detections(*tags: Msg) -> Msg:
    return Msg(header=Msg(frame_id="camera"), detections=list(tags))


TAG7_NEAR = MessagePredicate(["id == 7", "pose.position within 1.5"], array="detections")


def test_tag_7_within_1_5_m():
    assert TAG7_NEAR.evaluate(detections(tag(3, 0.5), tag(7, 1.0, 1.0)))
    assert not TAG7_NEAR.evaluate(detections(tag(7, 1.2, 1.2)))  # 1.7 m away
    assert not TAG7_NEAR.evaluate(detections(tag(3, 0.5)))  # another tag
    assert not TAG7_NEAR.evaluate(detections())  # nothing seen


def test_one_element_must_meet_every_condition():
    """Tag 7 far and tag 3 near: neither alone meets both conditions."""
    assert not TAG7_NEAR.evaluate(detections(tag(7, 5.0), tag(3, 0.2)))


def test_plain_message_contains_and_strings():
    assert MessagePredicate(["data > 2"]).evaluate(Msg(data=3))
    assert MessagePredicate(["ids contains 4"]).evaluate(Msg(ids=[1, 4]))
    assert MessagePredicate(["label == cup"]).evaluate(Msg(label="cup"))
    assert not MessagePredicate(["label > 2"]).evaluate(Msg(label="cup"))  # no order between text and numbers
    assert MessagePredicate(["pose.position beyond 1"], "").evaluate(tag(1, 2.0))


@given(st.lists(st.tuples(st.integers(0, 9), st.floats(-3, 3), st.floats(-3, 3)), max_size=8))
def test_predicate_is_any_element_meeting_all_conditions(tags):
    msg = detections(*(tag(i, x, y) for i, x, y in tags))
    expected = any(i == 7 and (x * x + y * y) ** 0.5 <= 1.5 for i, x, y in tags)
    assert TAG7_NEAR.evaluate(msg) == expected


def test_bad_conditions_are_refused_naming_them():
    with pytest.raises(ValueError, match="'id = 7' is not '<field> <op> <value>'"):
        Condition.parse("id = 7")
    with pytest.raises(ValueError, match="within needs a finite distance"):
        Condition.parse("pose.position within far")
    with pytest.raises(ValueError, match="at least one condition"):
        MessagePredicate([])
    with pytest.raises(LookupError, match="no field 'distance'"):
        MessagePredicate(["distance < 1"]).evaluate(Msg(data=1))


def test_an_index_past_the_end_of_an_array_does_not_hold():
    """``detections[0].id == 7`` on an empty list is not "the last value" and no error: it does not hold."""
    first_is_7 = MessagePredicate(["detections[0].id == 7"])
    assert first_is_7.evaluate(detections(tag(7, 1.0)))
    assert not first_is_7.evaluate(detections())
    assert not MessagePredicate(["ranges[5] > 1"]).evaluate(Msg(ranges=[2.0, 3.0]))
    assert MessagePredicate(["ranges[-1] > 1"]).evaluate(Msg(ranges=[0.0, 3.0]))


#: (condition, ROS type of its field, that type's fields when a message, the error's fragment or None)
POINT = {"x": "float64", "y": "float64", "z": "float64"}
POSE = {"position": "geometry_msgs/Point", "orientation": "geometry_msgs/Quaternion"}
TYPE_TABLE = [
    ("pose.position within 1.5", "geometry_msgs/Point", POINT, None),
    ("linear beyond 0.1", "geometry_msgs/Vector3", POINT, None),
    ("pose within 1.5", "geometry_msgs/Pose", POSE, "field pose is a geometry_msgs/Pose, not a vector"),
    ("ranges within 1", "float32[]", None, "field ranges is a float32[], not a vector"),
    ("id within 1", "int32", None, "field id is a int32, not a vector"),
    ("ids contains 7", "int32[]", None, None),
    ("data contains 7", "uint8[]", None, None),
    ("id contains 7", "int32", None, "field id is a int32, not an array"),
    ("names contains 7", "string[]", None, "is a string; 7 is not a value of that kind"),
    ("id == 7", "int32", None, None),
    ("confidence >= 0.8", "float32", None, None),
    ("label == cup", "string", None, None),
    ("label == 7", "string", None, "quote a text value"),
    ("flag == true", "bool", None, None),
    ("id == seven", "int32", None, "field id is a int32; 'seven' is not a value of that kind"),
    ("pose == 1", "geometry_msgs/Pose", POSE, "field pose is a geometry_msgs/Pose, not a number, bool or string"),
    ("ids == 1", "int32[]", None, "field ids is a int32[], not a number"),
    ("stamp > 3", "time", None, "field stamp is a time, not a number"),
]


@pytest.mark.parametrize("text, type_name, fields, fragment", TYPE_TABLE, ids=[row[0] for row in TYPE_TABLE])
def test_conditions_are_checked_against_the_type_of_their_field(text, type_name, fields, fragment):
    error = Condition.parse(text).type_error(type_name, fields)
    if fragment is None:
        assert error is None, error
    else:
        assert error is not None and fragment in error, error
