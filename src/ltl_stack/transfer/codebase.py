"""A.1: channel statistics mined from a codebase of programs for a robot (thesis §2.5.1, Table 2.1).

Statistics are YAML: ``robot -> message type -> channel name -> count``, plus ``scripts: N`` (how
many programs were mined). Channel names are counted without a leading ``/``.
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.inputs import load_yaml, read_text

from .channels import NAMED_KINDS, find_channels
from .errors import TransferError


@dataclass
class ChannelStats:
    """Counts of channel names per message type for one robot."""

    robot: str
    scripts: int = 0
    counts: dict[str, Counter] = field(default_factory=dict)
    skipped: list[str] = field(default_factory=list)

    def add(self, msg_type: str, name: str, n: int = 1) -> None:
        self.counts.setdefault(msg_type, Counter())[name.lstrip("/")] += n

    def merge(self, other: ChannelStats) -> None:
        self.scripts += other.scripts
        for msg_type, counter in other.counts.items():
            for name, n in counter.items():
                self.add(msg_type, name, n)

    def candidates(self, msg_type: str | None) -> list[tuple[str, int, float]]:
        """(channel, count, probability) for a type, most probable first; matches a bare type name too."""
        if not msg_type:
            return []
        counter: Counter = Counter()
        for known, names in self.counts.items():
            if known == msg_type or ("/" not in msg_type and known.split("/")[-1] == msg_type) \
                    or ("/" not in known and msg_type.split("/")[-1] == known):
                counter.update(names)
        total = sum(counter.values())
        ranked = sorted(counter.items(), key=lambda kv: (-kv[1], kv[0]))
        return [(name, n, n / total) for name, n in ranked]

    def to_yaml_data(self) -> dict:
        body: dict = {"scripts": self.scripts}
        for msg_type in sorted(self.counts):
            body[msg_type] = dict(sorted(self.counts[msg_type].items(), key=lambda kv: (-kv[1], kv[0])))
        return {self.robot: body}


def is_python_program(path: Path) -> bool:
    if path.suffix == ".py":
        return True
    if path.suffix:
        return False
    try:
        with open(path, "rb") as f:
            first = f.readline(200)
    except OSError:
        return False
    return first.startswith(b"#!") and b"python" in first


def mine_programs(folder: str | Path, robot: str, progress=None) -> ChannelStats:
    """Scan every Python program under ``folder`` and count its channel names per message type."""
    folder = Path(folder)
    if not folder.is_dir():
        raise TransferError("codebase folder does not exist", str(folder))
    stats = ChannelStats(robot)
    files = sorted(p for p in folder.rglob("*") if p.is_file() and is_python_program(p))
    for i, path in enumerate(files, 1):
        if progress:
            progress(f"[{i}/{len(files)}] {path}")
        try:
            uses = find_channels(read_text(path, "program"), str(path))
        except (TransferError, InputError) as err:
            stats.skipped.append(str(err))
            continue
        stats.scripts += 1
        for use in uses:
            if use.kind in NAMED_KINDS \
                    and use.name.value and use.msg_type:
                stats.add(use.msg_type, use.name.value)
    return stats


def parse_stats_file(path: str | Path) -> dict[str, ChannelStats]:
    """Read a statistics YAML (one or more robots)."""
    path = Path(path)
    data = load_yaml(path, "channel statistics file")
    if not isinstance(data, dict):
        raise TransferError("expected robot -> message type -> channel -> count", str(path))
    result = {}
    for robot, body in data.items():
        if not isinstance(body, dict):
            raise TransferError("expected a mapping of message types", str(path), str(robot))
        stats = ChannelStats(str(robot))
        for key, names in body.items():
            if key == "scripts":
                if isinstance(names, bool) or not isinstance(names, int) or names < 0:
                    raise TransferError("scripts must be a whole number", str(path), f"{robot}.scripts")
                stats.scripts = names
                continue
            if not isinstance(names, dict):
                raise TransferError("expected channel -> count", str(path), f"{robot}.{key}")
            for name, n in names.items():
                if isinstance(n, bool) or not isinstance(n, int) or n < 0:
                    raise TransferError(f"count must be a whole number, got {n!r}", str(path),
                                        f"{robot}.{key}.{name}")
                stats.add(str(key), str(name), n)
        result[str(robot)] = stats
    return result


def load_codebase(path: str | Path, robot: str, progress=None) -> ChannelStats | None:
    """Statistics for ``robot`` from a YAML file, or a folder of YAML files and/or ``<robot>/`` programs."""
    path = Path(path)
    if path.is_file():
        return parse_stats_file(path).get(robot)
    if not path.is_dir():
        raise TransferError("codebase file or folder does not exist", str(path))
    found: ChannelStats | None = None
    for stats_file in sorted(path.glob("*.yaml")):
        stats = parse_stats_file(stats_file).get(robot)
        if stats:
            found = found or ChannelStats(robot)
            found.merge(stats)
    if (path / robot).is_dir():
        found = found or ChannelStats(robot)
        found.merge(mine_programs(path / robot, robot, progress))
    return found
