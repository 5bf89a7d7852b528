"""Region sensing from localization (RegionTracker) and region goals, on Example 8's map."""
from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from shapely import Point

from ltl_stack.runtime.propositions.localization import RegionPose, RegionTracker, region_goal, yaw_of
from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError

MAP = RegionMap.load(Path(__file__).resolve().parents[3] / "config" / "clean_and_patrol" / "clean_and_patrol.regions")


def test_first_position_picks_its_region_and_exactly_one_is_true():
    tracker = RegionTracker(MAP)
    assert tracker.current is None and not any(tracker.valuation().values())
    x, y = MAP.find("bottomLane").interior_point()
    assert tracker.update(x, y) == "bottomLane"
    assert [n for n, v in tracker.valuation().items() if v] == ["bottomLane"]
    assert set(tracker.valuation()) == set(MAP.names())


def test_crossing_a_border_switches_only_past_the_hysteresis():
    tracker = RegionTracker(MAP, hysteresis=0.2)
    start = MAP.find("topLane").interior_point()
    tracker.update(*start)
    seen = []
    legs = [start, *MAP.route(start, "rightLane")]  # across the middle of the border, as the robot drives
    for a, b in zip(legs, legs[1:]):
        for i in range(101):
            x, y = a[0] + (b[0] - a[0]) * i / 100, a[1] + (b[1] - a[1]) * i / 100
            seen.append(tracker.update(x, y))
            if seen[-1] == "rightLane":
                assert tracker.shapes["topLane"].distance(Point(x, y)) > 0.2
    assert [r for i, r in enumerate(seen) if i == 0 or r != seen[i - 1]] == ["topLane", "rightLane"]


@given(st.lists(st.floats(-0.09, 0.09), min_size=1, max_size=60))
def test_a_robot_jittering_on_a_border_does_not_chatter(offsets):
    """Localization noise smaller than the hysteresis around a border never changes the region."""
    tracker = RegionTracker(MAP, hysteresis=0.1)
    (x1, y1), (x2, y2) = _border("topLane", "rightLane")
    mx, my = (x1 + x2) / 2, (y1 + y2) / 2
    first = tracker.update(mx, my)
    for d in offsets:
        assert tracker.update(mx + d, my + d) == first
        assert sum(tracker.valuation().values()) == 1


@given(st.lists(st.tuples(st.floats(-2, 8), st.floats(-2, 6)), min_size=1, max_size=40),
       st.floats(0, 0.5))
def test_after_any_positions_exactly_one_region_is_true(points, hysteresis):
    tracker = RegionTracker(MAP, hysteresis=hysteresis)
    for x, y in points:
        tracker.update(x, y)
        assert sum(tracker.valuation().values()) == 1


def test_a_gap_or_a_jump_out_of_the_map_keeps_the_region():
    tracker = RegionTracker(MAP)
    tracker.update(*MAP.find("leftGround").interior_point())
    assert tracker.update(100.0, 100.0) == "leftGround"
    assert tracker.update(float("nan"), 1.0) == "leftGround"


def test_region_goal_is_inside_the_region_or_the_mapping_pose():
    for name in MAP.names():
        goal = region_goal(MAP, name)
        assert MAP.find(name).contains(goal.x, goal.y)
    assert region_goal(MAP, "right_lane", [1, 2, 1.5]) == RegionPose(1.0, 2.0, 1.5)
    q = RegionPose(0, 0, 1.2).quaternion()
    assert yaw_of(*q) == pytest.approx(1.2)
    with pytest.raises(RegionsError, match="no region named 'kitchen'"):
        region_goal(MAP, "kitchen")
    with pytest.raises(RegionsError, match=r"\[x, y\] or \[x, y, yaw\]"):
        region_goal(MAP, "topLane", [1])


def test_bad_hysteresis_and_unknown_region_are_refused():
    with pytest.raises(ValueError, match="hysteresis"):
        RegionTracker(MAP, hysteresis=float("nan"))
    with pytest.raises(RegionsError, match="no region named"):
        RegionTracker(MAP, ["nowhere"])


def _border(a: str, b: str):
    from ltl_stack.runtime.propositions.regions import shared_border

    border = shared_border(MAP.find(a), MAP.find(b))
    assert border is not None
    return border
