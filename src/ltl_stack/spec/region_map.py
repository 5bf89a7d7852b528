"""Region names and adjacency from an LTLMoP ``.regions`` map, for the Structured English reader.

``read_region_file`` is the one reader of the file format: every region's outline and holes in file
coordinates, the obstacles, in file order. ``parse_region_map`` builds on it what a specification
needs: which regions there are and which touch (the topology constraints of thesis section 4.3 /
[75]). ``ltl_stack.runtime.regions`` builds on it the geometry that drives a robot (world
coordinates, point location, routes).

A ``.regions`` file is a list of sections, each introduced by a line ``Name: # comment`` at column 0:

    Regions:      a JSON list of {"name", "type" (poly|rect), "position", "points", "size", ...}
    Obstacles:    region names, one per line (not places the robot can be)
    Transitions:  "a<TAB>b<TAB>face coordinates..." — a and b touch

Adjacency comes from ``Transitions:`` when the file has any; otherwise two regions touch when their
outlines share a stretch of border of positive length (what LTLMoP's editor writes into
``Transitions:``). The region called ``boundary`` is the workspace outline, not a region.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from ltl_stack.errors import InputError
from ltl_stack.inputs import parse_json
from ltl_stack.spec.errors import SpecError

BOUNDARY = "boundary"
#: a map with more vertices than this is refused (the border test compares edges pairwise)
MAX_VERTICES = 2000
MAX_REGIONS = 200

_HEADER = re.compile(r"^([A-Za-z][A-Za-z0-9_]*):\s*(#.*)?$")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

Point = tuple[float, float]


@dataclass
class RegionTopology:
    """The regions of a map in file order and, for each, the regions it touches."""

    regions: list[str]
    adjacent: dict[str, set[str]] = field(default_factory=dict)
    source: str = "<regions>"

    def neighbours(self, name: str) -> set[str]:
        return self.adjacent.get(name, set())


def complete_topology(regions: list[str], source: str = "<declaration>") -> RegionTopology:
    """Every region touches every other (regions declared without a map)."""
    return RegionTopology(list(regions), {r: set(regions) - {r} for r in regions}, source)


@dataclass
class RegionOutline:
    """One entry of a map's Regions section, in file coordinates (``position`` added)."""

    name: str
    outline: list[Point]
    holes: list[list[Point]] = field(default_factory=list)


@dataclass
class RegionFile:
    """What a ``.regions`` file holds: every region (boundary and obstacles included), in file order."""

    regions: list[RegionOutline]
    obstacles: list[str]
    sections: dict[str, tuple[int, list[str]]]
    regions_line: int


def read_region_file(text: str, file: str) -> RegionFile:
    """Every region of an LTLMoP ``.regions`` text; ``SpecError`` names file and line.

    Bounded on hostile input: the Regions JSON goes through ``ltl_stack.inputs.parse_json`` (nesting,
    over-long integers), coordinates must be finite and every region needs three vertices."""
    sections = _sections(text)
    if "Regions" not in sections:
        raise SpecError(file, 0, 0, "no 'Regions:' section (is this an LTLMoP .regions file?)")
    start, lines = sections["Regions"]
    try:
        items = parse_json("\n".join(lines), file)
    except InputError as error:
        raise SpecError(file, start + error.line if error.line else 0, 0,
                        f"Regions section: {error.message}") from None
    if not isinstance(items, list):
        raise SpecError(file, start + 1, 0, "the Regions section must be a JSON list of regions")
    obstacles = [line.strip() for line in sections.get("Obstacles", (0, []))[1] if line.strip()]
    regions = [_region(item, index, file, start) for index, item in enumerate(items)]
    return RegionFile(regions, obstacles, sections, start)


def _region(item: object, index: int, file: str, line: int) -> RegionOutline:
    where = f"region #{index + 1} of the Regions section"
    if not isinstance(item, dict) or not isinstance(item.get("name"), str):
        raise SpecError(file, line, 0, f"{where} is not an object with a \"name\"")
    name = item["name"]
    try:
        ox, oy = (float(v) for v in item.get("position", (0, 0)))
        if item.get("type", "poly") == "rect":
            w, h = (float(v) for v in item["size"])
            raw = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        else:
            raw = [(float(p[0]), float(p[1])) for p in item["points"]]
        holes = [[(ox + float(p[0]), oy + float(p[1])) for p in hole] for hole in item.get("holeList", [])]
    except OverflowError:
        raise SpecError(file, line, 0, f"region {name!r}: a coordinate is not a finite number") from None
    except (KeyError, TypeError, ValueError, IndexError):
        raise SpecError(file, line, 0, f"region {name!r} has no valid \"points\" (or \"size\" for a rect, "
                                       "\"position\", \"holeList\")") from None
    outline = [(ox + x, oy + y) for x, y in raw]
    if not all(math.isfinite(c) for p in [*outline, *(q for hole in holes for q in hole)] for c in p):
        raise SpecError(file, line, 0, f"region {name!r}: a coordinate is not a finite number")
    if len(outline) < 3:
        raise SpecError(file, line, 0, f"region {name!r} has fewer than 3 vertices")
    return RegionOutline(name, outline, holes)


def parse_region_map(text: str, file: str) -> RegionTopology:
    """The regions and adjacency of an LTLMoP ``.regions`` text; ``SpecError`` names file and line."""
    content = read_region_file(text, file)
    sections, start = content.sections, content.regions_line
    obstacles = set(content.obstacles)
    names: list[str] = []
    outlines: dict[str, list[Point]] = {}
    vertices = 0
    for region in content.regions:
        name = region.name
        if name == BOUNDARY or name in obstacles:
            continue
        if not _NAME.match(name):
            raise SpecError(file, start, 1, f"region name {name!r} is not a proposition name "
                                            "(letters, digits and '_', not starting with a digit)")
        if name in outlines:
            raise SpecError(file, start, 1, f"region {name!r} appears twice in the Regions section")
        vertices += len(region.outline)
        if vertices > MAX_VERTICES or len(names) >= MAX_REGIONS:
            raise SpecError(file, start, 1, f"the map is too large for a specification (more than "
                                            f"{MAX_REGIONS} regions or {MAX_VERTICES} vertices)")
        names.append(name)
        outlines[name] = region.outline
    adjacent: dict[str, set[str]] = {n: set() for n in names}
    transitions = sections.get("Transitions")
    listed = [(n, line) for n, line in enumerate(transitions[1], start=transitions[0] + 1)
              if line.strip() and not line.lstrip().startswith("#")] if transitions else []
    if listed:
        for number, line in listed:
            parts = re.split(r"\t+|\s+", line.strip())
            if len(parts) < 2:
                raise SpecError(file, number, 1, "a transition names two regions: 'a<TAB>b ...'")
            a, b = parts[0], parts[1]
            if {a, b} & ({BOUNDARY} | obstacles):
                continue
            for region in (a, b):
                if region not in adjacent:
                    raise SpecError(file, number, 1, f"transition between unknown region {region!r}")
            if a != b:
                adjacent[a].add(b)
                adjacent[b].add(a)
    else:
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                if _touch(outlines[a], outlines[b]):
                    adjacent[a].add(b)
                    adjacent[b].add(a)
    return RegionTopology(names, adjacent, file)


def _sections(text: str) -> dict[str, tuple[int, list[str]]]:
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


def _touch(a: list[Point], b: list[Point]) -> bool:
    """Do outlines ``a`` and ``b`` share a stretch of border of positive length?"""
    xs = [p[0] for p in a + b]
    ys = [p[1] for p in a + b]
    tolerance = 1e-6 * max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
    ax0, ax1, ay0, ay1 = _box(a)
    bx0, bx1, by0, by1 = _box(b)
    if ax0 > bx1 + tolerance or bx0 > ax1 + tolerance or ay0 > by1 + tolerance or by0 > ay1 + tolerance:
        return False
    return shared_border(a, b, tolerance) is not None


def shared_border(a: list[Point], b: list[Point], tolerance: float = 1e-6) -> tuple[Point, Point] | None:
    """The longest stretch of border that outlines ``a`` and ``b`` share (collinear, overlapping
    edges, longer than ``tolerance``), or None if they do not touch."""
    best: tuple[Point, Point] | None = None
    best_length = tolerance
    for p1, p2 in _edges(a):
        ex, ey = p2[0] - p1[0], p2[1] - p1[1]
        length = math.hypot(ex, ey)
        if length <= tolerance:
            continue
        ux, uy = ex / length, ey / length
        for q1, q2 in _edges(b):
            if any(abs((q[0] - p1[0]) * uy - (q[1] - p1[1]) * ux) > tolerance for q in (q1, q2)):
                continue  # b's edge is not on the line of a's edge
            t1 = (q1[0] - p1[0]) * ux + (q1[1] - p1[1]) * uy
            t2 = (q2[0] - p1[0]) * ux + (q2[1] - p1[1]) * uy
            lo, hi = max(0.0, min(t1, t2)), min(length, max(t1, t2))
            if hi - lo > best_length:
                best_length = hi - lo
                best = ((p1[0] + ux * lo, p1[1] + uy * lo), (p1[0] + ux * hi, p1[1] + uy * hi))
    return best


def _box(points: list[Point]) -> tuple[float, float, float, float]:
    return (min(p[0] for p in points), max(p[0] for p in points),
            min(p[1] for p in points), max(p[1] for p in points))


def _edges(points: list[Point]) -> list[tuple[Point, Point]]:
    return [(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]
