"""Where proposition nodes can fight each other: checks E1, E2, E3, C1, C2 of thesis section 3.5.2.

- E1 (3.5.2.2): an output proposition's nodes publish-reach an input proposition node; one
  finding per (output, input) pair with every chain under it. Pairs that are the designed feedback
  of the activation-completion paradigm ([75]: an action ``X`` and its completion ``X_ac``, a region
  ``R`` and its completion ``R_rc``), and the pairs the mapping declares under ``expected_feedback:``,
  are kept apart as *expected feedback*: shown, not counted as findings (see ``expected_feedback``).
- E2 (3.5.2.3): two or more output propositions publish-reach the same topic or action
  (refined in ``conflicts``: they must compete there, not merely both reach a driver's outputs).
- E3 (3.5.2.4): one output proposition's nodes publish-reach the same topic through several nodes
  (same refinement).
- C1 (3.5.2.5): for one output, a robot topic ``/<robot>/<suffix>`` is reached for some robots of
  the user's list but not for all.
- C2 (3.5.2.6): a robot of the list whose topics no output reaches at all.
- P1 (3.5.1): an input proposition topic that nodes other than the input's own publish on (a second
  publisher the controller would listen to as well).

Every finding carries one witness chain per proposition (or node) in the thesis' notation.
"""
from __future__ import annotations

from collections.abc import Callable, Collection, Iterable, Sequence
from dataclasses import dataclass, field
from fnmatch import fnmatchcase

from ltl_stack.analysis.conflicts import channel_lanes, conflict_pairs
from ltl_stack.analysis.graph import ACTION, DEFAULT_MERGERS, ComputationGraph, relay_nodes
from ltl_stack.analysis.reach import PUBLISH, SUBSCRIBE, Reach, reach
from ltl_stack.runtime.mapping import INPUT, OUTPUT, Mapping, resolve_node_name, resolve_topics
from ltl_stack.spec.activation_completion import ACTION_COMPLETION, REGION_COMPLETION


@dataclass(frozen=True)
class Witness:
    """One way a proposition's node reaches something: the chain of vertices, first to last."""

    proposition: str
    node: str
    path: tuple[tuple[str, str], ...]  # (kind, name), kind in node / topic / action

    @property
    def text(self) -> str:
        return " -> ".join(f"[{name}]" if kind == "topic" else f"({name})" for kind, name in self.path)

    def to_dict(self) -> dict:
        return {"proposition": self.proposition, "node": self.node, "chain": self.text,
                "path": [{"kind": k, "name": n} for k, n in self.path]}


@dataclass(frozen=True)
class E1Finding:
    """Output ``output`` publish-reaches the node(s) of input ``input``: one chain per (output node,
    input node) pair, folded under the one (output, input) row. ``expected`` is the reason when the
    pair is designed feedback (activation-completion: its kind), else ''."""

    output: str
    input: str
    witnesses: tuple[Witness, ...]
    input_nodes: tuple[str, ...]  # the input node each witness ends at
    expected: str = ""  # a kind of expected feedback (``expected_feedback``) or ''

    @property
    def witness(self) -> Witness:
        return self.witnesses[0]

    @property
    def input_node(self) -> str:
        return self.input_nodes[0]

    def to_dict(self) -> dict:
        data = {"output": self.output, "input": self.input, "input_node": self.input_node,
                "output_node": self.witness.node, "chain": self.witness.text,
                "chains": [{"output_node": w.node, "input_node": n, "chain": w.text}
                           for w, n in zip(self.witnesses, self.input_nodes)]}
        if self.expected:
            data["expected"] = self.expected
            data["why"] = feedback_reason(self)
        return data


@dataclass(frozen=True)
class E2Group:
    """Output propositions that compete on one channel (topic or action): one witness per output."""

    channel: str
    kind: str  # "topic" or "action"
    witnesses: tuple[Witness, ...]
    pairs: tuple[tuple[str, str], ...] = ()  # the competing pairs (all pairs unless a mux merges some)

    @property
    def outputs(self) -> tuple[str, ...]:
        return tuple(w.proposition for w in self.witnesses)

    @property
    def complete(self) -> bool:
        """True when every two of the outputs compete on the channel."""
        k = len(self.witnesses)
        return len(self.pairs) == k * (k - 1) // 2

    def to_dict(self) -> dict:
        return {"topic": self.channel, "kind": self.kind, "outputs": list(self.outputs),
                "pairs": [list(p) for p in self.pairs], "chains": [w.to_dict() for w in self.witnesses]}


@dataclass(frozen=True)
class E3Finding:
    """Several nodes of one output proposition reach one channel: one witness per node."""

    output: str
    channel: str
    kind: str
    witnesses: tuple[Witness, ...]

    def to_dict(self) -> dict:
        return {"output": self.output, "topic": self.channel, "kind": self.kind,
                "nodes": [w.node for w in self.witnesses], "chains": [w.to_dict() for w in self.witnesses]}


@dataclass(frozen=True)
class C1Finding:
    """For ``output``, the robot topic ``/<robot><suffix>`` is reached for ``present`` robots only."""

    output: str
    suffix: str
    present: tuple[tuple[str, Witness], ...]
    missing: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"output": self.output, "suffix": self.suffix, "missing": list(self.missing),
                "present": [{"robot": r, **w.to_dict()} for r, w in self.present]}


@dataclass(frozen=True)
class C2Finding:
    """``robot`` has no topic reached by any output; ``suffixes`` are what the other robots get."""

    robot: str
    suffixes: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"robot": self.robot, "suffixes_of_other_robots": list(self.suffixes)}


@dataclass(frozen=True)
class InputPublisherFinding:
    """An input proposition topic published by nodes other than the input's own (thesis §3.5.1: an
    input topic takes exactly one node): the controller reads whichever spoke last."""

    input: str
    topic: str
    others: tuple[str, ...]   # the other publishers
    nodes: tuple[str, ...]    # the input's mapped nodes

    def to_dict(self) -> dict:
        return {"input": self.input, "topic": self.topic, "other_publishers": list(self.others),
                "mapped_nodes": list(self.nodes)}


@dataclass(frozen=True)
class MissingNode:
    """A mapped node that is not in the graph (not launched, or a typo in the mapping)."""

    proposition: str
    kind: str
    node: str
    line: int


@dataclass
class Analysis:
    """Everything one run of the checks found; ``pub``/``sub`` keep the reachability per (prop, node)."""

    graph: ComputationGraph
    inputs: list[str]
    outputs: list[str]
    nodes: dict[str, list[str]]  # proposition -> its nodes present in the graph
    missing: list[MissingNode]
    unmapped: list[str]
    boundary: list[str]  # proposition topics the traversal does not cross
    pub: dict[tuple[str, str], Reach]
    sub: dict[tuple[str, str], Reach]
    robots: list[str] = field(default_factory=list)
    namespace: str = ""  # the scenario namespace of the mapping (robots may be named relative to it)
    robot_topics_ignored: list[str] = field(default_factory=list)
    e1: list[E1Finding] = field(default_factory=list)
    feedback: list[E1Finding] = field(default_factory=list)  # E1 pairs that are expected feedback
    e2: list[E2Group] = field(default_factory=list)
    e3: list[E3Finding] = field(default_factory=list)
    c1: list[C1Finding] = field(default_factory=list)
    c2: list[C2Finding] = field(default_factory=list)
    relays: list[str] = field(default_factory=list)  # nodes E2/E3 followed as relays (not known mergers)
    declared_feedback: list[tuple[str, str, int]] = field(default_factory=list)  # the mapping's expected_feedback
    p1: list[InputPublisherFinding] = field(default_factory=list)  # input topics with other publishers

    @property
    def finding_count(self) -> int:
        return len(self.e1) + len(self.e2) + len(self.e3) + len(self.c1) + len(self.c2) + len(self.p1)

    def witness(self, prop: str, node: str, target: int, direction: str = PUBLISH) -> Witness:
        r = (self.pub if direction == PUBLISH else self.sub)[(prop, node)]
        return make_witness(self.graph, prop, node, r.chain(target))


def make_witness(graph: ComputationGraph, prop: str, node: str, chain: Iterable[int]) -> Witness:
    path = []
    for v in chain:
        if graph.is_node(v):
            path.append(("node", graph.nodes[v]))
        else:
            ch = graph.channel_of_vertex(v)
            path.append(("action" if ch.kind == ACTION else "topic", ch.name))
    return Witness(prop, node, tuple(path))


def analyze(graph: ComputationGraph, mapping: Mapping, inputs: Sequence[str], outputs: Sequence[str], *,
            robots: Sequence[str] = (), robot_topics_to_ignore: Sequence[str] = (),
            progress: Callable[[str], None] | None = None, mergers: Sequence[str] = DEFAULT_MERGERS) -> Analysis:
    """Run reachability for every mapped proposition node, then E1, E2, E3 and (with robots) C1, C2.

    ``inputs``/``outputs`` are the spec's propositions in spec order (findings follow that order);
    mapping entries for other names are left out (``runtime.mapping.check_mapping`` reports them).
    E2/E3 follow competitions through relays, except nodes matching ``mergers`` (``graph.relay_nodes``).
    """
    namespace = mapping.scenario_namespace() or ""
    in_topics, out_topics = resolve_topics(mapping, inputs, outputs, namespace)
    boundary = sorted({*in_topics.values(), *(t for ts in out_topics.values() for t in ts)})
    blocked = {v for v in (graph.channel_vertex(t) for t in boundary) if v is not None}
    result = Analysis(graph, list(inputs), list(outputs), {}, [], [], boundary, {}, {},
                      robots=list(robots), namespace=namespace, robot_topics_ignored=list(robot_topics_to_ignore))
    for kind, props, section in ((INPUT, inputs, mapping.inputs), (OUTPUT, outputs, mapping.outputs)):
        for prop in props:
            named = [e for e in section.get(prop) or [] if e.node is not None]
            if not named:
                result.unmapped.append(prop)
                continue
            present = []
            for entry in named:
                node = resolve_node_name(entry.node, namespace)
                if node in graph.node_index:
                    if node not in present:
                        present.append(node)
                else:
                    result.missing.append(MissingNode(prop, kind, node, entry.line))
            result.nodes[prop] = present
    todo = [(p, n) for p in (*inputs, *outputs) for n in result.nodes.get(p, [])]
    for i, (prop, node) in enumerate(todo):
        if progress and i % 50 == 0:
            progress(f"reachability {i}/{len(todo)} proposition nodes")
        start = graph.node_index[node]
        result.pub[(prop, node)] = reach(graph, start, PUBLISH, blocked)
        result.sub[(prop, node)] = reach(graph, start, SUBSCRIBE, blocked)
    result.declared_feedback = list(mapping.expected_feedback)
    result.p1 = check_input_publishers(graph, mapping, inputs, in_topics, namespace)
    relays = relay_nodes(graph, mergers)
    result.relays = sorted(graph.nodes[i] for i in relays)
    result.e2, result.e3 = check_conflicts(result, blocked, relays)
    pairs = check_e1(result)
    result.e1 = [f for f in pairs if not f.expected]
    result.feedback = [f for f in pairs if f.expected]
    if robots:
        result.c2 = check_c2(result)
        result.c1 = check_c1(result, skip={f.robot for f in result.c2})
    return result


def check_input_publishers(graph: ComputationGraph, mapping: Mapping, inputs: Sequence[str],
                           in_topics: dict[str, str], namespace: str) -> list[InputPublisherFinding]:
    """P1: input proposition topics that nodes other than the input's mapped node(s) publish on."""
    lanes_of = channel_lanes(graph)
    found = []
    for x in inputs:
        topic = in_topics.get(x)
        v = graph.channel_vertex(topic) if topic else None
        if v is None:
            continue
        publishers = [graph.nodes[p] for lane in lanes_of[v - len(graph.nodes)] for p in graph.lane_publishers[lane]]
        own = tuple(resolve_node_name(e.node, namespace) for e in mapping.inputs.get(x) or [] if e.node)
        others = tuple(sorted(set(publishers) - set(own)))
        if others and own:
            found.append(InputPublisherFinding(x, topic, others, own))
    return found


def check_e1(a: Analysis) -> list[E1Finding]:
    """Output propositions whose nodes publish-reach an input proposition node (thesis Fig. 3.6).

    One finding per (output, input) pair in spec order, with a chain for every (output node,
    input node) pair that reaches; each is marked with ``expected_feedback``'s reason, if any.
    """
    input_nodes = [(x, [(n, a.graph.node_index[n]) for n in a.nodes.get(x, [])]) for x in a.inputs]
    found = []
    for y in a.outputs:
        for x, nodes in input_nodes:
            witnesses, ends = [], []
            for x_node, v in nodes:
                for y_node in a.nodes.get(y, []):
                    r = a.pub[(y, y_node)]
                    if v in r:
                        witnesses.append(make_witness(a.graph, y, y_node, r.chain(v)))
                        ends.append(x_node)
            if witnesses:
                kind = expected_feedback(y, x, a.declared_feedback)
                found.append(E1Finding(y, x, tuple(witnesses), tuple(ends), kind))
    return found


#: kinds of expected feedback (``E1Finding.expected``) and what each means
ACTION_FEEDBACK = "action completion"
REGION_FEEDBACK = "region completion"
DECLARED_FEEDBACK = "declared in the mapping"


def expected_feedback(output: str, input: str, declared: Iterable[tuple[str, str, int]] = ()) -> str:
    """The kind of designed feedback that ``output`` reaching ``input`` is, or '' when it is a finding.

    Exactly the activation-completion pairs of [75] (thesis 4.3), plus what the user declares:
    - ``ACTION_FEEDBACK``: ``X`` -> ``X_ac``, the action reports its own completion (thesis Fig. 3.6
      calls this connection desirable);
    - ``REGION_FEEDBACK``: ``R`` -> ``R_rc``, heading for region R, the robot's own location sensing
      reports its arrival;
    - ``DECLARED_FEEDBACK``: a pair the mapping's ``expected_feedback:`` matches (output pattern, input
      pattern), e.g. a robot whose every motion output reaches every region sensor through a simulator.
    Anything else — a motion output reaching another region's sensor included — is a finding.
    """
    if input == output + ACTION_COMPLETION:
        return ACTION_FEEDBACK
    if input == output + REGION_COMPLETION:
        return REGION_FEEDBACK
    if any(fnmatchcase(output, o) and fnmatchcase(input, i) for o, i, _ in declared):
        return DECLARED_FEEDBACK
    return ""


def feedback_reason(f: E1Finding) -> str:
    """One sentence saying why ``f`` is expected feedback."""
    if f.expected == ACTION_FEEDBACK:
        return f"{f.input} reports the completion of the action {f.output}"
    if f.expected == REGION_FEEDBACK:
        return f"{f.input} reports the robot's arrival in region {f.output}"
    if f.expected == DECLARED_FEEDBACK:
        return f"the mapping declares {f.output} -> {f.input} expected feedback"
    return ""


def check_conflicts(a: Analysis, blocked: Collection[int] = (),
                    relays: Collection[int] = ()) -> tuple[list[E2Group], list[E3Finding]]:
    """E2 (Figs. 3.7, 3.8) and E3 (Fig. 3.9) from the competing pairs of ``conflicts.conflict_pairs``."""
    reaches = {(y, node): a.pub[(y, node)] for y in a.outputs for node in a.nodes.get(y, [])}
    rank = {y: i for i, y in enumerate(a.outputs)}
    e2, e3 = [], []
    for v, pairs in conflict_pairs(a.graph, reaches, blocked, relays).items():
        ch = a.graph.channel_of_vertex(v)
        first: dict[str, str] = {}  # output -> its first node in a competing pair
        prop_pairs = set()
        same: dict[str, set[str]] = {}
        for (y1, n1), (y2, n2) in pairs:
            if y1 == y2:
                same.setdefault(y1, set()).update((n1, n2))
                continue
            prop_pairs.add(tuple(sorted((y1, y2), key=rank.__getitem__)))
            for y, node in ((y1, n1), (y2, n2)):
                if y not in first or a.nodes[y].index(node) < a.nodes[y].index(first[y]):
                    first[y] = node
        if prop_pairs:
            outputs = sorted(first, key=rank.__getitem__)
            e2.append(E2Group(ch.name, ch.kind, tuple(a.witness(y, first[y], v) for y in outputs),
                              tuple(sorted(prop_pairs, key=lambda p: (rank[p[0]], rank[p[1]])))))
        for y, nodes in same.items():
            ordered = [node for node in a.nodes[y] if node in nodes]
            e3.append(E3Finding(y, ch.name, ch.kind, tuple(a.witness(y, node, v) for node in ordered)))
    e2.sort(key=lambda g: (-len(g.witnesses), g.channel))
    e3.sort(key=lambda f: (rank[f.output], f.channel))
    return e2, e3


def e2_groups(a: Analysis) -> list[tuple[str, tuple[tuple[str, str], ...]]]:
    """(channel, competing output pairs) of every E2 group: the input of ``suggest.mutual_exclusions``."""
    return [(g.channel, g.pairs) for g in a.e2]


def split_robot_topic(name: str, robots: Iterable[str], namespace: str = "") -> tuple[str, str] | None:
    """``/sphero_wpw/cmd_vel`` -> (``sphero_wpw``, ``/cmd_vel``) when the name lies under a listed robot.

    A robot is a namespace: ``sphero_wpw`` (the thesis' robots at the root), or one with several
    segments (``spheros/sphero_wpw``). Inside the scenario namespace ``namespace`` robots may also be
    named relative to it, as the mapping names its nodes: with ``namespace`` ``spheros``,
    ``/spheros/sphero_wpw/cmd_vel`` belongs to robot ``sphero_wpw``. The longest robot name wins.
    """
    full = "/" + name.strip("/")
    candidates = [full]
    ns = namespace.strip("/")
    if ns and full.startswith(f"/{ns}/"):
        candidates.insert(0, full[len(ns) + 1:])
    ordered = sorted(robots, key=lambda r: len(r.strip("/")), reverse=True)
    for candidate in candidates:
        for robot in ordered:
            prefix = "/" + robot.strip("/")
            if prefix != "/" and candidate.startswith(prefix + "/"):
                return robot, candidate[len(prefix):]
    return None


def suffix_ignored(suffix: str, patterns: Iterable[str]) -> bool:
    """A robot-topic suffix is ignored if a pattern equals it, is a parent of it, or glob-matches it."""
    for p in patterns:
        p = "/" + p.strip().strip("/")
        if suffix == p or suffix.startswith(p + "/") or fnmatchcase(suffix, p):
            return True
    return False


def _robot_topics(a: Analysis, y: str) -> dict[str, dict[str, tuple[str, int]]]:
    """For output y: suffix -> robot -> (node, channel vertex) of the first witness."""
    robots = set(a.robots)
    out: dict[str, dict[str, tuple[str, int]]] = {}
    for node in a.nodes.get(y, []):
        for v in a.pub[(y, node)].channels:
            split = split_robot_topic(a.graph.vertex_name(v), robots, a.namespace)
            if split is None or suffix_ignored(split[1], a.robot_topics_ignored):
                continue
            robot, suffix = split
            out.setdefault(suffix, {}).setdefault(robot, (node, v))
    return out


def check_c1(a: Analysis, skip: Iterable[str] = ()) -> list[C1Finding]:
    """Per output: robot topics reached for some robots of the list but not all (Fig. 3.14).

    Robots in ``skip`` (those C2 already reports as not controlled at all) are not repeated here.
    """
    considered = [r for r in a.robots if r not in set(skip)]
    found = []
    for y in a.outputs:
        for suffix, by_robot in sorted(_robot_topics(a, y).items()):
            missing = tuple(r for r in considered if r not in by_robot)
            if not missing:
                continue
            present = tuple((r, a.witness(y, node, v)) for r in a.robots if r in by_robot
                            for node, v in [by_robot[r]])
            found.append(C1Finding(y, suffix, present, missing))
    return found


def check_c2(a: Analysis) -> list[C2Finding]:
    """Robots of the list that no output proposition reaches through any robot topic (Fig. 3.15)."""
    reached: dict[str, set[str]] = {r: set() for r in a.robots}
    for y in a.outputs:
        for suffix, by_robot in _robot_topics(a, y).items():
            for r in by_robot:
                reached[r].add(suffix)
    others = sorted(set().union(*reached.values())) if reached else []
    return [C2Finding(r, tuple(others)) for r in a.robots if not reached[r]]


def reach_listing(a: Analysis, prop: str, direction: str = PUBLISH) -> list[dict]:
    """T^a and N^a of each node of ``prop`` with one witness chain each (for ``--reach`` reports)."""
    rows = []
    table = a.pub if direction == PUBLISH else a.sub
    for node in a.nodes.get(prop, []):
        r = table[(prop, node)]
        rows.append({
            "node": node,
            "topics": {a.graph.vertex_name(v): r.chain_text(v) for v in r.channels},
            "nodes": {a.graph.vertex_name(v): r.chain_text(v) for v in r.nodes},
        })
    return rows


__all__ = ["PUBLISH", "SUBSCRIBE", "Analysis", "analyze"]
