"""Reading users' files safely: one ``InputError`` naming file and line for anything that is not
what it should be, and bounded time and memory on hostile input.

Every loader of the project (specs, mappings, snapshots, region maps, schedules, limits, URDF,
codebase counts, saved strategies, programs) reads through these functions, so a device or FIFO
where a file should be, a file above ``MAX_INPUT_BYTES``, a binary file, a
file that is not UTF-8, YAML whose keys are not strings, nesting deeper than any real file has, or an
integer longer than Python converts all give the same kind of message instead of a traceback.
"""
from __future__ import annotations

import json
import os
import re
from itertools import accumulate
from typing import Any

import yaml

from ltl_stack.errors import InputError
from ltl_stack.textio import MAX_INPUT_BYTES, decode_text, read_bytes, read_text

__all__ = ["MAX_ALIASES", "MAX_DEPTH", "MAX_INPUT_BYTES", "MAX_INT_DIGITS", "construct_yaml", "decode_text",
           "load_json", "load_yaml", "parse_json", "parse_yaml", "parse_yaml_node", "read_bytes", "read_text"]

#: nesting deeper than this (YAML or JSON) is refused: no file of ours needs a tenth of it, and the
#: recursive parsers of PyYAML and json would otherwise end in RecursionError
MAX_DEPTH = 100
#: YAML aliases (``*ref``) in one document; a "billion laughs" file multiplies through them
MAX_ALIASES = 1000
#: digits of one integer; Python refuses to convert longer ones (sys.get_int_max_str_digits)
MAX_INT_DIGITS = 4000

_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)  # libyaml when present: big files load fast
_STR_TAG = "tag:yaml.org,2002:str"
_INT_TAG = "tag:yaml.org,2002:int"


def parse_yaml_node(text: str, file: str) -> yaml.Node | None:
    """Compose a YAML document into nodes (with line marks) after checking it is safe to use.

    Refused with ``InputError`` (file:line): invalid YAML, nesting deeper than ``MAX_DEPTH``, more
    than ``MAX_ALIASES`` aliases, a mapping key that is not a string (``5:``, ``yes:``, ``~:``), an
    integer of more than ``MAX_INT_DIGITS`` digits, more than one document.
    """
    try:
        _check_events(text, file)
        loader = _LOADER(text)
        try:
            node = loader.get_single_node()
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        line = mark.line + 1 if mark is not None else 0
        raise InputError(file, f"invalid YAML: {e.problem or e.context}", line) from None
    except yaml.YAMLError as e:
        raise InputError(file, f"invalid YAML: {e}") from None
    if node is not None:
        _check_nodes(node, file)
    return node


def construct_yaml(node: yaml.Node | None, file: str) -> Any:
    """The Python data of a node checked by ``parse_yaml_node``."""
    if node is None:
        return None
    loader = _LOADER("")
    try:
        return loader.construct_document(node)
    except (yaml.YAMLError, ValueError) as e:
        line = node.start_mark.line + 1 if getattr(node, "start_mark", None) else 0
        raise InputError(file, f"invalid YAML value: {e}", line) from None
    finally:
        loader.dispose()


def parse_yaml(text: str, file: str) -> Any:
    """``text`` as YAML data with the checks of ``parse_yaml_node``."""
    return construct_yaml(parse_yaml_node(text, file), file)


def load_yaml(path: str | os.PathLike, what: str = "YAML file") -> Any:
    """Read and parse a YAML file with every check of ``read_text`` and ``parse_yaml_node``."""
    return parse_yaml(read_text(path, what), str(path))


def parse_json(text: str, file: str) -> Any:
    """``text`` as JSON, refusing nesting deeper than ``MAX_DEPTH`` and over-long integers."""
    depth = _json_depth(text)
    if depth[0] > MAX_DEPTH:
        raise InputError(file, f"nested more than {MAX_DEPTH} levels deep", depth[1])
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise InputError(file, f"invalid JSON: {e.msg} (column {e.colno})", e.lineno) from None
    except ValueError as e:  # an integer longer than Python converts
        raise InputError(file, f"invalid JSON value: {e}") from None


def load_json(path: str | os.PathLike, what: str = "JSON file") -> Any:
    """Read and parse a JSON file with every check of ``read_text`` and ``parse_json``."""
    return parse_json(read_text(path, what), str(path))


def _check_events(text: str, file: str) -> None:
    depth = aliases = 0
    for event in yaml.parse(text, Loader=_LOADER):
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
            if depth > MAX_DEPTH:
                raise InputError(file, f"nested more than {MAX_DEPTH} levels deep", event.start_mark.line + 1)
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        elif isinstance(event, yaml.AliasEvent):
            aliases += 1
            if aliases > MAX_ALIASES:
                raise InputError(file, f"more than {MAX_ALIASES} aliases", event.start_mark.line + 1)


def _check_nodes(root: yaml.Node, file: str) -> None:
    seen: set[int] = set()
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            for key, value in node.value:
                if not isinstance(key, yaml.ScalarNode) or key.tag != _STR_TAG:
                    shown = key.value if isinstance(key, yaml.ScalarNode) else "a collection"
                    raise InputError(file, f"key {shown!r} is not a string (quote it: '{shown}':)",
                                     key.start_mark.line + 1)
                stack.append(value)
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
        elif node.tag == _INT_TAG and len(node.value) > MAX_INT_DIGITS:
            raise InputError(file, f"integer of {len(node.value)} digits (at most {MAX_INT_DIGITS})",
                             node.start_mark.line + 1)


_JSON_TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]')


_PLAIN_STRING = re.compile(r'"[^"]*"')
_NOT_BRACKET = re.compile(r"[^\[\]{}]")
#: drops every ASCII character but brackets and quotes
_BRACKETS_AND_QUOTES = {c: None for c in range(128) if chr(c) not in '[]{}"'}
_DEPTH_STEP = {"[": 1, "{": 1, "]": -1, "}": -1}


def _json_depth(text: str) -> tuple[int, int]:
    """The deepest nesting of ``text`` and the line where it is first reached (strings skipped)."""
    if text.count("[") + text.count("{") <= MAX_DEPTH or _json_max_depth(text) <= MAX_DEPTH:
        return 0, 0
    depth = deepest = where = 0
    for match in _JSON_TOKEN.finditer(text):
        ch = match.group()
        if ch in "[{":
            depth += 1
            if depth > deepest:
                deepest, where = depth, match.start()
                if deepest > MAX_DEPTH:
                    break
        elif ch in "]}":
            depth -= 1
    return deepest, text.count("\n", 0, where) + 1


def _json_max_depth(text: str) -> int:
    """The deepest nesting of JSON ``text``, fast (a 2.6 MB graph snapshot in ~15 ms): escaped
    backslashes and quotes dropped, then only quotes and brackets kept, strings cut out, and the
    brackets summed in C."""
    plain = text.replace("\\\\", "").replace('\\"', "").translate(_BRACKETS_AND_QUOTES)
    brackets = _NOT_BRACKET.sub("", _PLAIN_STRING.sub("", plain))
    return max(accumulate(map(_DEPTH_STEP.__getitem__, brackets)), default=0)
