"""Region names and adjacency from an LTLMoP ``.regions`` map, for the Structured English reader.

``read_region_file`` is the one reader of the file format: every region's outline and holes in file
coordinates, the obstacles, in file order. ``parse_region_map`` builds on it what a specification
needs: which regions there are and which touch (the topology constraints of thesis section 4.3 /
[75]). ``ltl_stack.runtime.propositions.regions`` builds on it the geometry that drives a robot (world
coordinates, point location, routes).

A ``.regions`` file is a list of sections, each introduced by a line ``Name: # comment`` at column 0:

    Regions:      a JSON list of {"name", "type" (poly|rect), "position", "points", "size", ...}, or
                  (LTLMoP's older format) one region per line, tab-separated:
                  name, poly|rect, x, y, width, height, red, green, blue, then x y of each vertex
                  (relative to x, y; a rect has none)
    Obstacles:    region names, one per line (not places the robot can be)
    Transitions:  "a<TAB>b<TAB>face coordinates..." — a and b touch

Adjacency comes from ``Transitions:`` when the file has any; otherwise two regions touch when their
outlines share a stretch of border of positive length (what LTLMoP's editor writes into
``Transitions:``). The region called ``boundary`` (any case, as LTLMoP compares it) is the workspace
outline, not a region.

``decompose=True`` is LTLMoP's ``decompose`` compile option (``regions.py``/``parseLP.py``): the free
space inside the boundary that no region (and no obstacle) covers becomes regions too (``others``,
or ``others_1``, ``others_2``, … for each separate piece), and adjacency is recomputed from shared
borders of all of them (the file's ``Transitions:`` are ignored, as LTLMoP recomputes them). The
geometry is shapely's. LTLMoP also cuts regions into convex pieces; a region here stays one
proposition, which changes nothing a specification can say about it.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Tuple

from ltl_stack.errors import InputError
from ltl_stack.inputs import parse_json
from ltl_stack.spec.errors import SpecError

if TYPE_CHECKING:  # shapely (and numpy under it) load only when a map is read: not at every tool's start
    from shapely.geometry import Polygon

BOUNDARY = "boundary"
#: a map with more vertices or regions than this is refused (bounded input)
MAX_VERTICES = 100_000
MAX_REGIONS = 10_000
#: at most this many regions and derived areas are cut into pieces when regions overlap
MAX_OVERLAY = 300
#: and the pieces they are cut into (each area is tested against every piece so far)
MAX_PIECES = 2000
#: the name of the free space inside the boundary (``decompose``), as LTLMoP's RegionMapping calls it
FREE_SPACE = "others"

_HEADER = re.compile(r"^([A-Za-z][A-Za-z0-9_]*):\s*(#.*)?$")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")

Point = Tuple[float, float]


@dataclass
class RegionTopology:
    """The regions of a map in file order and, for each, the regions it touches."""

    regions: list[str]
    adjacent: dict[str, set[str]] = field(default_factory=dict)
    source: str = "<regions>"
    #: things a user should hear about the map (an isolated region), one line each
    warnings: list[str] = field(default_factory=list)
    #: every region touches every other (``adjacent`` is then not filled: n squared entries)
    complete: bool = False
    #: after an overlay (overlapping regions, ``between``/``near`` areas): each named area and the
    #: pieces (``regions``) it is made of, as LTLMoP's RegionMapping
    areas: dict[str, list[str]] = field(default_factory=dict)

    def neighbours(self, name: str) -> set[str]:
        if self.complete:
            return set(self.regions) - {name}
        return self.adjacent.get(name, set())

    def degree(self, name: str) -> int:
        """How many regions ``name`` touches (without building the set for a complete topology)."""
        return len(self.regions) - 1 if self.complete else len(self.adjacent.get(name, ()))


def complete_topology(regions: list[str], source: str = "<declaration>") -> RegionTopology:
    """Every region touches every other (regions declared without a map)."""
    return RegionTopology(list(regions), {}, source, complete=True)


@dataclass
class RegionOutline:
    """One entry of a map's Regions section, in file coordinates (``position`` added)."""

    name: str
    outline: list[Point]
    holes: list[list[Point]] = field(default_factory=list)
    #: the line of the file it was read from (the Regions header's line for the JSON format)
    line: int = 0


@dataclass
class RegionFile:
    """What a ``.regions`` file holds: every region (boundary and obstacles included), in file order."""

    regions: list[RegionOutline]
    obstacles: list[str]
    sections: dict[str, tuple[int, list[str]]]
    regions_line: int
    #: what ``check_regions`` says a user should hear (nested regions), one line each
    warnings: list[str] = field(default_factory=list)


def read_region_file(text: str, file: str) -> RegionFile:
    """Every region of an LTLMoP ``.regions`` text; ``SpecError`` names file and line.

    Bounded on hostile input: the Regions JSON goes through ``ltl_stack.inputs.parse_json`` (nesting,
    over-long integers), coordinates must be finite and every region needs three vertices."""
    sections = _sections(text)
    if "Regions" not in sections:
        raise SpecError(file, 0, 0, "no 'Regions:' section (is this an LTLMoP .regions file?)")
    start, lines = sections["Regions"]
    obstacles = [line.strip() for line in sections.get("Obstacles", (0, []))[1] if line.strip()]
    first = next((line for line in lines if line.strip()), "")
    if first and not first.lstrip().startswith(("[", "{")):  # LTLMoP's older, tab-separated format
        regions = [_old_region(line, number, file) for number, line in enumerate(lines, start=start + 1)
                   if line.strip()]
        return RegionFile(regions, obstacles, sections, start, check_regions(regions, obstacles, file))
    try:
        items = parse_json("\n".join(lines), file)
    except InputError as error:
        raise SpecError(file, start + error.line if error.line else 0, 0,
                        f"Regions section: {error.message}") from None
    if not isinstance(items, list):
        raise SpecError(file, start + 1, 0, "the Regions section must be a JSON list of regions")
    regions = [_region(item, index, file, start) for index, item in enumerate(items)]
    return RegionFile(regions, obstacles, sections, start, check_regions(regions, obstacles, file))


def check_regions(regions: list[RegionOutline], obstacles: list[str], file: str) -> list[str]:
    """The one validation of a map's regions, shared by every reader (the specification reader, the
    localization and sensing nodes, map_markers, the simulator), so that a map means the same everywhere.

    Refused (``SpecError`` naming file, line and region): two regions of one name (one would be lost),
    a region of zero area (it can never be the robot's), an outline that crosses itself (a bow-tie:
    which of its lobes is inside is not defined; LTLMoP's back-and-forth "spike" vertices, which
    enclose no area, are not crossings and are accepted). Accepted with a warning: a region that lies
    inside another (nesting). Where regions overlap, the smallest one holding a point is the region
    there, everywhere (``RegionMap.region_at``, ``RegionTracker``): a nested region is reported inside
    the one around it. Bounded work: shapely's vectorised predicates and an R-tree (n log n)."""
    import numpy
    import shapely
    from shapely.geometry import Polygon
    seen: dict[str, RegionOutline] = {}
    for region in regions:
        if region.name in seen:
            raise SpecError(file, region.line, 1, f"region {region.name!r} appears twice in the Regions section "
                                                  "(one of its outlines would be lost)")
        seen[region.name] = region
    shapes = [Polygon(r.outline) for r in regions]
    valid = shapely.is_valid(shapes) if shapes else numpy.zeros(0, dtype=bool)
    for index, region in enumerate(regions):
        shape, ok = shapes[index], bool(valid[index])
        signed = abs(_shoelace(region.outline))
        area = signed if ok else shapely.make_valid(shape).area
        minx, miny, maxx, maxy = shape.bounds
        extent = max(maxx - minx, maxy - miny)
        if area <= 1e-9 * extent * extent or area == 0.0:
            raise SpecError(file, region.line, 1, f"region {region.name!r} has zero area (its vertices lie on "
                                                  "one line): it can never hold the robot")
        if not ok and abs(area - signed) > 1e-6 * area:
            raise SpecError(file, region.line, 1, f"region {region.name!r}: its outline crosses itself (a "
                                                  "bow-tie); draw it as two regions or reorder its vertices")
    places = [i for i, r in enumerate(regions) if not is_boundary(r.name) and r.name not in set(obstacles)]
    if len(places) < 2:
        return []
    solid = [shapely.make_valid(shapes[i]) if not valid[i] else shapes[i] for i in places]
    outer, inner = shapely.STRtree(solid).query(solid, predicate="contains")
    pairs = sorted((int(a), int(inner[k])) for k, a in enumerate(outer) if a != inner[k])
    return [f"{file}: region {regions[places[b]].name} lies inside region {regions[places[a]].name}: there the "
            f"robot is in {regions[places[b]].name} (the smallest region holding a point is the region there)"
            for a, b in pairs]


def _shoelace(points: list[Point]) -> float:
    total = 0.0
    for i, (x1, y1) in enumerate(points):
        x2, y2 = points[(i + 1) % len(points)]
        total += x1 * y2 - x2 * y1
    return total / 2.0


def _old_region(line: str, number: int, file: str) -> RegionOutline:
    """One line of the older format: name, type, x, y, width, height, r, g, b, vertices (relative)."""
    fields = line.strip().split("\t") if "\t" in line else line.split()
    if len(fields) < 6:
        raise SpecError(file, number, 1, "a region line of the older format has at least name, type, x, y, "
                                         "width and height, separated by tabs")
    name = fields[0]
    try:
        numbers = [float(v) for v in fields[2:]]
    except ValueError:
        raise SpecError(file, number, 1, f"region {name!r}: expected numbers after its type") from None
    if not all(math.isfinite(v) for v in numbers):
        raise SpecError(file, number, 1, f"region {name!r}: a coordinate is not a finite number")
    ox, oy, w, h = numbers[:4]
    if fields[1].lower() == "rect":
        raw = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
    else:
        points = numbers[7:]
        if len(points) % 2:
            raise SpecError(file, number, 1, f"region {name!r}: its vertices need an x and a y each")
        raw = [(points[i], points[i + 1]) for i in range(0, len(points), 2)]
    outline = [(ox + x, oy + y) for x, y in raw]
    if len(outline) < 3:
        raise SpecError(file, number, 1, f"region {name!r} has fewer than 3 vertices")
    return RegionOutline(name, outline, line=number)


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
    return RegionOutline(name, outline, holes, line)


def is_boundary(name: str) -> bool:
    """LTLMoP compares the workspace outline's name without regard to case."""
    return name.lower() == BOUNDARY


def parse_region_map(text: str, file: str, decompose: bool = False,
                     derived: dict[str, tuple] | None = None) -> RegionTopology:
    """The regions and adjacency of an LTLMoP ``.regions`` text; ``SpecError`` names file and line.

    ``decompose``: the free space inside the boundary becomes regions and adjacency comes from shared
    borders (LTLMoP's ``decompose`` option). A region that touches no other gets a warning.
    ``derived`` (with ``decompose``): areas LTLMoP computes from the geometry, by name:
    ``("between", a, b)`` is the convex hull of a and b without them (``findRegionBetween``),
    ``("near", r, distance)`` r grown by the distance (``findRegionNear``). When regions overlap or
    such areas are asked for, the map is cut into pieces no two areas share (LTLMoP's
    ``checkOverLapping``): ``regions`` are then the pieces and ``areas`` says which pieces make up
    each region, derived area and ``others``.
    """
    content = read_region_file(text, file)
    sections, start = content.sections, content.regions_line
    obstacles = set(content.obstacles)
    names: list[str] = []
    outlines: dict[str, list[Point]] = {}
    vertices = 0
    boundary: RegionOutline | None = None
    blocked: list[RegionOutline] = []
    for region in content.regions:
        name = region.name
        if is_boundary(name):
            boundary = region
            continue
        if name in obstacles:
            blocked.append(region)
            continue
        if not _NAME.match(name):
            raise SpecError(file, start, 1, f"region name {name!r} is not a proposition name "
                                            "(letters, digits and '_', not starting with a digit)")
        vertices += len(region.outline)
        if vertices > MAX_VERTICES or len(names) >= MAX_REGIONS:
            raise SpecError(file, start, 1, f"the map is too large for a specification (more than "
                                            f"{MAX_REGIONS} regions or {MAX_VERTICES} vertices)")
        names.append(name)
        outlines[name] = region.outline
    holes: dict[str, list[list[Point]]] = {}  # of the free space's pieces (the regions inside it)
    transitions = sections.get("Transitions")
    listed = [(n, line) for n, line in enumerate(transitions[1], start=transitions[0] + 1)
              if line.strip() and not line.lstrip().startswith("#")] if transitions else []
    if decompose and boundary is not None and (derived or _overlapping(names, outlines)):
        return _overlay(file, boundary, names, outlines, derived or {}, start, blocked)
    if decompose and boundary is not None:
        pieces = _free_space(boundary, [r for r in content.regions if r is not boundary])
        for k, (piece, piece_holes) in enumerate(pieces, start=1):
            name = FREE_SPACE if len(pieces) == 1 else f"{FREE_SPACE}_{k}"
            while name in outlines:
                name += "_"
            names.append(name)
            outlines[name] = piece
            holes[name] = piece_holes
    adjacent: dict[str, set[str]] = {n: set() for n in names}
    if listed and not decompose:
        for number, line in listed:
            parts = re.split(r"\t+|\s+", line.strip())
            if len(parts) < 2:
                raise SpecError(file, number, 1, "a transition names two regions: 'a<TAB>b ...'")
            a, b = parts[0], parts[1]
            if is_boundary(a) or is_boundary(b) or {a, b} & obstacles:
                continue
            for region in (a, b):
                if region not in adjacent:
                    raise SpecError(file, number, 1, f"transition between unknown region {region!r}")
            if a != b:
                adjacent[a].add(b)
                adjacent[b].add(a)
    else:
        for a, b in _touching(names, outlines, holes):
            adjacent[a].add(b)
            adjacent[b].add(a)
    warnings = [f"{file}: region {n} touches no other region (the robot can never leave or reach it)"
                for n in names if not adjacent[n] and len(names) > 1]
    return RegionTopology(names, adjacent, file, [*content.warnings, *warnings])


def _overlapping(names: list[str], outlines: dict[str, list[Point]]) -> bool:
    shapes = [_polygon(outlines[n]) for n in names]
    if not _may_overlap(shapes):
        return False
    for i, j in _box_candidates(shapes):
        shape = shapes[i]
        scale = max(shape.bounds[2] - shape.bounds[0], shape.bounds[3] - shape.bounds[1], 1e-9)
        if shape.intersection(shapes[j]).area > 1e-6 * scale * scale:
            return True
    return False


def _may_overlap(shapes: list) -> bool:
    """False when no two shapes share area: their union (GEOS' cascaded union, about n log n) is as
    large as their areas together. Only then are pairs looked at one by one (``_box_candidates``:
    a pie's thin slices all meet at its centre and their boxes all overlap, n squared pairs)."""
    import shapely
    if len(shapes) < 2:
        return False
    total = sum(shape.area for shape in shapes)
    bounds = shapely.total_bounds(shapes)
    extent = max(bounds[2] - bounds[0], bounds[3] - bounds[1], 1e-9)
    return total - shapely.union_all(shapes).area > 1e-9 * extent * extent + 1e-9 * total


def _box_candidates(shapes: list, grow: float = 0.0) -> list[tuple[int, int]]:
    """Pairs ``i < j`` whose boxes (grown by ``grow``) meet, from an R-tree."""
    import shapely
    tree = shapely.STRtree(shapes)
    pairs = []
    for i, shape in enumerate(shapes):
        for j in tree.query(shape.buffer(grow) if grow else shape):
            if int(j) > i:
                pairs.append((i, int(j)))
    return pairs


def _overlay(file: str, boundary: RegionOutline, names: list[str], outlines: dict[str, list[Point]],
             derived: dict[str, tuple], line: int, blocked: list[RegionOutline]) -> RegionTopology:
    """Cut the boundary into pieces no two named areas share; each area is the union of its pieces.
    Obstacles are no place to be, but ``between``/``near`` may name them (LTLMoP's examples do).
    Each area may cut every piece so far, so the work is bounded by refusing large overlays."""
    from shapely.ops import unary_union
    if len(names) + len(derived) > MAX_OVERLAY:
        raise SpecError(file, line, 1, f"the map's regions overlap (or the spec names areas between or near "
                                       f"them): cutting more than {MAX_OVERLAY} areas into pieces is refused")
    polygons = {n: _polygon(outlines[n]) for n in names}
    areas: list[tuple[str, object]] = list(polygons.items())
    solid = {r.name: _polygon(r.outline, r.holes) for r in blocked}
    shape_of = {**solid, **polygons}
    for name, (kind, first, second) in derived.items():
        for region in (first,) if kind == "near" else (first, second):
            if region not in shape_of:
                raise SpecError(file, line, 1, f"'{name}' refers to {region!r}, which is not a region of the map")
        if kind == "between":
            a, b = shape_of[first], shape_of[second]
            shape = unary_union([a, b]).convex_hull.difference(a).difference(b)
        else:
            shape = shape_of[first].buffer(float(second), join_style="mitre").convex_hull
        areas.append((name, shape))
    space = _polygon(boundary.outline)
    if solid:
        space = space.difference(unary_union(list(solid.values())))
    scale = max(space.bounds[2] - space.bounds[0], space.bounds[3] - space.bounds[1], 1e-9)
    tiny = 1e-6 * scale * scale
    cells: list[tuple[object, frozenset[str]]] = [(g, frozenset()) for g in _parts(space) if g.area > tiny]
    for name, shape in areas:
        cut = []
        for cell, labels in cells:
            inside, outside = cell.intersection(shape), cell.difference(shape)
            cut += [(g, labels | {name}) for g in _parts(inside) if g.area > tiny]
            cut += [(g, labels) for g in _parts(outside) if g.area > tiny]
        cells = cut
        if len(cells) > MAX_PIECES:
            raise SpecError(file, line, 1, f"the map's overlapping regions make more than {MAX_PIECES} pieces; "
                                           "refused (draw them without overlaps)")
    taken = set(names) | set(derived)
    pieces: list[str] = []
    shapes: dict[str, object] = {}
    members: dict[str, list[str]] = {n: [] for n in [*names, *derived, FREE_SPACE]}
    for k, (cell, labels) in enumerate(cells, start=1):
        piece = f"p{k}"
        while piece in taken:
            piece += "_"
        pieces.append(piece)
        shapes[piece] = cell
        for label in labels or {FREE_SPACE}:
            members[label].append(piece)
    if not members[FREE_SPACE]:
        del members[FREE_SPACE]
    adjacent: dict[str, set[str]] = {p: set() for p in pieces}
    for a, b in _touching_shapes(pieces, shapes):
        adjacent[a].add(b)
        adjacent[b].add(a)
    warnings = [f"{file}: region {n} touches no other region (the robot can never leave or reach it)"
                for n in names if len(pieces) > 1 and all(not adjacent[p] - set(members[n]) for p in members[n])]
    return RegionTopology(pieces, adjacent, file, warnings, areas=members)


def _parts(shape) -> list[Polygon]:
    from shapely.geometry import Polygon
    return [g for g in getattr(shape, "geoms", [shape]) if isinstance(g, Polygon)]


def _polygon(points: list[Point], holes: list[list[Point]] | None = None) -> Polygon:
    from shapely.geometry import Polygon
    polygon = Polygon(points, holes or [])
    return polygon if polygon.is_valid else polygon.buffer(0)  # self-touching outlines: the area they enclose


def _free_space(boundary: RegionOutline, others: list[RegionOutline]) -> list[tuple[list[Point], list[list[Point]]]]:
    """The outlines and holes of the pieces of the boundary that no other region covers (LTLMoP's
    ``others``): with its holes a piece shares area with no region, and touches the ones on its
    border (edge to edge), not every region inside it."""
    from shapely.geometry import Polygon
    from shapely.ops import unary_union
    covered = unary_union([_polygon(r.outline, r.holes) for r in others]) if others else None
    space = _polygon(boundary.outline)
    if covered is not None:
        space = space.difference(covered)
    scale = max(space.bounds[2] - space.bounds[0], space.bounds[3] - space.bounds[1], 1e-9) if not space.is_empty \
        else 1.0
    pieces = [g for g in getattr(space, "geoms", [space]) if isinstance(g, Polygon) and g.area > 1e-9 * scale * scale]
    def ring(coords) -> list[Point]:
        return [(float(x), float(y)) for x, y in list(coords)[:-1]]
    return [(ring(p.exterior.coords), [ring(h.coords) for h in p.interiors]) for p in pieces]


def _touching(names: list[str], outlines: dict[str, list[Point]],
              holes: dict[str, list[list[Point]]] | None = None) -> list[tuple[str, str]]:
    """Pairs of regions whose outlines share a stretch of border of positive length (shapely; the
    candidates are edges on one line, ``_collinear_candidates``, so a map of n regions costs about
    n log n, not n squared)."""
    holes = holes or {}
    return _touching_shapes(names, {n: _polygon(outlines[n], holes.get(n)) for n in names})


def _touching_shapes(names: list[str], polygons: dict[str, object]) -> list[tuple[str, str]]:
    import shapely
    if len(names) < 2:
        return []
    shapes = [polygons[n] for n in names]
    bounds = shapely.total_bounds(shapes)
    tolerance = 1e-6 * max(bounds[2] - bounds[0], bounds[3] - bounds[1], 1e-9)
    candidates = _collinear_candidates(shapes, tolerance)
    if _may_overlap(shapes):  # shapes that share area touch without a common edge
        candidates |= set(_box_candidates(shapes, tolerance))
    pairs = []
    for i, j in sorted(candidates):
        shape = shapes[i]
        shared = shape.boundary.intersection(shapes[j].boundary)
        if shared.length > tolerance or shape.intersection(shapes[j]).area > tolerance * tolerance:
            pairs.append((names[i], names[j]))
    return pairs


def _collinear_candidates(shapes: list, tolerance: float) -> set[tuple[int, int]]:
    """Pairs ``i < j`` of shapes with edges on (nearly) one line whose spans overlap by more than
    ``tolerance``: the only way two outlines share a stretch of border. Edges are grouped by their
    line (direction and distance from the origin, on two grids half a cell apart, so lines closer
    than half a cell share a cell) and each group is swept in order along its line: about E log E
    for E edges, where an R-tree of whole outlines is n squared for a pie of thin slices."""
    cells: dict[tuple[int, int, int], list[tuple[float, float, int]]] = {}
    angle_step, offset_step = 1e-6, 1e3 * tolerance
    for index, shape in enumerate(shapes):
        for ring in _rings(shape):
            for (x0, y0), (x1, y1) in zip(ring[:-1], ring[1:]):
                dx, dy = x1 - x0, y1 - y0
                length = math.hypot(dx, dy)
                if length <= tolerance:
                    continue
                ux, uy = dx / length, dy / length
                if ux < 0 or (ux == 0 and uy < 0):
                    ux, uy = -ux, -uy
                angle, offset = math.atan2(uy, ux) / angle_step, (x0 * uy - y0 * ux) / offset_step
                t0, t1 = sorted((x0 * ux + y0 * uy, x1 * ux + y1 * uy))
                for grid in range(4):
                    shift_a, shift_o = 0.5 * (grid & 1), 0.5 * (grid >> 1)
                    key = (grid, math.floor(angle + shift_a), math.floor(offset + shift_o))
                    cells.setdefault(key, []).append((t0, t1, index))
    pairs: set[tuple[int, int]] = set()
    for spans in cells.values():
        if len(spans) < 2:
            continue
        spans.sort()
        active: list[tuple[float, int]] = []  # (end, shape) of the spans that may still overlap
        for t0, t1, index in spans:
            active = [(end, other) for end, other in active if end - t0 > tolerance]
            for _end, other in active:
                if other != index:
                    pairs.add((min(index, other), max(index, other)))
            active.append((t1, index))
    return pairs


def _rings(shape) -> list[list[Point]]:
    """The outer and inner rings of a polygon or of each part of a multi-polygon."""
    rings = []
    for part in _parts(shape):
        rings.append(list(part.exterior.coords))
        rings.extend(list(hole.coords) for hole in part.interiors)
    return rings


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


def _edges(points: list[Point]) -> list[tuple[Point, Point]]:
    return [(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]
