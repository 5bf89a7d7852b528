"""What RViz shows of a running controller, ROS-free: the region map, the robot's region, the region
it heads for, and the proposition values. ``ltl_stack.ros.markers`` turns these shapes into a
``visualization_msgs/MarkerArray``.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Tuple

from shapely.geometry import Polygon
from shapely.ops import triangulate

from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.propositions.regions import RegionMap
from ltl_stack.spec.region_map import BOUNDARY, Point
from ltl_stack.synthesis.automaton import goal_text

Color = Tuple[float, float, float, float]

OUTLINE: Color = (0.2, 0.2, 0.2, 1.0)
CURRENT: Color = (0.1, 0.7, 0.2, 0.55)  # the region the robot is in
HEADING: Color = (1.0, 0.6, 0.0, 0.35)  # a region the controller heads for
IDLE: Color = (0.6, 0.6, 0.6, 0.15)
TEXT: Color = (0.0, 0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Shape:
    """One thing to draw: an ``outline`` (closed line), a ``fill`` (triangles) or a ``label`` (text)."""

    kind: str
    key: str
    color: Color
    points: tuple[Point, ...] = ()
    text: str = ""


def fill_triangles(polygon: Polygon) -> list[tuple[Point, Point, Point]]:
    """Triangles covering ``polygon`` (holes left out): the Delaunay triangles of its vertices that
    lie inside it, enough for the convex and mildly concave regions of a workspace map."""
    triangles = []
    for triangle in triangulate(polygon):
        if polygon.contains(triangle.representative_point()):
            a, b, c = list(triangle.exterior.coords)[:3]
            triangles.append((a, b, c))
    return triangles


def region_shapes(regions: RegionMap, current: str | None, heading: set[str]) -> list[Shape]:
    """Outline, fill and name of every region (the boundary only outlined); the fill's colour says
    whether the robot is in it (``current``), heads for it (``heading``) or neither."""
    shapes = []
    places = set(regions.names())
    for name in regions.names(include_boundary=True):
        region = regions.regions[name]
        shapes.append(Shape("outline", name, OUTLINE, tuple([*region.polygon, region.polygon[0]])))
        if name not in places:
            continue
        color = CURRENT if name == current else HEADING if name in heading else IDLE
        polygon = Polygon(region.polygon, region.holes)
        shapes.append(Shape("fill", name, color, tuple(p for t in fill_triangles(polygon) for p in t)))
        shapes.append(Shape("label", name, TEXT, (region.interior_point(),), name))
    return shapes


def valuation_text(inputs: Mapping[str, bool], outputs: Mapping[str, bool], state: int, goal: int,
                   goals: int | None = None, mode: str = Mode.NORMAL.value, running: bool = True) -> str:
    """The controller's state in a few lines: state, goal (counted from 1, as every display does:
    ``synthesis.automaton.goal_text``), mode (the executor's: recovering, stale inputs, aborted, …; paused
    when it is not running), the true inputs and outputs."""
    true_inputs = ", ".join(p for p, v in inputs.items() if v) or "-"
    true_outputs = ", ".join(p for p, v in outputs.items() if v) or "-"
    return (f"state {state}  goal {goal_text(goal, goals)}  mode {mode_label(mode, running)}\n"
            f"sensing: {true_inputs}\ndoing: {true_outputs}")


def mode_label(mode: str, running: bool = True) -> str:
    """The executor's ``~state`` mode in words ("normal" when it reports none), "paused" when not running."""
    words = (mode or Mode.NORMAL.value).replace("_", " ")
    if running:
        return words
    return "paused" if words == Mode.NORMAL.value else f"{words}, paused"


def region_from_inputs(regions: RegionMap, inputs: Mapping[str, bool], suffix: str = "_rc") -> str | None:
    """The region whose ``R<suffix>`` input is true (the first such input), when the spec has such
    inputs. Work in the number of inputs, not of regions (a map may hold thousands)."""
    for key, value in inputs.items():
        name = key[:-len(suffix)] if suffix and key.endswith(suffix) else None
        if value and name and name in regions.regions and name != BOUNDARY:
            return name
    return None


def heading_regions(regions: RegionMap, outputs: Mapping[str, bool]) -> set[str]:
    """The regions the controller heads for: true outputs named as a region."""
    return {name for name, value in outputs.items() if value and name in regions.regions and name != BOUNDARY}
