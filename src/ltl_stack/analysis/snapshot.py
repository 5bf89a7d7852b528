"""A snapshot of a ROS computation graph as the master reports it, saved and loaded as YAML or JSON.

The snapshot is the raw material of the analysis (thesis section 3.5.2): every node, every topic
with its type, publishers and subscribers, and the services (listed, not analysed). Saving it lets
the analysis run offline, in CI, or on a graph taken from another robot.

File format (YAML or JSON, chosen by the file suffix; ``.json`` is JSON, anything else YAML)::

    format: ltl_stack/graph_snapshot/1
    master: http://localhost:11311/      # where it was taken (informative)
    taken: '2026-11-21T12:00:00Z'        # when (informative)
    nodes: [/move_base, /pickup]
    topics:
      /cmd_vel: {type: geometry_msgs/Twist, publishers: [/move_base], subscribers: [/base]}
    services:
      /move_base/make_plan: [/move_base]
"""
from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from ltl_stack.cli import write_output
from ltl_stack.errors import InputError, UserError
from ltl_stack.inputs import parse_json, parse_yaml, read_text

FORMAT = "ltl_stack/graph_snapshot/1"
_YAML_DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)


class SnapshotError(UserError):
    """A snapshot file that cannot be read (the message names the file and what is wrong), or a
    master the snapshot cannot be taken from (``code`` says which: 2 bad input, 3 no master)."""


@dataclass
class Topic:
    """One topic: its message type ('' when unknown) and the nodes on each side."""

    type: str = ""
    publishers: list[str] = field(default_factory=list)
    subscribers: list[str] = field(default_factory=list)


@dataclass
class Snapshot:
    """Nodes, topics and services of one ROS master at one moment."""

    nodes: list[str] = field(default_factory=list)
    topics: dict[str, Topic] = field(default_factory=dict)
    services: dict[str, list[str]] = field(default_factory=dict)
    master: str = ""
    taken: str = ""

    @classmethod
    def from_system_state(cls, publishers: Iterable, subscribers: Iterable, services: Iterable,
                          topic_types: Iterable = (), *, master: str = "", taken: str = "") -> Snapshot:
        """Build from the lists that the master's ``getSystemState`` and ``getTopicTypes`` return."""
        snap = cls(master=master, taken=taken)
        nodes: set[str] = set()
        for name, type_ in topic_types:
            snap.topics.setdefault(name, Topic()).type = type_
        for name, who in publishers:
            snap.topics.setdefault(name, Topic()).publishers = sorted(set(who))
            nodes.update(who)
        for name, who in subscribers:
            snap.topics.setdefault(name, Topic()).subscribers = sorted(set(who))
            nodes.update(who)
        for name, who in services:
            snap.services[name] = sorted(set(who))
            nodes.update(who)
        snap.nodes = sorted(nodes)
        return snap

    def to_dict(self) -> dict:
        return {
            "format": FORMAT,
            "master": self.master,
            "taken": self.taken,
            "nodes": list(self.nodes),
            "topics": {
                name: {"type": t.type, "publishers": list(t.publishers), "subscribers": list(t.subscribers)}
                for name, t in sorted(self.topics.items())
            },
            "services": {name: list(who) for name, who in sorted(self.services.items())},
        }

    @classmethod
    def from_dict(cls, data: object, where: str = "<snapshot>") -> Snapshot:
        """Parse ``to_dict`` output; raises ``SnapshotError`` naming ``where`` and the bad entry."""
        if not isinstance(data, Mapping):
            raise SnapshotError(f"{where}: expected a mapping with 'nodes' and 'topics'")
        fmt = data.get("format", FORMAT)
        if fmt != FORMAT:
            raise SnapshotError(f"{where}: unknown format {fmt!r} (expected {FORMAT!r})")
        snap = cls(master=str(data.get("master") or ""), taken=str(data.get("taken") or ""))
        snap.nodes = _names(data.get("nodes") or [], f"{where}: nodes")
        topics = data.get("topics") or {}
        if not isinstance(topics, Mapping):
            raise SnapshotError(f"{where}: 'topics' must be a mapping of topic name to its entry")
        for name, entry in topics.items():
            if not isinstance(entry, Mapping):
                raise SnapshotError(f"{where}: topic {name!r}: expected a mapping with type/publishers/subscribers")
            snap.topics[str(name)] = Topic(
                type=str(entry.get("type") or ""),
                publishers=_names(entry.get("publishers") or [], f"{where}: topic {name}: publishers"),
                subscribers=_names(entry.get("subscribers") or [], f"{where}: topic {name}: subscribers"),
            )
        services = data.get("services") or {}
        if not isinstance(services, Mapping):
            raise SnapshotError(f"{where}: 'services' must be a mapping of service name to provider nodes")
        for name, who in services.items():
            snap.services[str(name)] = _names(who or [], f"{where}: service {name}")
        known = set(snap.nodes)
        for t in snap.topics.values():
            known.update(t.publishers)
            known.update(t.subscribers)
        for who in snap.services.values():
            known.update(who)
        snap.nodes = sorted(known)
        return snap

    def to_text(self, json_format: bool = False) -> str:
        """The file text: JSON when ``json_format``, else YAML."""
        data = self.to_dict()
        if json_format:
            return json.dumps(data, indent=1) + "\n"
        return yaml.dump(data, Dumper=_YAML_DUMPER, sort_keys=False, default_flow_style=None, width=120)

    def save(self, path: str | os.PathLike) -> None:
        """Write atomically (temp file + rename); JSON for ``.json``, YAML otherwise. A failure is
        ``OutputError`` (``Exit.WRITE_FAILED``) and leaves no file behind."""
        write_output(path, self.to_text(is_json_path(path)), "snapshot")

    @classmethod
    def load(cls, path: str | os.PathLike) -> Snapshot:
        """Read a snapshot (JSON for ``.json``, YAML otherwise) through ``ltl_stack.inputs``: a file
        that is missing, binary, not UTF-8, invalid, too deeply nested, with non-string keys or
        over-long integers is a ``SnapshotError`` naming file and line."""
        file = str(path)
        try:
            text = read_text(path, "snapshot")
            data = parse_json(text, file) if is_json_path(path) else parse_yaml(text, file)
        except InputError as e:
            raise SnapshotError(str(e)) from None
        return cls.from_dict(data, file)


def is_json_path(path: str | os.PathLike) -> bool:
    """Snapshots named ``*.json`` are JSON, all others YAML."""
    return Path(path).suffix.lower() == ".json"


def _names(value: object, where: str) -> list[str]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise SnapshotError(f"{where}: expected a list of names")
    return sorted(set(value))
