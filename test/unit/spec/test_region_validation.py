"""One validation of region maps (``check_regions``), the same through every reader: the spec reader's
topology (``parse_region_map``), the runtime map of localization, sensing and map_markers
(``RegionMap``) and the localization's tracker. Duplicate names, zero area and bow-ties are refused
naming the region; a nested region is reported (a warning) and is the region inside the one around it."""
from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.propositions.localization import RegionTracker
from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.region_map import parse_region_map

SQUARE_A = [[0, 0], [4, 0], [4, 4], [0, 4]]
SQUARE_B = [[4, 0], [8, 0], [8, 4], [4, 4]]


def regions_text(*regions: tuple[str, list]) -> str:
    items = [{"name": name, "type": "poly", "position": [0, 0], "points": points} for name, points in regions]
    return "Regions: # JSON\n" + json.dumps(items) + "\n"


#: (the map's regions, the error's fragment)
REFUSED = [
    ([("a", SQUARE_A), ("b", SQUARE_B), ("a", [[10, 10], [12, 10], [12, 12]])], "region 'a' appears twice"),
    ([("a", SQUARE_A), ("flat", [[0, 5], [2, 5], [4, 5]])], "region 'flat' has zero area"),
    ([("a", SQUARE_A), ("dot", [[5, 5], [5, 5], [5, 5]])], "region 'dot' has zero area"),
    ([("a", SQUARE_A), ("bowtie", [[10, 0], [14, 4], [14, 0], [10, 4]])], "region 'bowtie': its outline crosses itself"),
]


def readers(text: str):
    """What each reader makes of the map: the spec reader, the runtime map, the tracker."""
    return [lambda: parse_region_map(text, "m.regions"), lambda: RegionMap.parse(text, "m.regions"),
            lambda: RegionTracker(RegionMap.parse(text, "m.regions"))]


@pytest.mark.parametrize("regions, fragment", REFUSED, ids=[row[1] for row in REFUSED])
def test_every_reader_refuses_the_same_maps_naming_the_region(regions, fragment):
    for read in readers(regions_text(*regions)):
        with pytest.raises((SpecError, RegionsError)) as caught:
            read()
        assert fragment in str(caught.value) and "m.regions" in str(caught.value), caught.value


def test_a_spiky_outline_that_encloses_no_crossing_is_accepted():
    """LTLMoP's editor writes back-and-forth vertices (a spike of zero width): not a bow-tie."""
    spiky = [[0, 0], [4, 0], [4, 2], [6, 2], [4, 2], [4, 4], [0, 4]]
    regions = RegionMap.parse(regions_text(("a", spiky), ("b", [[4, 4], [8, 4], [8, 8], [4, 8]])), "m.regions")
    assert regions.region_at(2, 2) == "a"


NESTED = regions_text(("room", [[0, 0], [10, 0], [10, 10], [0, 10]]), ("desk", [[4, 4], [6, 4], [6, 6], [4, 6]]),
                      ("hall", [[10, 0], [20, 0], [20, 10], [10, 10]]))


def test_a_nested_region_is_reported_and_is_the_region_inside_the_other_everywhere():
    warning = "region desk lies inside region room"
    assert any(warning in w for w in parse_region_map(NESTED, "m.regions").warnings)
    regions = RegionMap.parse(NESTED, "m.regions")
    assert any(warning in w for w in regions.warnings)
    assert regions.region_at(5, 5) == "desk"
    assert regions.region_at(1, 1) == "room"
    tracker = RegionTracker(regions, hysteresis=0.1)
    assert tracker.update(1, 1) == "room"
    assert tracker.update(5, 5) == "desk"  # walking into the desk from the room
    assert tracker.update(6.05, 5) == "desk"  # within the hysteresis of its border
    assert tracker.update(8, 5) == "room"
    assert RegionTracker(regions).update(5, 5) == "desk"  # a first position


@given(st.floats(0.01, 9.99), st.floats(0.01, 9.99))
def test_the_tracker_and_the_map_agree_away_from_borders(x, y):
    regions = RegionMap.parse(NESTED, "m.regions")
    near_border = min(abs(x - 4), abs(x - 6), abs(y - 4), abs(y - 6)) < 0.2
    if not near_border:
        assert RegionTracker(regions, hysteresis=0.1).update(x, y) == regions.region_at(x, y)
