"""What RViz shows (map_view): fills cover each region, colours say where the robot is and heads."""
from __future__ import annotations

from pathlib import Path

import pytest
from shapely.geometry import Polygon

from ltl_stack.runtime.propositions.regions import RegionMap
from ltl_stack.runtime.runs.map_view import (
    CURRENT,
    HEADING,
    IDLE,
    fill_triangles,
    region_from_inputs,
    region_shapes,
    valuation_text,
)

ROOT = Path(__file__).resolve().parents[3]
MAPS = sorted(ROOT.glob("config/*/*.regions"))


@pytest.mark.parametrize("path", MAPS, ids=[p.stem for p in MAPS])
def test_the_fill_triangles_cover_each_region_exactly(path):
    regions = RegionMap.load(path)
    for name in regions.names():
        region = regions.regions[name]
        polygon = Polygon(region.polygon, region.holes)
        area = sum(Polygon(t).area for t in fill_triangles(polygon))
        assert area == pytest.approx(polygon.area, rel=1e-6), name


def test_colours_say_current_and_heading():
    regions = RegionMap.load(ROOT / "config" / "clean_and_patrol" / "clean_and_patrol.regions")
    shapes = region_shapes(regions, "bottomLane", {"rightGround"})
    fills = {s.key: s.color for s in shapes if s.kind == "fill"}
    assert fills.pop("bottomLane") == CURRENT and fills.pop("rightGround") == HEADING
    assert set(fills.values()) == {IDLE}
    assert {s.key for s in shapes if s.kind == "outline"} == set(regions.names(include_boundary=True))
    assert sorted(s.text for s in shapes if s.kind == "label") == sorted(regions.names())


def test_text_and_region_from_inputs():
    regions = RegionMap.load(ROOT / "config" / "clean_and_patrol" / "clean_and_patrol.regions")
    assert region_from_inputs(regions, {"object": True, "leftLane_rc": True}) == "leftLane"
    assert region_from_inputs(regions, {"object": True}) is None
    text = valuation_text({"a": True, "b": False}, {"x": False}, 12, 3, 6, "recovering")
    assert text.splitlines() == ["state 12  goal 4/6  mode recovering", "sensing: a", "doing: -"]
