"""The proposition mapping YAML of the thesis' stack (thesis §3.5.1, Figs. 3.2–3.3).

Each input proposition is served by one *input proposition node* that publishes a ``std_msgs/Bool``
on the input topic; each output proposition drives one or more *output proposition nodes* that
subscribe to its output topic::

    inputs:
      person:
        node: '/simple/inputs/person'
        node_publish_topic: '/simple/inputs/person'
        pkg: 'controller_executor'
        filename: 'get_tag.py'
        parameters: {tag_no: 5}
    outputs:
      move:                        # one node ...
        node: 'move'
        node_subscribe_topic: '/simple/outputs/move'
        ...
      stop:                        # ... or a list of nodes
        - {node: '/ns/outputs/r1/stop', node_subscribe_topic: '/ns/outputs/stop', ...}

Compatible extensions: an optional top-level ``namespace:``; ``negotiation:`` (the proposition
classes for integrative negotiation, read by ``runtime.resilience.negotiation``, docs/negotiation.md); per node ``type:`` (the executable,
otherwise taken from ``filename``) and ``args:`` (command-line arguments for the launch file); per input
``freshness:`` (seconds a reading stays valid; 0: forever; ``runtime.executor.freshness``); per node ``robot:``
(the robot whose machine runs the node: ``generate_launch`` starts it with that robot, so that a
robot's output nodes, and their deadman, run on the robot's own host).

``load_mapping`` reads a file as it is (structure errors raise ``MappingError`` naming file and line);
``check_mapping`` compares it with a spec's propositions and returns errors and warnings.
"""
from __future__ import annotations

import os
import posixpath
import re
from collections import Counter
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import yaml

from ltl_stack.errors import InputError, UserError
from ltl_stack.inputs import construct_yaml, parse_yaml_node, read_text

INPUT = "input"
OUTPUT = "output"
_TOPIC_KEY = {INPUT: "node_publish_topic", OUTPUT: "node_subscribe_topic"}
_ENTRY_KEYS = {"node", "node_publish_topic", "node_subscribe_topic", "pkg", "filename", "parameters",
               "type", "args", "freshness", "robot"}
_TOP_KEYS = {"inputs", "outputs", "namespace", "negotiation", "expected_feedback"}
_NAME = re.compile(r"^/?[A-Za-z_~][A-Za-z0-9_/]*$")
#: A robot name (``robot:``): a ROS base name, as the robot's namespace usually is.
_ROBOT = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


class MappingError(UserError):
    """A mapping file that cannot be used; ``str()`` is ``file:line: message`` (exit code 2)."""

    def __init__(self, file: str, line: int, message: str):
        self.file, self.line, self.message = file, line, message
        super().__init__(f"{file}:{line}: {message}" if line else f"{file}: {message}")


@dataclass(frozen=True)
class MappingIssue:
    """One finding of ``check_mapping``: ``severity`` is ``"error"`` or ``"warning"``."""

    severity: str
    message: str
    file: str
    line: int = 0
    proposition: str = ""

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        return f"{where}: {self.severity}: {self.message}"


@dataclass(frozen=True)
class NodeEntry:
    """One proposition node of the mapping."""

    proposition: str
    kind: str
    node: str | None
    topic: str | None
    pkg: str | None = None
    filename: str | None = None
    parameters: dict[str, Any] = field(default_factory=dict)
    type: str | None = None
    args: str = ""
    line: int = 0
    #: seconds a reading of this input stays valid (None: derived, ``runtime.executor.freshness``; 0: forever)
    freshness: float | None = None
    #: the robot whose host runs this node (``robot:``; None: the scenario's, e.g. the controller's host)
    robot: str | None = None

    @property
    def executable(self) -> str | None:
        """The node ``type`` for roslaunch: ``type:`` if given, else the base name of ``filename``."""
        if self.type:
            return self.type
        return posixpath.basename(self.filename) if self.filename else None

    @property
    def group(self) -> str:
        """``inputs`` or ``outputs``: the group of the scenario namespace the node belongs to."""
        return "inputs" if self.kind == INPUT else "outputs"


@dataclass
class Mapping:
    """A loaded mapping: proposition name → its node entries, in file order."""

    file: str
    inputs: dict[str, list[NodeEntry]] = field(default_factory=dict)
    outputs: dict[str, list[NodeEntry]] = field(default_factory=dict)
    lines: dict[tuple[str, str], int] = field(default_factory=dict)
    namespace: str | None = None
    #: the ``negotiation:`` section as written (proposition classes, read by ``runtime.resilience.negotiation``)
    negotiation: Any = None
    negotiation_line: int = 0
    #: ``expected_feedback:`` — (output pattern, input pattern, line): E1 pairs the user declares designed
    #: feedback, beyond the activation-completion pairs (shell patterns on proposition names)
    expected_feedback: list[tuple[str, str, int]] = field(default_factory=list)

    def entries(self) -> list[NodeEntry]:
        """Every node entry, inputs first."""
        return [e for group in (self.inputs, self.outputs) for es in group.values() for e in es]

    def line_of(self, kind: str, proposition: str) -> int:
        return self.lines.get((kind, proposition), 0)

    def scenario_namespace(self) -> str | None:
        """The ``namespace:`` key, else the ``X`` most topics use as ``/X/inputs/...``/``/X/outputs/...``."""
        if self.namespace:
            return self.namespace.strip("/")
        found = Counter()
        for entry in self.entries():
            parts = (entry.topic or "").split("/")
            if entry.topic and entry.topic.startswith("/") and len(parts) >= 4 and parts[2] in ("inputs", "outputs"):
                found[parts[1]] += 1
        return found.most_common(1)[0][0] if found else None


def load_mapping(path: str | os.PathLike) -> Mapping:
    """Read a mapping YAML file; raises ``MappingError`` (file, line, message) when it is malformed."""
    file = str(path)
    try:
        text = read_text(path, "mapping file")
    except InputError as err:  # missing, a folder, binary, not UTF-8
        raise MappingError(file, err.line, err.message) from None
    return parse_mapping(text, file)


def parse_mapping(text: str, file: str = "<string>") -> Mapping:
    """Parse mapping YAML text (see ``load_mapping``).

    The YAML goes through ``ltl_stack.inputs.parse_yaml_node``, so invalid YAML, keys that are not
    strings (``5:``, ``yes:``, ``~:``), nesting deeper than any mapping needs, alias floods and
    over-long integers are ``MappingError``s naming the line, like every structure error below.
    """
    try:
        root = parse_yaml_node(text, file)
        data = construct_yaml(root, file)
    except InputError as err:
        raise MappingError(file, err.line, err.message) from None
    mapping = Mapping(file=file)
    if root is None or data is None:
        return mapping
    if not isinstance(root, yaml.MappingNode) or not isinstance(data, dict):
        raise MappingError(file, _line(root), "a mapping file must be a YAML mapping with 'inputs:' and 'outputs:'")
    top = _keyed_nodes(root, file)
    for key, (key_line, _) in top.items():
        if key not in _TOP_KEYS:
            raise MappingError(file, key_line, f"unknown top-level key {key!r} (expected inputs, outputs, namespace, "
                               "negotiation, expected_feedback)")
    if "namespace" in top:
        ns = data["namespace"]
        if not isinstance(ns, str) or not _NAME.match(ns):
            raise MappingError(file, top["namespace"][0], f"namespace must be a ROS name, got {ns!r}")
        mapping.namespace = ns
    if "negotiation" in top:
        mapping.negotiation, mapping.negotiation_line = data["negotiation"], top["negotiation"][0]
        if mapping.negotiation is not None:
            _check_negotiation(mapping)
    if "expected_feedback" in top:
        mapping.expected_feedback = _expected_feedback(file, *top["expected_feedback"], data["expected_feedback"])
    for kind, key in ((INPUT, "inputs"), (OUTPUT, "outputs")):
        if key not in top or data[key] is None:
            continue
        section_line, section_node = top[key]
        if not isinstance(section_node, yaml.MappingNode):
            raise MappingError(file, section_line, f"'{key}:' must map proposition names to nodes")
        target = mapping.inputs if kind == INPUT else mapping.outputs
        for prop_key, value_node in section_node.value:
            # A proposition may appear more than once: the thesis' mapping GUI writes one block per row, so
            # a proposition mapped to two nodes (Fig. 3.9) is the same key twice; its entries are joined.
            prop, prop_line = str(prop_key.value), _line(prop_key)
            mapping.lines.setdefault((kind, prop), prop_line)
            try:
                value = construct_yaml(value_node, file)
            except InputError as err:
                raise MappingError(file, err.line, err.message) from None
            entries = target.setdefault(prop, [])
            if value is None:
                continue
            if isinstance(value, dict):
                items = [(value, value_node)]
            elif isinstance(value, list):
                items = list(zip(value, value_node.value))
            else:
                raise MappingError(file, prop_line, f"{kind} {prop!r}: expected a node entry or a list of them, "
                                   f"got {type(value).__name__}")
            entries += [_entry(file, kind, prop, item, node) for item, node in items]
    return mapping


def _expected_feedback(file: str, line: int, node: yaml.Node, value: Any) -> list[tuple[str, str, int]]:
    """``expected_feedback: {output: input | [inputs]}`` (shell patterns) → (output, input, line) pairs."""
    if value is None:
        return []
    if not isinstance(node, yaml.MappingNode) or not isinstance(value, dict):
        raise MappingError(file, line, "expected_feedback: must map an output (pattern) to the input(s) it is "
                                       "expected to reach")
    pairs = []
    for output, (out_line, _) in _keyed_nodes(node, file).items():
        inputs = value[output]
        inputs = [inputs] if isinstance(inputs, str) else inputs
        if not isinstance(inputs, list) or not inputs or not all(isinstance(i, str) and i for i in inputs):
            raise MappingError(file, out_line, f"expected_feedback: {output!r} must name an input or a list of "
                                               "inputs (patterns allowed)")
        pairs += [(output, i, out_line) for i in inputs]
    return pairs


def _entry(file: str, kind: str, prop: str, value: Any, node: yaml.Node) -> NodeEntry:
    line = _line(node)
    if not isinstance(value, dict):
        raise MappingError(file, line, f"{kind} {prop!r}: a node entry must be a mapping, got {type(value).__name__}")
    keys = _keyed_nodes(node, file)
    for key, (key_line, _) in keys.items():
        if key not in _ENTRY_KEYS:
            raise MappingError(file, key_line, f"{kind} {prop!r}: unknown key {key!r} "
                               f"(expected {', '.join(sorted(_ENTRY_KEYS))})")
    wrong = _TOPIC_KEY[OUTPUT if kind == INPUT else INPUT]
    if wrong in value:
        raise MappingError(file, keys[wrong][0], f"{kind} {prop!r}: {wrong} is for "
                           f"{'outputs' if kind == INPUT else 'inputs'}; use {_TOPIC_KEY[kind]}")

    def text(key: str) -> str | None:
        raw = value.get(key)
        if raw is None:
            return None
        if not isinstance(raw, (str, int, float)) or isinstance(raw, bool):
            raise MappingError(file, keys[key][0], f"{kind} {prop!r}: {key} must be a string, got {raw!r}")
        return str(raw).strip() or None

    node_name, topic = text("node"), text(_TOPIC_KEY[kind])
    for key, name in (("node", node_name), (_TOPIC_KEY[kind], topic)):
        if name is not None and not _NAME.match(name):
            raise MappingError(file, keys[key][0], f"{kind} {prop!r}: {key} {name!r} is not a valid ROS name")
    parameters = value.get("parameters") or {}
    if not isinstance(parameters, dict):
        raise MappingError(file, keys["parameters"][0], f"{kind} {prop!r}: parameters must be a mapping")
    robot = text("robot")
    if robot is not None and (not _ROBOT.match(robot) or "__" in robot):
        raise MappingError(file, keys["robot"][0], f"{kind} {prop!r}: robot {robot!r} is not a legal ROS base name "
                           "(letters, digits and single _, starting with a letter)")
    freshness = value.get("freshness")
    if "freshness" in value:
        if kind != INPUT:
            raise MappingError(file, keys["freshness"][0], f"{kind} {prop!r}: freshness is for inputs")
        if isinstance(freshness, bool) or not isinstance(freshness, (int, float)) or not 0 <= freshness < float("inf"):
            raise MappingError(file, keys["freshness"][0], f"{kind} {prop!r}: freshness must be a number of seconds "
                               f">= 0 (0: a reading stays valid forever), got {freshness!r}")
    return NodeEntry(proposition=prop, kind=kind, node=node_name, topic=topic, pkg=text("pkg"),
                     filename=text("filename"), parameters={str(k): v for k, v in parameters.items()},
                     type=text("type"), args=text("args") or "", line=line,
                     freshness=float(freshness) if freshness is not None else None, robot=robot)


def _check_negotiation(mapping: Mapping) -> None:
    """The ``negotiation:`` section has the shape ``runtime.resilience.negotiation`` reads (robot:, peers: …),
    checked when the file is read, so every reader of mappings (the executor's ``--check``,
    ``generate_launch``, the mapping panel) refuses a wrong one, not only a running executor."""
    from ltl_stack.runtime.resilience.negotiation import NegotiationError, classes_from_data

    try:
        classes_from_data(mapping.negotiation, mapping.file, mapping.negotiation_line)
    except NegotiationError as err:
        raise MappingError(err.file, err.line, err.message) from None


def _line(node: yaml.Node) -> int:
    return node.start_mark.line + 1


def _keyed_nodes(node: yaml.MappingNode, file: str) -> dict[str, tuple[int, yaml.Node]]:
    """Keys of a YAML mapping node → (line of the key, value node); a repeated key is an error."""
    result: dict[str, tuple[int, yaml.Node]] = {}
    for key_node, value_node in node.value:
        key = str(key_node.value)
        if key in result:
            raise MappingError(file, _line(key_node), f"{key!r} appears twice (first on line {result[key][0]})")
        result[key] = (_line(key_node), value_node)
    return result


def check_mapping(mapping: Mapping, inputs: Sequence[str], outputs: Sequence[str]) -> list[MappingIssue]:
    """Compare a mapping with a spec's propositions (thesis §3.5.1).

    Errors: a proposition the spec does not have (or of the other kind), an input served by more than
    one node, two propositions sharing one proposition topic.
    Warnings: a proposition without a node (the executor still uses its default topic) and a node entry
    without ``node`` (nothing is started for it, so it counts as unmapped and its topic is ignored).
    """
    issues: list[MappingIssue] = []

    def add(severity: str, kind: str, prop: str, message: str, line: int | None = None) -> None:
        issues.append(MappingIssue(severity, message, mapping.file,
                                   mapping.line_of(kind, prop) if line is None else line, prop))

    for kind, section, own, other in ((INPUT, mapping.inputs, inputs, outputs),
                                      (OUTPUT, mapping.outputs, outputs, inputs)):
        for prop in section:
            if prop in own:
                continue
            if prop in other:
                add("error", kind, prop, f"{prop!r} is mapped as an {kind} but the spec declares it as an "
                    f"{OUTPUT if kind == INPUT else INPUT}")
            else:
                add("error", kind, prop, f"{kind} {prop!r} is not a proposition of the spec "
                    f"(its {kind}s: {', '.join(own) or 'none'})")
        for prop in own:
            entries = section.get(prop) or []
            named = [e for e in entries if e.node is not None]
            if not entries:
                add("warning", kind, prop, f"{kind} {prop!r} is not mapped to any node; "
                    "the executor uses its default topic")
            elif not named:
                add("warning", kind, prop, f"{kind} {prop!r} has no entry with a 'node'; it is treated as "
                    "unmapped and the executor uses its default topic")
            elif len(named) < len(entries):
                line = next(e.line for e in entries if e.node is None)
                add("warning", kind, prop, f"{kind} {prop!r} has an entry without 'node'; it is ignored", line)
            if kind == INPUT and len(named) > 1:
                add("error", kind, prop, f"input {prop!r} is mapped to {len(named)} nodes "
                    f"({', '.join(e.node for e in named)}); an input topic takes exactly one publisher "
                    "(thesis §3.5.1): use one input proposition per node")
    namespace = mapping.scenario_namespace() or ""
    in_topics, out_topics = resolve_topics(mapping, inputs, outputs, namespace)
    users: dict[str, list[tuple[str, str]]] = {}
    for prop, topic in in_topics.items():
        users.setdefault(topic, []).append((INPUT, prop))
    for prop, topics in out_topics.items():
        for topic in topics:
            users.setdefault(topic, []).append((OUTPUT, prop))
    for topic, props in users.items():
        if len(props) > 1:
            kind, prop = props[1]
            names = " and ".join(f"{k} {p!r}" for k, p in props)
            add("error", kind, prop, f"{names} share the proposition topic {topic}; each proposition needs its own")
    return issues


def default_topic(namespace: str, kind: str, prop: str) -> str:
    """``/<ns>/inputs/<prop>`` or ``/<ns>/outputs/<prop>`` (the thesis' layout)."""
    group = "inputs" if kind == INPUT else "outputs"
    return posixpath.join("/", namespace.strip("/"), group, prop)


def resolve_node_name(name: str, namespace: str) -> str:
    """A mapping node name made global: relative node names live in the scenario namespace ``/<ns>``,
    where ``generate_launch`` starts them (beside the executor and the robot's nodes, so their relative
    topic parameters reach the robot's topics)."""
    if name.startswith("/"):
        return posixpath.normpath(name)
    return posixpath.normpath(posixpath.join("/", namespace.strip("/"), name))


def resolve_name(name: str, namespace: str, kind: str) -> str:
    """A mapping name made global: relative names live in the ``<ns>/inputs`` or ``<ns>/outputs`` group."""
    if name.startswith("/"):
        return posixpath.normpath(name)
    return posixpath.join(default_topic(namespace, kind, ""), name).rstrip("/")


def resolve_topics(mapping: Mapping | None, inputs: Iterable[str], outputs: Iterable[str],
                   namespace: str) -> tuple[dict[str, str], dict[str, list[str]]]:
    """The executor's topics: input prop → the topic it subscribes, output prop → topics it publishes.

    A proposition uses the topics of its named node entries, else its default topic.
    For an input with several nodes (an error of ``check_mapping``) the first one's topic is used.
    """
    in_topics: dict[str, str] = {}
    out_topics: dict[str, list[str]] = {}
    for prop in inputs:
        topics = _entry_topics(mapping, INPUT, prop, namespace)
        in_topics[prop] = topics[0] if topics else default_topic(namespace, INPUT, prop)
    for prop in outputs:
        out_topics[prop] = _entry_topics(mapping, OUTPUT, prop, namespace) or [default_topic(namespace, OUTPUT, prop)]
    return in_topics, out_topics


def valuation_topics(mapping: Mapping | None, inputs: Iterable[str], namespace: str) -> dict[str, list[str]]:
    """``<node>/valuation`` of every node that owns several inputs (region localization, an
    exactly-one group) -> those inputs: such a node also publishes the valuation of all its
    propositions as one ``ltl_stack/PropositionValuation`` (keys: their topics), so that one change of
    several of them is one update."""
    owners: dict[str, list[str]] = {}
    for prop in inputs:
        entry = next((e for e in (mapping.inputs.get(prop) or []) if e.node), None) if mapping else None
        if entry is not None:
            owners.setdefault(resolve_node_name(entry.node, namespace), []).append(prop)
    return {posixpath.join(node, "valuation"): props for node, props in owners.items() if len(props) > 1}


def _entry_topics(mapping: Mapping | None, kind: str, prop: str, namespace: str) -> list[str]:
    if mapping is None:
        return []
    section = mapping.inputs if kind == INPUT else mapping.outputs
    topics: list[str] = []
    for entry in section.get(prop) or []:
        if entry.node is None:
            continue
        topic = resolve_name(entry.topic, namespace, kind) if entry.topic else default_topic(namespace, kind, prop)
        if topic not in topics:
            topics.append(topic)
    return topics


def format_mapping(mapping: Mapping) -> str:
    """The mapping as YAML in the thesis stack's layout (one node: a mapping; several: a list);
    ``parse_mapping`` reads it back to the same propositions, nodes and parameters."""
    data: dict[str, Any] = {}
    if mapping.namespace:
        data["namespace"] = mapping.namespace
    for key, section in (("inputs", mapping.inputs), ("outputs", mapping.outputs)):
        if not section:
            continue
        data[key] = {}
        for prop, entries in section.items():
            items = [_entry_dict(e) for e in entries]
            data[key][prop] = None if not items else items[0] if len(items) == 1 else items
    if mapping.expected_feedback:
        declared: dict[str, list[str]] = {}
        for output, input_, _ in mapping.expected_feedback:
            declared.setdefault(output, []).append(input_)
        data["expected_feedback"] = declared
    if mapping.negotiation is not None:  # kept as written: saving a mapping never drops a section
        data["negotiation"] = mapping.negotiation
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False, allow_unicode=True)


def _entry_dict(entry: NodeEntry) -> dict[str, Any]:
    fields = [("node", entry.node), (_TOPIC_KEY[entry.kind], entry.topic), ("pkg", entry.pkg),
              ("filename", entry.filename), ("type", entry.type), ("args", entry.args or None),
              ("parameters", dict(entry.parameters) or None), ("freshness", entry.freshness),
              ("robot", entry.robot)]
    return {key: value for key, value in fields if value is not None}


def errors(issues: Iterable[MappingIssue]) -> list[MappingIssue]:
    return [i for i in issues if i.severity == "error"]


def misfit(issues: Iterable[MappingIssue]) -> MappingError | None:
    """The one error line of a mapping that does not fit its spec (every tool says it alike): the
    first error with its file and line, and how many more there are; None when there is none."""
    bad = errors(issues)
    if not bad:
        return None
    more = f" (and {len(bad) - 1} more mapping errors)" if len(bad) > 1 else ""
    return MappingError(bad[0].file, bad[0].line, bad[0].message + more)
