"""ROS-free parts of the sensors: field paths, threshold comparison with hysteresis, pose reading."""
from __future__ import annotations

from types import SimpleNamespace as NS

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.propositions.sensing import (
    ThresholdComparator,
    check_field_path,
    extract_field,
    parse_field_path,
    pose_xy,
)


@pytest.mark.parametrize("path, expected", [
    ("data", ["data"]),
    ("pose.position.x", ["pose", "position", "x"]),
    ("ranges[3]", ["ranges", 3]),
    ("detections[0].id[1]", ["detections", 0, "id", 1]),
    ("ranges[-1]", ["ranges", -1]),
])
def test_parse_field_path(path, expected):
    assert parse_field_path(path) == expected, parse_field_path(path)


@pytest.mark.parametrize("path", ["", "a..b", "a[x]", "1abc", "a b"])
def test_parse_field_path_rejects_garbage(path):
    with pytest.raises(ValueError):
        parse_field_path(path)


def test_extract_field_follows_attributes_and_indices():
    msg = NS(detections=[NS(id=[4, 7])], ranges=[1.0, 2.0, 3.0])
    assert extract_field(msg, parse_field_path("detections[0].id[1]")) == 7
    assert extract_field(msg, parse_field_path("ranges[-1]")) == 3.0
    with pytest.raises(LookupError, match="no field 'pose'"):
        extract_field(msg, ["pose"])
    with pytest.raises(LookupError):
        extract_field(msg, ["ranges", 5])


def test_comparator_without_hysteresis_is_the_plain_comparison():
    got = [ThresholdComparator("<=", 1.0).update(v) for v in (0.5, 1.0, 1.5)]
    assert got == [True, True, False], got
    assert ThresholdComparator("==", 1).update(True) is True


def test_comparator_hysteresis_by_hand():
    c = ThresholdComparator(">", 10.0, hysteresis=1.0)
    got = [c.update(v) for v in (9.0, 10.5, 11.5, 10.5, 9.5, 8.9, 10.9, 11.1)]
    assert got == [False, False, True, True, True, False, False, True], got


@given(st.sampled_from([">", ">=", "<", "<="]), st.floats(-100, 100), st.floats(0, 10),
       st.lists(st.floats(-200, 200), min_size=1))
def test_comparator_agrees_with_plain_comparison_outside_the_band(op, threshold, h, values):
    c = ThresholdComparator(op, threshold, hysteresis=h)
    plain = ThresholdComparator(op, threshold)
    for v in values:
        got = c.update(v)
        if abs(v - threshold) > h:
            assert got == plain.update(v), (op, threshold, h, v)


def test_unknown_comparison_is_rejected():
    with pytest.raises(ValueError, match="unknown comparison '=>'"):
        ThresholdComparator("=>", 0.0)


def test_pose_xy_reads_the_usual_pose_messages():
    point = NS(x=1.0, y=2.0, z=0.0)
    assert pose_xy(NS(pose=NS(pose=NS(position=point)))) == (1.0, 2.0)  # Odometry
    assert pose_xy(NS(pose=NS(position=point))) == (1.0, 2.0)  # PoseStamped
    assert pose_xy(NS(position=point)) == (1.0, 2.0)  # Pose
    assert pose_xy(NS(x=3.0, y=4.0, theta=0.0)) == (3.0, 4.0)  # Pose2D
    with pytest.raises(LookupError):
        pose_xy(NS(data=True))


class _Range:
    __slots__ = ("header", "range", "ranges")

    def __init__(self):
        self.header = NS(stamp=NS(secs=0))
        self.range = 0.0
        self.ranges = []


@pytest.mark.parametrize("path, fragment", [
    ("nosuch", "has no field nosuch (fields there: header, range, ranges)"),
    ("header", "field header is a SimpleNamespace, not a number"),
    ("range[0]", "field range is not an array"),
])
def test_field_paths_the_message_type_does_not_have_are_refused(path, fragment):
    with pytest.raises(LookupError) as err:
        check_field_path(_Range(), parse_field_path(path), "sensor_msgs/Range")
    assert fragment in str(err.value), str(err.value)


@pytest.mark.parametrize("path", ["range", "ranges[3]", "header.stamp.secs"])
def test_field_paths_to_numbers_pass(path):
    check_field_path(_Range(), parse_field_path(path), "sensor_msgs/Range")
