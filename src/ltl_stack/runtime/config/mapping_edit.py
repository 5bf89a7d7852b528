"""Writing edited node rows back into a mapping YAML file, keeping everything that was not edited.

The mapping panel edits only each proposition's node rows (``node`` and the topic key); a file also has
comments, ``namespace:``, ``expected_feedback:``, ``negotiation:`` and per-entry keys (``pkg``,
``filename``, ``parameters``, ``type``, ``args``) that saving must not lose. The file is loaded with
ruamel.yaml's round-trip loader and only the edited values are changed in it, so comments, key order,
quoting and untouched sections come back as they were (``rows_text``). A file ruamel.yaml cannot
take (a proposition key written twice, as the thesis' mapping GUI does for two nodes) is ``None``:
the caller writes the whole mapping instead (``runtime.config.mapping.format_mapping``).
"""
from __future__ import annotations

import hashlib
import io
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ltl_stack.runtime.config.mapping import _TOPIC_KEY, INPUT


@dataclass(frozen=True)
class EditedRow:
    """One node row as edited: ``origin`` is the index of the entry it was loaded from (None: new)."""

    node: str
    topic: str
    origin: int | None = None


def text_digest(text: str) -> str:
    """SHA-256 of a file's text: what tells that a file changed on disk since it was read."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _yaml(original: str):
    from ruamel.yaml import YAML

    yaml = YAML()  # round trip
    yaml.preserve_quotes = True
    yaml.width = 4096  # never fold a long line the file did not fold
    # lists written under their key ("  - node: a") or indented below it ("    - node: a"), as the file does
    first = re.search(r"^( *)- ", original, re.M)
    indented = False
    if first is not None:
        before = original[:first.start()].rstrip("\n").rsplit("\n", 1)[-1]
        indented = len(first.group(1)) > len(before) - len(before.lstrip(" "))
    yaml.indent(mapping=2, sequence=4 if indented else 2, offset=2 if indented else 0)
    return yaml


def _set(item, key: str, value: str) -> bool:
    """Set ``item[key]`` to ``value`` (deleted when empty), keeping the old value's quoting; True if changed."""
    old = item.get(key)
    if not value:
        if key in item:
            del item[key]
            return True
        return False
    if old is not None and str(old).strip() == value:
        return False
    item[key] = type(old)(value) if isinstance(old, str) and type(old) is not str else value
    return True


def rows_text(original: str, rows: dict[tuple[str, str], Sequence[EditedRow]]) -> str | None:
    """``original`` (a mapping file's text) with each ``(kind, proposition)``'s node rows replaced by
    ``rows`` and nothing else changed; ``original`` itself when no row changed; None when ruamel.yaml
    cannot round-trip the file (see the module doc)."""
    from ruamel.yaml.comments import CommentedMap, CommentedSeq
    from ruamel.yaml.error import YAMLError

    yaml = _yaml(original)
    try:
        data = yaml.load(original)
    except YAMLError:
        return None
    if data is None:
        data = CommentedMap()
    if not isinstance(data, dict):
        return None
    changed = False
    for (kind, prop), edited in rows.items():
        key = "inputs" if kind == INPUT else "outputs"
        section = data.get(key)
        old = section.get(prop) if isinstance(section, dict) else None
        old_items = [old] if isinstance(old, dict) else list(old) if isinstance(old, list) else []
        items, touched = [], False
        for row in edited:
            fresh = row.origin is None or row.origin >= len(old_items) or not isinstance(old_items[row.origin], dict)
            item = CommentedMap() if fresh else old_items[row.origin]
            touched |= fresh
            touched |= _set(item, "node", row.node)
            touched |= _set(item, _TOPIC_KEY[kind], row.topic)
            items.append(item)
        if not touched and [id(i) for i in items] == [id(i) for i in old_items]:
            continue
        if not items and old is None:
            continue
        changed = True
        if not isinstance(section, dict):
            section = data[key] = CommentedMap()
        if not items:  # no node left: the proposition is unmapped, as format_mapping writes it
            del section[prop]
        elif len(items) == 1 and not isinstance(old, list):
            if section.get(prop) is not items[0]:
                section[prop] = items[0]
        elif isinstance(old, list):
            if [id(i) for i in items] != [id(i) for i in old]:
                old[:] = items
        else:
            section[prop] = CommentedSeq(items)
    if not changed:
        return original
    out = io.StringIO()
    yaml.dump(data, out)
    return out.getvalue()


__all__ = ["EditedRow", "rows_text", "text_digest"]
