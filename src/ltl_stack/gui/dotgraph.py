"""Graphs the panels draw, as Graphviz DOT, and their layout by the ``dot`` program (no Qt here).

The panels build a ``DotGraph`` (nodes with safe ids ``n0, n1, ...`` and a label, edges), lay it out with
Graphviz and draw the result: with ``qt_dotgraph`` (as rqt_graph does) from ``layout_dot``'s laid-out DOT
when that package is importable, else with the panel's own items from ``layout_plain``'s parsed
``-Tplain`` output. Both keep the node ids, so a view can highlight a node without a new layout.
"""
from __future__ import annotations

import shlex
import shutil
import subprocess
from collections import deque
from dataclasses import dataclass, field

LAYOUT_TIMEOUT = 60.0


class GraphvizError(RuntimeError):
    """Graphviz is missing, failed, or took longer than the timeout."""


@dataclass
class DotNode:
    id: str
    label: str
    shape: str = "box"
    color: str = "black"
    tooltip: str = ""


@dataclass
class DotEdge:
    source: str
    target: str
    label: str = ""
    color: str = "black"


@dataclass
class DotGraph:
    """A directed graph to draw; ``key`` maps the caller's names (state ids, vertex names) to node ids."""

    name: str = "g"
    rankdir: str = "LR"
    nodes: list[DotNode] = field(default_factory=list)
    edges: list[DotEdge] = field(default_factory=list)
    key: dict[object, str] = field(default_factory=dict)

    def add_node(self, key: object, label: str, **attrs: str) -> str:
        """The id of ``key``'s node, added on first use."""
        if key in self.key:
            return self.key[key]
        node_id = f"n{len(self.nodes)}"
        self.key[key] = node_id
        self.nodes.append(DotNode(node_id, label, **attrs))
        return node_id

    def add_edge(self, source: object, target: object, label: str = "", color: str = "black") -> None:
        self.edges.append(DotEdge(self.key[source], self.key[target], label, color))

    def node(self, node_id: str) -> DotNode:
        return self.nodes[int(node_id[1:])]

    def to_dot(self) -> str:
        lines = [f"digraph {quote(self.name)} {{", f"  rankdir={self.rankdir};",
                 '  node [fontname="Helvetica", fontsize=11];']  # no "edge [...]": qt_dotgraph draws it as a node
        for n in self.nodes:
            extra = f", tooltip={quote(n.tooltip)}" if n.tooltip else ""
            lines.append(f"  {n.id} [label={quote(n.label)}, shape={n.shape}, color={quote(n.color)}{extra}];")
        for e in self.edges:
            label = f"label={quote(e.label)}, " if e.label else ""
            lines.append(f"  {e.source} -> {e.target} [{label}color={quote(e.color)}, fontname=Helvetica, fontsize=9];")
        lines.append("}")
        return "\n".join(lines) + "\n"


def quote(text: str) -> str:
    """A DOT string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _run(dot_text: str, fmt: str, program: str, timeout: float) -> str:
    exe = shutil.which(program)
    if exe is None:
        raise GraphvizError(f"Graphviz '{program}' is not installed (Debian: apt-get install graphviz)")
    try:
        done = subprocess.run([exe, f"-T{fmt}"], input=dot_text, capture_output=True, text=True,
                              timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        raise GraphvizError(f"{program} did not lay the graph out in {timeout:.0f} s") from None
    if done.returncode != 0:
        raise GraphvizError(f"{shlex.join([program, '-T' + fmt])} failed: {done.stderr.strip()[:500]}")
    return done.stdout


def render(dot_text: str, fmt: str, program: str = "dot", timeout: float = LAYOUT_TIMEOUT) -> str:
    """Graphviz's output in a text format (``svg``, ``dot``, ``plain``) for ``dot_text``."""
    return _run(dot_text, fmt, program, timeout)


def layout_dot(dot_text: str, program: str = "dot", timeout: float = LAYOUT_TIMEOUT) -> str:
    """DOT with positions (``pos``, ``bb``, ``lp``): what ``qt_dotgraph.DotToQtGenerator`` draws."""
    # pydot splits long lines with a backslash-newline that qt_dotgraph cannot read; Graphviz too
    return _run(dot_text, "dot", program, timeout).replace("\\\n", "")


@dataclass
class PlainNode:
    id: str
    x: float
    y: float
    width: float
    height: float
    label: str
    shape: str
    color: str


@dataclass
class PlainEdge:
    source: str
    target: str
    points: list[tuple[float, float]]
    label: str = ""
    label_pos: tuple[float, float] | None = None
    color: str = "black"


@dataclass
class PlainLayout:
    """Graphviz ``-Tplain``: sizes and positions in inches, y upwards."""

    width: float
    height: float
    nodes: dict[str, PlainNode]
    edges: list[PlainEdge]


def layout_plain(dot_text: str, program: str = "dot", timeout: float = LAYOUT_TIMEOUT) -> PlainLayout:
    # Graphviz continues a long line (many points, a long label) with a backslash-newline, as in -Tdot
    return parse_plain(_run(dot_text, "plain", program, timeout).replace("\\\n", ""))


def parse_plain(text: str) -> PlainLayout:
    """Parse Graphviz's ``plain`` output (``graph``, ``node``, ``edge`` and ``stop`` lines)."""
    width = height = 0.0
    nodes: dict[str, PlainNode] = {}
    edges: list[PlainEdge] = []
    for line in text.splitlines():
        if not line.strip():
            continue
        f = shlex.split(line, posix=True)
        if f[0] == "graph":
            width, height = float(f[2]), float(f[3])
        elif f[0] == "node":
            nodes[f[1]] = PlainNode(f[1], float(f[2]), float(f[3]), float(f[4]), float(f[5]), f[6], f[8], f[9])
        elif f[0] == "edge":
            n = int(f[3])
            pts = [(float(f[4 + 2 * i]), float(f[5 + 2 * i])) for i in range(n)]
            rest = f[4 + 2 * n:]
            label, pos = "", None
            if len(rest) >= 5:  # label xl yl style color
                label, pos = rest[0], (float(rest[1]), float(rest[2]))
            edges.append(PlainEdge(f[1], f[2], pts, label, pos, rest[-1] if rest else "black"))
        elif f[0] == "stop":
            break
    return PlainLayout(width, height, nodes, edges)


def sketch_layout(graph: DotGraph, first: str) -> PlainLayout:
    """A layout made in a moment without Graphviz, drawn while Graphviz lays ``graph`` out: the nodes in
    columns by their number of steps from node ``first`` (edges either way; the unreached last), straight
    edges, no self-loops and no edge labels. It lets a view highlight a state in the frame it arrives."""
    near: dict[str, list[str]] = {n.id: [] for n in graph.nodes}
    for e in graph.edges:
        near[e.source].append(e.target)
        near[e.target].append(e.source)
    step = {first: 0} if first in near else {}
    queue = deque(step)
    while queue:
        n = queue.popleft()
        for m in near[n]:
            if m not in step:
                step[m] = step[n] + 1
                queue.append(m)
    last = max(step.values(), default=-1) + 1
    columns: list[list[DotNode]] = [[] for _ in range(last + 1)]
    for n in graph.nodes:
        columns[step.get(n.id, last)].append(n)
    nodes: dict[str, PlainNode] = {}
    x = 0.0
    for column in columns:
        sizes = [(0.2 + 0.075 * max(map(len, n.label.split("\n"))), 0.1 + 0.18 * (n.label.count("\n") + 1))
                 for n in column]
        width = max((w for w, _h in sizes), default=0.0)
        y = 0.0
        for n, (w, h) in zip(column, sizes):
            nodes[n.id] = PlainNode(n.id, x + width / 2, y - h / 2, w, h, n.label, n.shape, n.color)
            y -= h + 0.3
        x += width + 1.0 if column else 0.0
    height = max((-n.y + n.height / 2 for n in nodes.values()), default=0.0)
    for n in nodes.values():  # y upwards from 0, as Graphviz's
        n.y += height
    edges = [PlainEdge(e.source, e.target, _straight(nodes[e.source], nodes[e.target]), color=e.color)
             for e in graph.edges if e.source != e.target]
    return PlainLayout(x, height, nodes, edges)


def _straight(a: PlainNode, b: PlainNode) -> list[tuple[float, float]]:
    """A straight edge from ``a``'s border to ``b``'s as one cubic segment (four points, as -Tplain)."""
    dx, dy = b.x - a.x, b.y - a.y

    def border(n: PlainNode, sign: float) -> tuple[float, float]:
        t = min(n.width / 2 / abs(dx) if dx else float("inf"), n.height / 2 / abs(dy) if dy else float("inf"))
        return n.x + sign * dx * t, n.y + sign * dy * t
    (x0, y0), (x1, y1) = border(a, 1.0), border(b, -1.0)
    return [(x0 + (x1 - x0) * k / 3, y0 + (y1 - y0) * k / 3) for k in range(4)]
