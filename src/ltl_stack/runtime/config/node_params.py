"""Parameters of ROS nodes, validated before a node does anything. ROS-free.

Every node of ltl_stack (the controller executor, the proposition nodes, the simulated robot and
servers) declares its ``~private`` parameters as a list of ``Param``: name, default, meaning, legacy
aliases, type, and the values that make sense (``Bound``, ``choices``, ``ros_name``). ``check_param``
turns one raw value (as rospy's parameter server or a command line gives it) into the declared type
or raises ``NodeConfigError`` naming the parameter: a node with a bad value exits with
``Exit.BAD_INPUT`` at start-up instead of running with it (``nan`` rates, ``_settle_steps:=2.5``,
``_init_props:=5``, an illegal topic name ...).
"""
from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Any

from ltl_stack.cli import MAX_RATE
from ltl_stack.errors import Exit, UserError
from ltl_stack.runtime.config.ros_names import is_legal_name


class NodeConfigError(UserError):
    """A parameter of a node is missing or wrong; the message names it (exit ``Exit.BAD_INPUT``)."""

    code = Exit.BAD_INPUT


class Bound(Enum):
    """The range a numeric parameter must lie in (numbers are always finite: no nan, no inf)."""

    ANY = "any finite number"
    NON_NEGATIVE = ">= 0"
    POSITIVE = "> 0"
    #: a rate or frequency (Hz): ``POSITIVE`` (``RATE_OR_ZERO``: ``NON_NEGATIVE``) and at most ``MAX_RATE``
    RATE = f"> 0 and <= {MAX_RATE:g} (Hz)"
    RATE_OR_ZERO = f">= 0 and <= {MAX_RATE:g} (Hz; 0: off)"
    #: the period of something repeated (s): 0 (off) or at least ``1 / MAX_RATE`` (a shorter one spins a core)
    PERIOD_OR_ZERO = f"0 (off) or >= {1 / MAX_RATE:g} (s)"


@dataclass(frozen=True)
class Param:
    """One ``~private`` parameter of a node.

    ``kind`` is the expected type (float, int, str, bool, list, dict, or a tuple of them, meaning
    any one of them exactly); it defaults to the type of ``default``. ``required`` parameters have no
    default. ``bound`` limits numbers; ``choices`` lists the allowed strings; ``ros_name`` says the
    value (or, for a list, each item) must be a legal ROS graph name (empty allowed unless required).
    """

    name: str
    default: Any = None
    doc: str = ""
    aliases: tuple[str, ...] = ()
    kind: type | tuple[type, ...] | None = None
    required: bool = False
    bound: Bound = Bound.ANY
    choices: tuple[str, ...] = ()
    ros_name: bool = False

    @property
    def type(self) -> type | tuple[type, ...] | None:
        if self.kind is not None:
            return self.kind
        return None if self.default is None else type(self.default)

    @property
    def type_name(self) -> str:
        want = self.type
        if isinstance(want, tuple):
            return " or ".join(t.__name__ for t in want)
        return want.__name__ if want is not None else "value"


#: digits a number may have (a rate, duration, threshold or count of 10^18 is a typing mistake, and
#: longer integers overflow ROS' XML-RPC or Python's 4300-digit conversion limit)
MAX_DIGITS = 18
_LIMIT = 10.0 ** MAX_DIGITS
#: the smallest positive rate, duration or scale (ROS' clock counts nanoseconds)
SMALLEST = 1e-9
_LONG_INTEGER = re.compile(rf"^\s*[+-]?\d{{{MAX_DIGITS + 1},}}\s*$")
#: the largest integer XML-RPC (ROS' parameter server) carries
_XMLRPC_INT = 2 ** 31 - 1
_INNER_INTEGER = re.compile(r"(?<![\w.+-])[+-]?\d{10,}(?![\w.])")
#: what Python makes of bytes of a command line that are not UTF-8 (``\xff`` -> ``\udcff``)
_NOT_UTF8 = re.compile("[\udc80-\udcff]")
_PARAM_ARG = re.compile(r"^_(?P<name>[^:=]+):=(?P<value>.*)$", re.DOTALL)


def shown(value: Any) -> str:
    """``repr`` of a value for a message, cut short (a 5000-digit number is not repeated)."""
    text = repr(value)
    return text if len(text) <= 40 else text[:36] + "…"


#: nesting of a ``_name:=value`` list or dict (rospy reads it as YAML, recursively: 1,000 levels
#: end in RecursionError)
MAX_PARAM_DEPTH = 100


def _depth(text: str) -> int:
    """The deepest bracket nesting of ``text`` (quotes not skipped: an over-estimate is refused)."""
    if text.count("[") + text.count("{") <= MAX_PARAM_DEPTH:
        return 0
    depth = deepest = 0
    for ch in text:
        if ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def split_param_args(argv: Sequence[str]) -> tuple[list[str], str | None]:
    """``argv`` without its ``_name:=value`` items whose value is an integer of more than
    ``MAX_DIGITS`` digits, and the message for the first such item (None when there is none).

    rospy converts ``_name:=value`` items itself when the node starts, before any check of ours,
    and ends in a traceback for such a value (Python's int limit, XML-RPC's); the node starts
    without them and then reports the message as its one ``[FATAL]`` line."""
    kept, message = [], None
    for arg in argv:
        if ":=" in arg and _NOT_UTF8.search(arg):  # ROS names and parameters travel as UTF-8 (XML-RPC)
            message = message or f"argument {shown(arg)} is not UTF-8 text (ROS names and parameters are)"
            continue
        m = _PARAM_ARG.match(arg)
        if m and _LONG_INTEGER.match(m["value"]):
            digits = len(m["value"].strip().lstrip("+-"))
            message = message or (f"parameter ~{m['name']} must be a number of at most {MAX_DIGITS} digits, "
                                  f"got one of {digits} digits")
            continue
        if m and _depth(m["value"]) > MAX_PARAM_DEPTH:  # rospy's YAML reading recurses per level
            message = message or f"parameter ~{m['name']} is nested more than {MAX_PARAM_DEPTH} levels deep"
            continue
        inner = next((n for n in _INNER_INTEGER.findall(m["value"]) if abs(int(n[:40])) > _XMLRPC_INT), None) if m else None
        if inner is not None:  # in a list or dict: rospy's XML-RPC call to the master fails on it
            message = message or (f"parameter ~{m['name']}: {shown(inner)} is beyond a ROS parameter's integers "
                                  f"(at most {_XMLRPC_INT} in size)")
            continue
        kept.append(arg)
    return kept, message


def _fail(param: Param, node: str, message: str, label: str | None = None) -> NodeConfigError:
    return NodeConfigError(f"{node + ': ' if node else ''}{label or 'parameter ~' + param.name} {message}")


def coerce_param(param: Param, value: Any, node: str = "", label: str | None = None) -> Any:
    """Convert a raw value to ``param.type`` and check its range, choices and name; raise
    ``NodeConfigError`` naming the parameter (or ``label``, e.g. a command-line flag) otherwise."""
    if label is not None:
        try:
            return coerce_param(param, value, node)
        except NodeConfigError as err:
            prefix = f"{node}: parameter ~{param.name} " if node else f"parameter ~{param.name} "
            raise NodeConfigError(_fail(param, node, str(err)[len(prefix):], label).args[0]) from None
    want = param.type
    if value is None:
        if param.required:
            raise _fail(param, node, "is required")
        return value
    if isinstance(want, tuple):
        if float in want and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if not any(type(value) is t for t in want):
            raise _fail(param, node, f"must be a {param.type_name}, got {value!r}")
        result = value
    else:
        result = _convert(param, want, value, node)
    _check_value(param, result, node)
    return result


def _convert(param: Param, want: type | None, value: Any, node: str) -> Any:
    if want is None:
        return value
    if want is bool:
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in ("true", "false", "1", "0", "yes", "no"):
            return value.strip().lower() in ("true", "1", "yes")
        if isinstance(value, int) and value in (0, 1):
            return bool(value)
    elif want in (float, int):
        if isinstance(value, bool):
            raise _fail(param, node, f"must be a number, got {value!r}")
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            raise _fail(param, node, f"must be a number, got {shown(value)}") from None
        if math.isfinite(number) and abs(number) >= _LIMIT:
            raise _fail(param, node, f"must be a number of at most {MAX_DIGITS} digits, got {shown(value)}")
        if want is int:
            if not math.isfinite(number):
                raise _fail(param, node, f"must be an integer, got {value!r}")
            if number != int(number):
                raise _fail(param, node, f"must be an integer, got {value!r}")
            return int(number)
        return number
    elif want is str:
        if isinstance(value, str):
            return value
        if isinstance(value, (int, float)) and not isinstance(value, bool):  # a path or name typed as a number
            raise _fail(param, node, f"must be a string, got the number {shown(value)} (quote it to mean the text: "
                                     f"_{param.name}:=\"'{shown(value)}'\")")
    elif want is list:
        if isinstance(value, (list, tuple)):
            return list(value)
        if isinstance(value, str):
            return value.split()
    elif want is dict:
        if isinstance(value, dict):
            return value
    raise _fail(param, node, f"must be a {want.__name__}, got {value!r}")


_LOWER = {Bound.RATE: Bound.POSITIVE, Bound.RATE_OR_ZERO: Bound.NON_NEGATIVE, Bound.PERIOD_OR_ZERO: Bound.NON_NEGATIVE}


def _check_value(param: Param, value: Any, node: str) -> None:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        lower = _LOWER.get(param.bound, param.bound)
        if lower is not Bound.ANY and 0 < value < SMALLEST:
            raise _fail(param, node, f"must be 0 or at least {SMALLEST:g} (a rate or time that small is 0 for "
                                     f"ROS' clock, its inverse infinite), got {shown(value)}")
        if lower is Bound.NON_NEGATIVE and not 0 <= value < math.inf:
            raise _fail(param, node, f"must be a number >= 0, got {value!r}")
        if lower is Bound.POSITIVE and not 0 < value < math.inf:
            raise _fail(param, node, f"must be a number > 0, got {value!r}")
        if not math.isfinite(value):
            raise _fail(param, node, f"must be a finite number, got {value!r}")
        if param.bound is Bound.PERIOD_OR_ZERO and 0 < value < 1 / MAX_RATE:
            raise _fail(param, node, f"must be 0 (off) or at least {1 / MAX_RATE:g} s (a shorter period only spins "
                                     f"a core), got {shown(value)}")
        if param.bound in (Bound.RATE, Bound.RATE_OR_ZERO) and value > MAX_RATE:
            raise _fail(param, node, f"must be at most {MAX_RATE:g} (Hz; a faster loop only spins a core), "
                                     f"got {shown(value)}")
    if param.choices and value not in param.choices:
        raise _fail(param, node, f"must be one of {', '.join(param.choices)}, got {value!r}")
    if param.ros_name:
        names = value if isinstance(value, list) else [value]
        for name in names:
            text = name if isinstance(name, str) else None
            if text is None or not is_legal_name(text) or (param.required and not text):
                raise _fail(param, node, f"must be a legal ROS name (letters, digits, _ and /, starting "
                                         f"with a letter, / or ~), got {name!r}")
    if param.required and value in ("", [], {}):
        raise _fail(param, node, "is required (got an empty value)")


def describe_params(kind: str, description: str, params: Sequence[Param]) -> dict:
    """The machine-readable description of a node (what ``--json`` prints)."""
    return {
        "kind": kind,
        "description": description,
        "params": [
            {"name": p.name, "default": p.default, "required": p.required,
             "aliases": list(p.aliases), "doc": p.doc}
            for p in params
        ],
    }


def params_help(params: Sequence[Param]) -> str:
    """The parameter table of a node's ``--help``."""
    lines = []
    for p in params:
        limits = [f"{p.bound.value}"] if p.bound is not Bound.ANY else []
        if p.choices:
            limits.append("one of " + ", ".join(p.choices))
        if p.ros_name:
            limits.append("a ROS name")
        lines.append(f"  _{p.name}:=<{p.type_name}>"
                     f"{'  (required)' if p.required else f'  (default {p.default!r})'}"
                     f"{'  [' + '; '.join(limits) + ']' if limits else ''}"
                     f"{'  aliases: ' + ', '.join(p.aliases) if p.aliases else ''}\n      {p.doc}")
    return "\n".join(lines)


__all__ = ["MAX_DIGITS", "MAX_RATE", "Bound", "NodeConfigError", "Param", "coerce_param", "describe_params", "params_help",
           "shown", "split_param_args"]
