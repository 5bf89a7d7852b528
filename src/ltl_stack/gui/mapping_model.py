"""What the mapping panel edits and checks (thesis §3.6.1.1, Fig. 3.5), without Qt or ROS.

A ``MappingDocument`` holds the spec's propositions and, per proposition, the node rows being edited
(an input has one row, an output one row per node). Saving a loaded file changes only the edited rows
in its text (``runtime.config.mapping_edit``, a round-trip YAML writer): comments, ``expected_feedback:``,
``negotiation:`` and every entry's other keys come back as they were; a file changed on disk since it
was read is noticed (``changed_on_disk``) so the panel asks before overwriting it.
``validate`` joins ``runtime.config.mapping.check_mapping`` with what only the live graph can tell: a node
that is not on the master, an input topic with more than one publisher, a topic that is not a
``std_msgs/Bool``. ``LiveGraph`` is the master's graph as the drop-downs need it (from a snapshot).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from typing import Any

from ltl_stack.analysis.snapshot import Snapshot
from ltl_stack.cli import check_outputs, write_output
from ltl_stack.errors import InputError
from ltl_stack.inputs import read_text
from ltl_stack.runtime.config.launch import generate_launch
from ltl_stack.runtime.config.mapping import (
    INPUT,
    OUTPUT,
    Mapping,
    MappingError,
    NodeEntry,
    check_mapping,
    default_topic,
    format_mapping,
    parse_mapping,
    resolve_name,
    resolve_node_name,
)
from ltl_stack.runtime.config.mapping_edit import EditedRow, rows_text, text_digest
from ltl_stack.spec import load_spec

PROPOSITION_TYPE = "std_msgs/Bool"
ERROR, WARNING = "error", "warning"


@dataclass
class Row:
    """One proposition node being edited; ``base`` is the loaded entry whose other keys are kept."""

    node: str = ""
    topic: str = ""
    base: NodeEntry | None = None
    origin: int | None = None  # index of the file's entry it was loaded from (None: a new row)


@dataclass(frozen=True)
class Finding:
    """One validation message; ``row`` is the index of the row it concerns, -1 for the proposition."""

    severity: str
    kind: str
    proposition: str
    message: str
    row: int = -1

    def __str__(self) -> str:
        return f"{self.severity}: {self.message}"


class LiveGraph:
    """Nodes and topics of the master (a ``Snapshot``) as the drop-downs list them."""

    def __init__(self, snapshot: Snapshot):
        self.snapshot = snapshot
        self.nodes: list[str] = sorted(snapshot.nodes)
        self.topics: list[str] = sorted(snapshot.topics)
        self._pub: dict[str, list[str]] = {}
        self._sub: dict[str, list[str]] = {}
        for name, t in sorted(snapshot.topics.items()):
            for n in t.publishers:
                self._pub.setdefault(n, []).append(name)
            for n in t.subscribers:
                self._sub.setdefault(n, []).append(name)

    def published_by(self, node: str) -> list[str]:
        return list(self._pub.get(node, []))

    def subscribed_by(self, node: str) -> list[str]:
        return list(self._sub.get(node, []))

    def topics_for(self, kind: str, node: str) -> list[str]:
        """The topic drop-down of a row: what an input node publishes, what an output node subscribes."""
        return self.published_by(node) if kind == INPUT else self.subscribed_by(node)

    def publishers(self, topic: str) -> list[str]:
        t = self.snapshot.topics.get(topic)
        return list(t.publishers) if t else []

    def type_of(self, topic: str) -> str:
        t = self.snapshot.topics.get(topic)
        return t.type if t else ""


@dataclass
class MappingDocument:
    """The spec's propositions and the rows mapped to them; the panel's whole state."""

    spec_path: str
    inputs: list[str]
    outputs: list[str]
    mapping_path: str = ""
    namespace: str | None = None
    rows: dict[tuple[str, str], list[Row]] = field(default_factory=dict)
    extra: dict[tuple[str, str], list[NodeEntry]] = field(default_factory=dict)  # not in the spec: kept
    negotiation: Any = None  # the mapping's negotiation: section, not edited here: written back as loaded
    expected_feedback: list = field(default_factory=list)  # (output, input, line): written back as loaded
    source_text: str = ""  # the mapping file's text as loaded: what Save edits (rows point at its entries)
    source_digest: str = ""  # SHA-256 of the text loaded or last saved, to notice a file changed on disk

    @classmethod
    def load(cls, spec_path: str, mapping_path: str | None = None) -> MappingDocument:
        """Propositions from the spec (any format ``load_spec`` reads), rows from the mapping if given.

        Raises the loaders' ``SpecError``/``MappingError`` (both ``UserError``: ``file:line: message``).
        """
        spec = load_spec(spec_path)
        doc = cls(str(spec_path), list(spec.inputs), list(spec.outputs))
        for prop in doc.inputs:
            doc.rows[(INPUT, prop)] = [Row()]
        for prop in doc.outputs:
            doc.rows[(OUTPUT, prop)] = []
        if mapping_path:
            text = read_mapping_text(str(mapping_path))
            doc.merge(parse_mapping(text, str(mapping_path)))
            doc.mapping_path = str(mapping_path)
            doc.source_text, doc.source_digest = text, text_digest(text)
        return doc

    def merge(self, mapping: Mapping) -> None:
        """Take the mapping's entries: rows for the spec's propositions, ``extra`` for the others."""
        self.namespace = mapping.namespace
        self.negotiation = mapping.negotiation
        self.expected_feedback = list(mapping.expected_feedback)
        for kind, section in ((INPUT, mapping.inputs), (OUTPUT, mapping.outputs)):
            for prop, entries in section.items():
                if (kind, prop) not in self.rows:
                    self.extra[(kind, prop)] = list(entries)
                    continue
                rows = [Row(e.node or "", e.topic or "", e, i) for i, e in enumerate(entries)]
                if kind == INPUT and not rows:
                    rows = [Row()]
                self.rows[(kind, prop)] = rows

    def propositions(self, kind: str) -> list[str]:
        return self.inputs if kind == INPUT else self.outputs

    def row(self, kind: str, prop: str, index: int = 0) -> Row:
        return self.rows[(kind, prop)][index]

    def set_node(self, kind: str, prop: str, index: int, node: str) -> None:
        self.rows[(kind, prop)][index].node = node.strip()

    def set_topic(self, kind: str, prop: str, index: int, topic: str) -> None:
        self.rows[(kind, prop)][index].topic = topic.strip()

    def add_row(self, prop: str) -> int:
        """A new node row for output ``prop`` (the ``+`` of Fig. 3.5); returns its index."""
        rows = self.rows[(OUTPUT, prop)]
        topic = default_topic(self.scenario_namespace(), OUTPUT, prop)
        rows.append(Row(topic=self.relative_name(OUTPUT, "topic", topic)))  # relative in a relative mapping
        return len(rows) - 1

    def delete_row(self, kind: str, prop: str, index: int) -> None:
        """Delete a node row; an input keeps one (empty) row, as an input has exactly one node."""
        rows = self.rows[(kind, prop)]
        del rows[index]
        if kind == INPUT and not rows:
            rows.append(Row())

    def scenario_namespace(self) -> str:
        """The namespace of the proposition topics: the mapping's, else the spec's file name."""
        return self.to_mapping().scenario_namespace() or os.path.splitext(os.path.basename(self.spec_path))[0]

    def to_mapping(self, file: str | None = None) -> Mapping:
        """The mapping as edited, in spec order, entries not in the spec after them (as loaded)."""
        mapping = Mapping(file=file or self.mapping_path or "<mapping panel>", namespace=self.namespace,
                          negotiation=self.negotiation, expected_feedback=list(self.expected_feedback))
        for kind in (INPUT, OUTPUT):
            target = mapping.inputs if kind == INPUT else mapping.outputs
            for prop in self.propositions(kind):
                entries = [self._entry(kind, prop, r) for r in self.rows[(kind, prop)] if r.node or r.base]
                if entries:
                    target[prop] = entries
            for (k, prop), entries in self.extra.items():
                if k == kind:
                    target[prop] = list(entries)
        return mapping

    @staticmethod
    def _entry(kind: str, prop: str, row: Row) -> NodeEntry:
        node, topic = row.node or None, row.topic or None
        if row.base is not None:
            return replace(row.base, node=node, topic=topic)
        return NodeEntry(proposition=prop, kind=kind, node=node, topic=topic)

    def text(self) -> str:
        """The YAML ``save`` writes: the loaded file with the edited rows changed and everything else as
        it was (``runtime.config.mapping_edit.rows_text``); a new mapping, or a file the round-trip writer cannot
        take, as ``runtime.config.mapping.format_mapping`` writes it (comments are then lost)."""
        if self.source_text:
            rows = {key: [EditedRow(r.node, r.topic, r.origin) for r in rows if r.node or r.base]
                    for key, rows in self.rows.items()}
            kept = rows_text(self.source_text, rows)
            if kept is not None:
                return kept
        return format_mapping(self.to_mapping())

    def changed_on_disk(self, path: str | None = None) -> bool:
        """True when the file at ``path`` (default: the loaded one) is not the text this document loaded
        or last saved: someone edited it meanwhile. A file that is gone counts as changed."""
        path = path or self.mapping_path
        if not path or not self.source_digest:
            return False
        try:
            return text_digest(read_mapping_text(path)) != self.source_digest
        except MappingError:
            return True

    def save(self, path: str) -> None:
        """Write atomically (nothing half-written on failure). Raises ``UserError`` when ``path`` is the
        spec, ``OutputError`` when it cannot be written."""
        check_outputs([self.spec_path], [path])
        text = self.text()
        write_output(path, text, "mapping")
        self.mapping_path = str(path)
        # the rows keep pointing at the loaded text's entries (``source_text`` is never replaced, so an Undo
        # after a Save still edits the right entry); what is on disk now is what was written
        self.source_digest = text_digest(text)

    def resolved_node(self, kind: str, node: str, graph: LiveGraph | None = None) -> str:
        """The global node name: relative node names live in the scenario namespace ``/<ns>``, where
        generated launch files start them (``runtime.config.mapping.resolve_node_name``), so a completion input
        (thesis §4.3) and its output name the same node (``pickup_ac`` and ``pickup``: ``/<ns>/pickup``)."""
        return resolve_node_name(node, self.scenario_namespace())

    @property
    def relative(self) -> bool:
        """True when the mapping names things relative to its scenario namespace (a ``namespace:`` key or
        a relative name in a row): names picked from the master's absolute lists are then written relative."""
        if self.namespace:
            return True
        names = [n for rows in self.rows.values() for r in rows for n in (r.node, r.topic) if n]
        return any(not n.startswith("/") for n in names)

    def relative_name(self, kind: str, which: str, name: str) -> str:
        """``name`` (a node, or a topic when ``which == "topic"``) as this mapping writes it: relative to
        the scenario namespace when the mapping is relative and the name lies in it (so it resolves back
        to ``name`` exactly), else unchanged."""
        if not self.relative or not name.startswith("/"):
            return name
        ns = self.scenario_namespace()
        group = "/" + ns.strip("/") if which == "node" else default_topic(ns, kind, "").rstrip("/")
        if not name.startswith(group + "/"):
            return name
        short = name[len(group) + 1:]
        back = resolve_node_name(short, ns) if which == "node" else resolve_name(short, ns, kind)
        return short if back == name else name

    def resolved_topic(self, kind: str, prop: str, row: Row) -> str:
        ns = self.scenario_namespace()
        return resolve_name(row.topic, ns, kind) if row.topic else default_topic(ns, kind, prop)

    def validate(self, graph: LiveGraph | None = None) -> list[Finding]:
        """``check_mapping``'s errors and warnings, plus the live checks when ``graph`` is given."""
        findings = []
        for issue in check_mapping(self.to_mapping(), self.inputs, self.outputs):
            kind = INPUT if (INPUT, issue.proposition) in self.rows or \
                (INPUT, issue.proposition) in self.extra else OUTPUT
            findings.append(Finding(issue.severity, kind, issue.proposition, issue.message))
        for (kind, prop), rows in self.rows.items():
            for i, row in enumerate(rows):
                if not row.node:
                    if row.topic and (kind == OUTPUT or len(rows) > 1):
                        findings.append(Finding(WARNING, kind, prop, f"{kind} {prop!r}: a row has topic "
                                                f"{row.topic} but no node; it is ignored", i))
                    continue
                if graph is not None:
                    findings.extend(self._live(graph, kind, prop, i, row))
        return findings

    def _live(self, graph: LiveGraph, kind: str, prop: str, i: int, row: Row) -> list[Finding]:
        found = []
        node = self.resolved_node(kind, row.node, graph)
        topic = self.resolved_topic(kind, prop, row)
        if node not in graph.snapshot.nodes:
            found.append(Finding(WARNING, kind, prop, f"{kind} {prop!r}: node {node} is not on the master "
                                 "(not launched yet, or a typo)", i))
        if kind == INPUT:
            others = [n for n in graph.publishers(topic) if n != node]
            if others:
                found.append(Finding(ERROR, kind, prop, f"input {prop!r}: topic {topic} has other publishers "
                                     f"({', '.join(others)}); an input topic takes exactly one (thesis §3.5.1)", i))
        elif node in graph.snapshot.nodes and topic not in graph.subscribed_by(node):
            found.append(Finding(WARNING, kind, prop, f"output {prop!r}: node {node} does not subscribe to {topic} "
                                 "on the master: it will not hear the executor", i))
        type_ = graph.type_of(topic)
        if type_ and type_ != PROPOSITION_TYPE:
            found.append(Finding(ERROR, kind, prop, f"{kind} {prop!r}: topic {topic} has type {type_}, "
                                 f"a proposition topic must be {PROPOSITION_TYPE}", i))
        return found


def read_mapping_text(path: str) -> str:
    """A mapping file's text; ``MappingError`` (file, line, message) when it cannot be read."""
    try:
        return read_text(path, "mapping file")
    except InputError as err:  # missing, a folder, binary, not UTF-8
        raise MappingError(path, err.line, err.message) from None


def launch_file(doc: MappingDocument, out: str) -> list[str]:
    """Write the launch file of the saved mapping (``generate_launch``) atomically; returns its warnings.

    The launch file names the mapping by its path, so the document must have been saved.
    Raises ``LaunchError`` when the mapping does not fit the spec, ``UserError`` when ``out`` is an input
    or cannot be written.
    """
    if not doc.mapping_path:
        raise ValueError("save the mapping first: the launch file names it by its path")
    check_outputs([doc.spec_path, doc.mapping_path], [out])
    mapping = doc.to_mapping(doc.mapping_path)
    result = generate_launch(mapping, spec_path=os.path.abspath(doc.spec_path), namespace=doc.scenario_namespace(),
                             propositions=(doc.inputs, doc.outputs))
    write_output(out, result.xml, "launch file")
    return result.warnings
