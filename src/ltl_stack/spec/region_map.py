"""Region names and adjacency from an LTLMoP ``.regions`` map, for the Structured English reader.

Only what a specification needs: which regions there are and which touch (the topology constraints
of thesis section 4.3 / [75]). The geometry used to drive a robot lives with the ROS adapters; this
module is self-contained so that ``ltl_stack.spec`` stays below every other layer.

A ``.regions`` file is a list of sections, each introduced by a line ``Name: # comment`` at column 0:

    Regions:      a JSON list of {"name", "type" (poly|rect), "position", "points", "size", ...}
    Obstacles:    region names, one per line (not places the robot can be)
    Transitions:  "a<TAB>b<TAB>face coordinates..." — a and b touch

Adjacency comes from ``Transitions:`` when the file has any; otherwise two regions touch when their
outlines share a stretch of border of positive length (what LTLMoP's editor writes into
``Transitions:``). The region called ``boundary`` is the workspace outline, not a region.
"""
from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field

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


def parse_region_map(text: str, file: str) -> RegionTopology:
    """The regions and adjacency of an LTLMoP ``.regions`` text; ``SpecError`` names file and line."""
    sections = _sections(text)
    if "Regions" not in sections:
        raise SpecError(file, 0, 0, "no 'Regions:' section (is this an LTLMoP .regions file?)")
    start, lines = sections["Regions"]
    body = "\n".join(lines)
    try:
        items = _load_json(body)
    except ValueError as e:
        line, message = e.args
        raise SpecError(file, start + line, 1, f"the Regions section is not valid JSON: {message}") from None
    if not isinstance(items, list):
        raise SpecError(file, start + 1, 1, "the Regions section must be a JSON list of regions")
    obstacles = {line.strip() for line in sections.get("Obstacles", (0, []))[1] if line.strip()}
    names: list[str] = []
    outlines: dict[str, list[Point]] = {}
    vertices = 0
    for index, item in enumerate(items):
        where = f"region #{index + 1} of the Regions section"
        if not isinstance(item, dict) or not isinstance(item.get("name"), str):
            raise SpecError(file, start, 1, f"{where} has no \"name\"")
        name = item["name"]
        if name == BOUNDARY or name in obstacles:
            continue
        if not _NAME.match(name):
            raise SpecError(file, start, 1, f"region name {name!r} is not a proposition name "
                                            "(letters, digits and '_', not starting with a digit)")
        if name in outlines:
            raise SpecError(file, start, 1, f"region {name!r} appears twice in the Regions section")
        outline = _outline(item, file, start, name)
        vertices += len(outline)
        if vertices > MAX_VERTICES or len(names) >= MAX_REGIONS:
            raise SpecError(file, start, 1, f"the map is too large for a specification (more than "
                                            f"{MAX_REGIONS} regions or {MAX_VERTICES} vertices)")
        names.append(name)
        outlines[name] = outline
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


def _load_json(body: str):
    """JSON with bounded nesting; ValueError(line, message) on any problem."""
    depth = deepest = 0
    in_string = escaped = False
    for char in body:  # refuse deep nesting before json's recursive parser sees it
        if in_string:
            if escaped:
                escaped = False
            elif char == "\\":
                escaped = True
            elif char == '"':
                in_string = False
            continue
        if char == '"':
            in_string = True
        elif char in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in "]}":
            depth -= 1
    if deepest > 20:
        raise ValueError(1, "nested deeper than a region list can be")
    try:
        return json.loads(body)
    except json.JSONDecodeError as e:
        raise ValueError(e.lineno, e.msg) from None
    except (RecursionError, ValueError) as e:
        raise ValueError(1, str(e)) from None


def _outline(item: dict, file: str, line: int, name: str) -> list[Point]:
    """The region's vertices in file coordinates (``position`` added)."""
    try:
        ox, oy = (float(v) for v in item.get("position", (0, 0)))
        if item.get("type", "poly") == "rect":
            w, h = (float(v) for v in item["size"])
            raw = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        else:
            raw = [(float(p[0]), float(p[1])) for p in item["points"]]
    except (KeyError, TypeError, ValueError, IndexError, OverflowError):
        raise SpecError(file, line, 1, f"region {name!r} has no valid \"points\" (or \"size\" for a rect)") from None
    points = [(ox + x, oy + y) for x, y in raw]
    if len(points) < 3 or not all(math.isfinite(c) for p in points for c in p):
        raise SpecError(file, line, 1, f"region {name!r} needs at least 3 finite vertices")
    return points


def _touch(a: list[Point], b: list[Point]) -> bool:
    """Do outlines ``a`` and ``b`` share a stretch of border (collinear, overlapping edges)?"""
    xs = [p[0] for p in a + b]
    ys = [p[1] for p in a + b]
    scale = max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
    tolerance = 1e-6 * scale
    ax0, ax1, ay0, ay1 = _box(a)
    bx0, bx1, by0, by1 = _box(b)
    if ax0 > bx1 + tolerance or bx0 > ax1 + tolerance or ay0 > by1 + tolerance or by0 > ay1 + tolerance:
        return False
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
            if min(length, max(t1, t2)) - max(0.0, min(t1, t2)) > tolerance:
                return True
    return False


def _box(points: list[Point]) -> tuple[float, float, float, float]:
    return (min(p[0] for p in points), max(p[0] for p in points),
            min(p[1] for p in points), max(p[1] for p in points))


def _edges(points: list[Point]) -> list[tuple[Point, Point]]:
    return [(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]
