"""Region sensing from localization and region goals for navigation, ROS-free.

A real base knows where it is from localization (amcl's ``map`` -> ``base_link``, motion capture,
odometry), not from a region name. ``RegionTracker`` turns such poses into the region propositions
the specification expects (the thesis' ``R_rc`` inputs of Example 8, §3.6.2): exactly one region is
current at any time, and the current region changes only once the robot is ``hysteresis`` metres
past its border, so a robot standing on a border does not make the propositions chatter.
``region_goal`` gives the pose a navigation goal for a region aims at (``move_base``'s target pose).

The polygons are those of ``ltl_stack.runtime.propositions.regions.RegionMap`` (read by the Structured English
reader's map code), as shapely geometries.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from shapely import STRtree
from shapely.geometry import Point as ShapelyPoint
from shapely.geometry import Polygon

from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError


@dataclass(frozen=True)
class RegionPose:
    """A planar pose in the map frame: where a navigation goal for a region points."""

    x: float
    y: float
    yaw: float = 0.0

    def quaternion(self) -> tuple[float, float, float, float]:
        """(x, y, z, w) of the rotation by ``yaw`` about z."""
        return (0.0, 0.0, math.sin(self.yaw / 2.0), math.cos(self.yaw / 2.0))


def yaw_of(x: float, y: float, z: float, w: float) -> float:
    """Heading (rotation about z) of a quaternion."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def region_goal(regions: RegionMap, name: str, pose: Sequence[float] = ()) -> RegionPose:
    """The goal pose of region ``name``: ``pose`` ([x, y] or [x, y, yaw], from the mapping) when
    given, else a point well inside the region's polygon (its centre when that lies inside).
    RegionsError for an unknown region or a malformed pose."""
    region = regions.find(name)
    if pose:
        if len(pose) not in (2, 3) or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in pose):
            raise RegionsError(f"the pose of region {name!r} must be [x, y] or [x, y, yaw] (finite numbers), "
                               f"not {list(pose)!r}")
        return RegionPose(*(float(v) for v in pose))
    return RegionPose(*region.interior_point())


class RegionTracker:
    """Which region the robot is in, from its positions, with hysteresis (see the module doc).

    ``names`` are the regions tracked (default: every region but the boundary and the obstacles).
    Before the first position no region is current; after it, exactly one always is: a position in
    no region (a gap between polygons, a localization jump out of the map) keeps the region it was
    in, and a first position outside every region takes the nearest one. Where regions overlap the
    smallest one holding the position is current (a nested region is reported inside the one around
    it), as ``RegionMap.region_at`` and the map validation (``check_regions``) say.
    """

    def __init__(self, regions: RegionMap, names: Sequence[str] = (), hysteresis: float = 0.1) -> None:
        if not math.isfinite(hysteresis) or hysteresis < 0:
            raise ValueError(f"hysteresis must be a finite distance >= 0, not {hysteresis!r}")
        wanted = list(names) or [n for n in regions.names() if n not in regions.obstacles]
        if not wanted:
            raise RegionsError(f"{regions.source}: no region to track")
        self.shapes: dict[str, Polygon] = {}
        for name in wanted:
            region = regions.find(name)
            self.shapes[region.name] = Polygon(region.polygon, region.holes).buffer(0)
        self.hysteresis = float(hysteresis)
        self.current: str | None = None
        #: the map's warnings (nested regions), for the node to log
        self.warnings = list(regions.warnings)
        #: for each region, the smaller regions overlapping it (nested ones): entering one of them by
        #: more than the hysteresis leaves it (an R-tree finds them once, so an update stays cheap)
        self.smaller: dict[str, list[str]] = {name: [] for name in self.shapes}
        names = list(self.shapes)
        if len(names) > 1:
            shapes = [self.shapes[n] for n in names]
            big, small = STRtree(shapes).query(shapes, predicate="overlaps")
            for k, i in enumerate(big):
                if shapes[int(small[k])].area < shapes[int(i)].area:
                    self.smaller[names[int(i)]].append(names[int(small[k])])
            big, small = STRtree(shapes).query(shapes, predicate="contains")
            for k, i in enumerate(big):
                if int(i) != int(small[k]):
                    self.smaller[names[int(i)]].append(names[int(small[k])])

    def update(self, x: float, y: float) -> str | None:
        """Take a position; return the current region (None only before a finite position came)."""
        if not (math.isfinite(x) and math.isfinite(y)):
            return self.current
        point = ShapelyPoint(x, y)
        if self.current is not None and self.shapes[self.current].distance(point) <= self.hysteresis:
            deeper = [name for name in self.smaller[self.current] if self.shapes[name].covers(point)
                      and self.shapes[name].boundary.distance(point) >= self.hysteresis]
            if deeper:
                self.current = min(deeper, key=lambda name: self.shapes[name].area)
            return self.current
        inside = [name for name, shape in self.shapes.items() if shape.covers(point)]
        if inside:  # nested or overlapping regions: the smallest holding the point (as RegionMap.region_at)
            self.current = min(inside, key=lambda name: self.shapes[name].area)
        elif self.current is None:
            self.current = min(self.shapes, key=lambda name: self.shapes[name].distance(point))
        return self.current

    def valuation(self) -> dict[str, bool]:
        """Every tracked region's proposition: true for the current region only."""
        return {name: name == self.current for name in self.shapes}
