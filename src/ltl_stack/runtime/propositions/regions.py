"""Named polygon regions of a workspace, read from LTLMoP ``.regions`` files. ROS-free.

The file format is read by ``ltl_stack.spec.region_map.read_region_file`` (the reader the
Structured English front end uses for the topology): the ``Regions:`` section's JSON list of
``name``, ``type`` (``poly`` or ``rect``), ``position`` (an offset), ``points``, ``size`` and
``holeList`` (vertices relative to ``position``), and the ``Obstacles:`` names. The region named
``boundary`` is the outline of the whole workspace.

File coordinates are drawing pixels; ``RegionMap.load`` maps them to world metres with
``world = scale * file + (x_trans, y_trans)``, with y negated first when ``flip_y`` is set (the
drawing's y axis points down).

Every map is validated by ``ltl_stack.spec.region_map.check_regions`` (duplicate names, zero area and
self-crossing outlines refused, nesting reported in ``RegionMap.warnings``); where regions overlap the
smallest one holding a point is the region there (``region_at``).
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.errors import InputError, UserError
from ltl_stack.inputs import read_text
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.region_map import BOUNDARY, Point, read_region_file
from ltl_stack.spec.region_map import shared_border as _shared_outline_border


class RegionsError(UserError, ValueError):
    """A ``.regions`` file or a region name is wrong; the message names the file, line or region."""


def point_in_polygon(x: float, y: float, polygon: Sequence[Point]) -> bool:
    """Even-odd ray casting: is (x, y) inside ``polygon`` (vertices in order, not closed)?"""
    inside = False
    n = len(polygon)
    for i in range(n):
        x1, y1 = polygon[i]
        x2, y2 = polygon[(i + 1) % n]
        if (y1 > y) != (y2 > y):
            x_cross = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if x < x_cross:
                inside = not inside
    return inside


def polygon_area(polygon: Sequence[Point]) -> float:
    """Signed area (shoelace formula); positive for counter-clockwise vertices."""
    total = 0.0
    n = len(polygon)
    for i in range(n):
        x1, y1 = polygon[i]
        x2, y2 = polygon[(i + 1) % n]
        total += x1 * y2 - x2 * y1
    return total / 2.0


@dataclass
class Region:
    """One named region: an outer polygon minus holes, in world coordinates."""

    name: str
    polygon: list[Point]
    holes: list[list[Point]] = field(default_factory=list)

    def contains(self, x: float, y: float) -> bool:
        return point_in_polygon(x, y, self.polygon) and not any(
            point_in_polygon(x, y, hole) for hole in self.holes)

    def area(self) -> float:
        """Area of the outer polygon minus the holes."""
        return abs(polygon_area(self.polygon)) - sum(abs(polygon_area(hole)) for hole in self.holes)

    def centroid(self) -> Point:
        """Area centroid of the outer polygon (vertex mean for degenerate polygons)."""
        area = polygon_area(self.polygon)
        n = len(self.polygon)
        if abs(area) < 1e-12:
            return (sum(p[0] for p in self.polygon) / n, sum(p[1] for p in self.polygon) / n)
        cx = cy = 0.0
        for i in range(n):
            x1, y1 = self.polygon[i]
            x2, y2 = self.polygon[(i + 1) % n]
            cross = x1 * y2 - x2 * y1
            cx += (x1 + x2) * cross
            cy += (y1 + y2) * cross
        return (cx / (6.0 * area), cy / (6.0 * area))

    def interior_point(self) -> Point:
        """A point well inside the region: the centroid if inside, else the middle of the widest
        horizontal chord through the centroid's height (or through the middle height)."""
        cx, cy = self.centroid()
        if self.contains(cx, cy):
            return (cx, cy)
        ys = [p[1] for p in self.polygon]
        for y in (cy, (min(ys) + max(ys)) / 2.0):
            best = _widest_chord(self, y)
            if best is not None:
                return best
        raise RegionsError(f"region {self.name!r} has no interior point")


def _widest_chord(region: Region, y: float) -> Point | None:
    xs = []
    n = len(region.polygon)
    for i in range(n):
        x1, y1 = region.polygon[i]
        x2, y2 = region.polygon[(i + 1) % n]
        if (y1 > y) != (y2 > y):
            xs.append(x1 + (y - y1) * (x2 - x1) / (y2 - y1))
    xs.sort()
    best, width = None, 0.0
    for a, b in zip(xs[0::2], xs[1::2]):
        mid = ((a + b) / 2.0, y)
        if b - a > width and region.contains(*mid):
            best, width = mid, b - a
    return best


def normalize_name(name: str) -> str:
    """Region names compared loosely: ``rightLane`` matches ``right_lane``."""
    return name.replace("_", "").replace("-", "").replace(" ", "").lower()


@dataclass
class RegionMap:
    """The regions of one workspace, looked up by name or by position."""

    regions: dict[str, Region]
    obstacles: list[str] = field(default_factory=list)
    source: str = "<regions>"
    #: what a user should hear about the map (nested regions), one line each
    warnings: list[str] = field(default_factory=list)

    @classmethod
    def load(cls, path: str | Path, scale: float = 1.0, x_trans: float = 0.0, y_trans: float = 0.0,
             flip_y: bool = False) -> RegionMap:
        """Read an LTLMoP ``.regions`` file, mapping its coordinates to the world (see module doc)."""
        try:
            text = read_text(path, "regions file")
        except InputError as error:  # missing, a folder, binary, not UTF-8
            raise RegionsError(str(error)) from None
        return cls.parse(text, str(path), scale=scale, x_trans=x_trans, y_trans=y_trans, flip_y=flip_y)

    @classmethod
    def parse(cls, text: str, source: str = "<regions>", scale: float = 1.0, x_trans: float = 0.0,
              y_trans: float = 0.0, flip_y: bool = False) -> RegionMap:
        try:
            content = read_region_file(text, source)
        except SpecError as error:
            raise RegionsError(str(error)) from None

        def world(px: float, py: float) -> Point:
            return (scale * px + x_trans, scale * (-py if flip_y else py) + y_trans)

        regions = {r.name: Region(r.name, [world(*p) for p in r.outline], [[world(*p) for p in hole] for hole in r.holes])
                   for r in content.regions}
        return cls(regions=regions, obstacles=content.obstacles, source=source, warnings=content.warnings)

    def names(self, include_boundary: bool = False) -> list[str]:
        return [n for n in self.regions if include_boundary or n != BOUNDARY]

    def find(self, name: str) -> Region:
        """The region called ``name`` (exactly, else by ``normalize_name``); RegionsError if none."""
        if name in self.regions:
            return self.regions[name]
        matches = [r for n, r in self.regions.items() if normalize_name(n) == normalize_name(name)]
        if len(matches) == 1:
            return matches[0]
        known = ", ".join(sorted(self.regions))
        if matches:
            raise RegionsError(f"{self.source}: region name {name!r} is ambiguous (known: {known})")
        raise RegionsError(f"{self.source}: no region named {name!r} (known: {known})")

    def region_at(self, x: float, y: float, skip: Iterable[str] = ()) -> str | None:
        """Name of the smallest non-obstacle region (other than the boundary) that contains (x, y): a
        region nested in another is the region inside it (``check_regions``)."""
        skipped = {BOUNDARY, *self.obstacles, *skip}
        holding = [name for name, region in self.regions.items() if name not in skipped and region.contains(x, y)]
        if len(holding) < 2:
            return holding[0] if holding else None
        return min(holding, key=lambda name: self.regions[name].area())

    def route(self, start: Point, target: str, margin: float = 0.15) -> list[Point]:
        """Waypoints from ``start`` to a point well inside region ``target``.

        When the robot is in a region that shares a border with ``target``, the route crosses the
        middle of that border at right angles (a point ``margin`` inside each side, then the target's
        interior point), so between convex regions the robot never passes through a third region,
        as the region-adjacency assumptions of a specification expect. Otherwise it is one straight leg.
        """
        goal_region = self.find(target)
        here = self.region_at(*start)
        goal = goal_region.interior_point()
        if here is None or here == goal_region.name:
            return [goal]
        border = shared_border(self.regions[here], goal_region)
        if border is None:
            return [goal]
        (x1, y1), (x2, y2) = border
        mx, my = (x1 + x2) / 2.0, (y1 + y2) / 2.0
        length = math.hypot(x2 - x1, y2 - y1)
        nx, ny = -(y2 - y1) / length, (x2 - x1) / length
        step = min(margin, length / 4.0)
        if not self.regions[here].contains(mx + nx * step, my + ny * step):
            nx, ny = -nx, -ny
        return [(mx + nx * step, my + ny * step), (mx - nx * step, my - ny * step), goal]


def shared_border(a: Region, b: Region, tolerance: float = 1e-6) -> tuple[Point, Point] | None:
    """The longest stretch of boundary that regions ``a`` and ``b`` share, or None if they do not touch."""
    return _shared_outline_border(a.polygon, b.polygon, tolerance)


def distance(a: Point, b: Point) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])
