"""Named polygon regions of a workspace, read from LTLMoP ``.regions`` files. ROS-free.

An LTLMoP ``.regions`` file is a list of sections, each introduced by a header line ``Name: # comment``
at column 0. The ``Regions:`` section holds a JSON list of objects with ``name``, ``type`` (``poly`` or
``rect``), ``position`` (an offset), ``points`` (vertices relative to ``position``), ``size`` and
``holeList`` (lists of vertices, also relative to ``position``). ``Obstacles:`` lists region names,
one per line. The region named ``boundary`` is the outline of the whole workspace.

File coordinates are drawing pixels; ``RegionMap.load`` maps them to world metres with
``world = scale * file + (x_trans, y_trans)``, with y negated first when ``flip_y`` is set (the
drawing's y axis points down).
"""
from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.errors import InputError, UserError
from ltl_stack.inputs import parse_json, read_text

Point = tuple[float, float]

BOUNDARY = "boundary"
_HEADER = re.compile(r"^([A-Za-z][A-Za-z0-9_]*):\s*(#.*)?$")


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
    for a, b in zip(xs[0::2], xs[1::2], strict=False):
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
        sections = _sections(text)
        if "Regions" not in sections:
            raise RegionsError(f"{source}: no 'Regions:' section (is this an LTLMoP .regions file?)")
        start_line, lines = sections["Regions"]
        try:
            items = parse_json("\n".join(lines), source)
        except InputError as error:  # invalid JSON, nested too deep, an over-long integer
            where = f"{source}:{start_line + error.line}" if error.line else source
            raise RegionsError(f"{where}: Regions section: {error.message}") from None
        if not isinstance(items, list):
            raise RegionsError(f"{source}:{start_line + 1}: Regions section must be a JSON list")

        def world(px: float, py: float) -> Point:
            return (scale * px + x_trans, scale * (-py if flip_y else py) + y_trans)

        regions: dict[str, Region] = {}
        for index, item in enumerate(items):
            try:
                if not isinstance(item, dict):
                    raise TypeError(f"expected an object, got {type(item).__name__}")
                name = str(item["name"])
                ox, oy = (float(v) for v in item.get("position", (0, 0)))
                if item.get("type", "poly") == "rect":
                    w, h = (float(v) for v in item["size"])
                    raw = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
                else:
                    raw = [(float(p[0]), float(p[1])) for p in item["points"]]
                holes_raw = [[(float(p[0]), float(p[1])) for p in hole] for hole in item.get("holeList", [])]
                points = [(ox, oy), *raw, *(p for hole in holes_raw for p in hole)]
                if not all(math.isfinite(c) for point in points for c in point):
                    raise ValueError("a coordinate is not a finite number")
            except (KeyError, TypeError, ValueError, IndexError, OverflowError) as error:
                raise RegionsError(f"{source}: region #{index} of the Regions section is malformed "
                                   f"({type(error).__name__}: {error})") from None
            if len(raw) < 3:
                raise RegionsError(f"{source}: region {name!r} has fewer than 3 vertices")
            regions[name] = Region(
                name=name,
                polygon=[world(ox + x, oy + y) for x, y in raw],
                holes=[[world(ox + x, oy + y) for x, y in hole] for hole in holes_raw],
            )
        obstacles = [line.strip() for line in sections.get("Obstacles", (0, []))[1] if line.strip()]
        return cls(regions=regions, obstacles=obstacles, source=source)

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
        """Name of the first non-obstacle region (other than the boundary) that contains (x, y)."""
        skipped = {BOUNDARY, *self.obstacles, *skip}
        for name, region in self.regions.items():
            if name not in skipped and region.contains(x, y):
                return name
        return None

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
    best: tuple[Point, Point] | None = None
    best_length = tolerance
    for p1, p2 in _edges(a.polygon):
        ex, ey = p2[0] - p1[0], p2[1] - p1[1]
        length = math.hypot(ex, ey)
        if length < tolerance:
            continue
        ux, uy = ex / length, ey / length
        for q1, q2 in _edges(b.polygon):
            # Both ends of b's edge must lie on the line through a's edge.
            if any(abs((q[0] - p1[0]) * uy - (q[1] - p1[1]) * ux) > tolerance for q in (q1, q2)):
                continue
            t1 = (q1[0] - p1[0]) * ux + (q1[1] - p1[1]) * uy
            t2 = (q2[0] - p1[0]) * ux + (q2[1] - p1[1]) * uy
            lo, hi = max(0.0, min(t1, t2)), min(length, max(t1, t2))
            if hi - lo > best_length:
                best_length = hi - lo
                best = ((p1[0] + ux * lo, p1[1] + uy * lo), (p1[0] + ux * hi, p1[1] + uy * hi))
    return best


def _edges(polygon: Sequence[Point]) -> list[tuple[Point, Point]]:
    return [(polygon[i], polygon[(i + 1) % len(polygon)]) for i in range(len(polygon))]


def _sections(text: str) -> dict[str, tuple[int, list[str]]]:
    """Split a .regions file into {section name: (header line number, body lines)}."""
    sections: dict[str, tuple[int, list[str]]] = {}
    current: list[str] | None = None
    for number, line in enumerate(text.splitlines(), start=1):
        match = _HEADER.match(line)
        if match:
            current = []
            sections[match.group(1)] = (number, current)
        elif current is not None:
            current.append(line)
    return sections


def distance(a: Point, b: Point) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])
