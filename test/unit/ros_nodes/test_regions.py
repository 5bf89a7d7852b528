"""LTLMoP .regions reading and polygon geometry (ROS-free)."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.runtime.propositions.regions import Region, RegionMap, RegionsError, point_in_polygon

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from helpers import require_shared  # noqa: E402

SQUARE = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
L_SHAPE = [(0.0, 0.0), (3.0, 0.0), (3.0, 1.0), (1.0, 1.0), (1.0, 3.0), (0.0, 3.0)]

SMALL = """# comment
Background: # Relative path of background image file
None

Obstacles: # Names of regions to treat as obstacles
pillar

Regions: # Stored as JSON string
[
  {"name": "boundary", "type": "rect", "position": [0, 0], "size": [100, 50], "points": []},
  {"name": "left", "type": "poly", "position": [0, 0], "points": [[0, 0], [50, 0], [50, 50], [0, 50]],
   "holeList": [[[10, 10], [20, 10], [20, 20], [10, 20]]]},
  {"name": "right_room", "type": "rect", "position": [50, 0], "size": [50, 50]},
  {"name": "pillar", "type": "rect", "position": [70, 20], "size": [5, 5]}
]

Transitions: # Region 1 Name, Region 2 Name, faces
left\tright_room\t50\t0\t50\t50
"""


def test_point_in_polygon_by_hand():
    assert point_in_polygon(1, 1, SQUARE)
    assert not point_in_polygon(3, 1, SQUARE)
    assert point_in_polygon(0.5, 2.5, L_SHAPE)
    assert not point_in_polygon(2, 2, L_SHAPE)


@given(st.floats(-10, 10), st.floats(-10, 10), st.floats(0.1, 5), st.floats(0.1, 5),
       st.floats(-20, 20), st.floats(-20, 20))
def test_point_in_rectangle_matches_the_bounds(x0, y0, w, h, px, py):
    rect = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    strictly_in = x0 < px < x0 + w and y0 < py < y0 + h
    strictly_out = not (x0 <= px <= x0 + w and y0 <= py <= y0 + h)
    if strictly_in or strictly_out:
        assert point_in_polygon(px, py, rect) == strictly_in


def test_parse_a_small_file_with_rect_hole_obstacle_and_transform():
    regions = RegionMap.parse(SMALL, "small.regions", scale=0.1, x_trans=1.0, y_trans=-1.0)
    assert regions.names() == ["left", "right_room", "pillar"], regions.names()
    assert regions.obstacles == ["pillar"]
    assert regions.region_at(1.0 + 0.3, -1.0 + 0.3) == "left"
    assert regions.region_at(1.0 + 1.5, -1.0 + 1.5) is None  # in the hole of left
    assert regions.region_at(1.0 + 7.2, -1.0 + 2.2) == "right_room"  # the pillar is an obstacle
    assert regions.find("rightRoom").name == "right_room"


def test_flip_y_negates_file_y():
    regions = RegionMap.parse(SMALL, scale=1.0, flip_y=True)
    assert regions.region_at(25.0, -5.0) == "left"
    assert regions.region_at(25.0, 5.0) is None


@pytest.mark.parametrize("text, message", [
    ("Background:\nNone\n", "small.regions: no 'Regions:' section"),
    ("Regions:\n[\n  {\"name\": \"a\",\n  oops\n]\n", "small.regions:4: Regions section: invalid JSON"),
    ("Regions:\n" + "[" * 100000 + "\n", "small.regions:2: Regions section: nested more than 100 levels deep"),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[" + "9" * 5000 + ", 0]]}]\n",
     "small.regions: Regions section: invalid JSON value"),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[1" + "0" * 400 + ", 0], [1, 0], [0, 1]]}]\n",
     "small.regions:1: region 'a': a coordinate is not a finite number"),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[NaN, 0], [1, 0], [0, 1]]}]\n", "not a finite number"),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[0, 0], [1e999, 0], [0, 1]]}]\n", "not a finite number"),
    ("Regions:\n[\"a\"]\n", "small.regions:1: region #1 of the Regions section is not an object with a \"name\""),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[0, 0], [1, 1]]}]\n", "region 'a' has fewer than 3 vertices"),
    ("Regions:\n[{\"points\": []}]\n", "small.regions:1: region #1 of the Regions section is not an object"),
    ("Regions:\n[{\"name\": \"a\", \"points\": [[0, 0], [1, 0], [0, 1]], \"holeList\": [[[0, \"x\"]]]}]\n",
     "small.regions:1: region 'a' has no valid \"points\""),
])
def test_bad_files_give_one_clear_error(text, message):
    with pytest.raises(RegionsError) as err:
        RegionMap.parse(text, "small.regions")
    assert message in str(err.value), str(err.value)


def test_unknown_region_lists_the_known_ones():
    regions = RegionMap.parse(SMALL, "small.regions")
    with pytest.raises(RegionsError, match=r"small.regions: no region named 'kitchen' \(known: boundary, left"):
        regions.find("kitchen")


def test_missing_file_names_it(tmp_path):
    with pytest.raises(RegionsError, match="nothere.regions: no such file"):
        RegionMap.load(tmp_path / "nothere.regions")
    binary = tmp_path / "b.regions"
    binary.write_bytes(b"Regions:\n[\x00]\n")
    with pytest.raises(RegionsError) as err:
        RegionMap.load(binary)
    assert str(err.value) == f"{binary}:2: not a text regions file: it holds a NUL byte", err.value
    assert err.value.code == 2


@pytest.mark.parametrize("spec, name, count", [
    ("move_group_and_move_base", "lab_loop.regions", 6),
    ("firefighting", "floorplan.regions", 6),
])
def test_real_ltlmop_files_have_interior_points_inside_exactly_their_region(spec, name, count):
    regions = RegionMap.load(require_shared("specs", spec, name))
    usable = [n for n in regions.names() if n not in regions.obstacles]
    assert len(usable) == count, usable
    for region_name in usable:
        x, y = regions.find(region_name).interior_point()
        assert regions.region_at(x, y) == region_name, (region_name, x, y)


def test_interior_point_of_a_concave_region_is_inside():
    region = Region("l", [(0.0, 0.0), (10.0, 0.0), (10.0, 1.0), (1.0, 1.0), (1.0, 10.0), (0.0, 10.0)])
    cx, cy = region.centroid()
    assert not region.contains(cx, cy), (cx, cy)  # the centroid of this L is outside it
    assert region.contains(*region.interior_point())


def _clean_and_patrol_map():
    from pathlib import Path

    from ltl_stack.runtime.propositions.regions import RegionMap

    return RegionMap.load(Path(__file__).resolve().parents[3] / "config/clean_and_patrol/clean_and_patrol.regions")


def test_shared_border_of_touching_and_separate_regions():
    from ltl_stack.runtime.propositions.regions import shared_border

    regions = _clean_and_patrol_map().regions
    got = shared_border(regions["topLane"], regions["rightLane"])
    assert got is not None and sorted(got) == [(5.0, 3.0), (6.0, 3.0)], got
    got = shared_border(regions["leftGround"], regions["rightGround"])
    assert got is not None and sorted(got) == [(3.0, 1.0), (3.0, 3.0)], got
    assert shared_border(regions["topLane"], regions["bottomLane"]) is None


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(["topLane", "rightLane", "bottomLane", "leftLane", "leftGround", "rightGround"]),
       st.sampled_from(["topLane", "rightLane", "bottomLane", "leftLane", "leftGround", "rightGround"]),
       st.floats(0.05, 0.95), st.floats(0.05, 0.95))
def test_route_to_an_adjacent_region_never_passes_through_a_third(start_region, goal_region, fx, fy):
    import math

    from ltl_stack.runtime.propositions.regions import shared_border

    regions = _clean_and_patrol_map()
    xs = [p[0] for p in regions.regions[start_region].polygon]
    ys = [p[1] for p in regions.regions[start_region].polygon]
    start = (min(xs) + fx * (max(xs) - min(xs)), min(ys) + fy * (max(ys) - min(ys)))
    route = regions.route(start, goal_region)
    assert regions.region_at(*route[-1]) == goal_region, route
    adjacent = shared_border(regions.regions[start_region], regions.regions[goal_region]) is not None
    if start_region == goal_region or not adjacent:
        assert len(route) == 1, route
        return
    seen = []
    for a, b in zip([start, *route], route):
        n = max(2, int(math.dist(a, b) / 0.01))
        for i in range(n + 1):
            x, y = a[0] + (b[0] - a[0]) * i / n, a[1] + (b[1] - a[1]) * i / n
            here = regions.region_at(x, y)
            if here and (not seen or seen[-1] != here):
                seen.append(here)
    assert seen == [start_region, goal_region], (start, route, seen)
