"""ROS graph-resource names, checked without ROS (the rules of ``rosgraph.names``).

A legal name starts with a letter, ``/`` or ``~`` and continues with letters, digits, ``_`` and
``/`` (no ``//``); a base name (one path element, what a proposition becomes in ``inputs/<p>``)
is a letter followed by letters, digits and ``_``. The synthesizer accepts more proposition names
(``see-person``, the bit-blasted ``x@0.0.3`` of integer variables); the ROS tools refuse those.
"""
from __future__ import annotations

import re
from collections.abc import Iterable

from ltl_stack.errors import Exit, UserError
from ltl_stack.spec import SpecError, load_spec
from ltl_stack.spec.model import Spec

_LEGAL = re.compile(r"[~/A-Za-z][\w/]*", re.ASCII)
_BASE = re.compile(r"[A-Za-z]\w*", re.ASCII)


def is_legal_name(name: str) -> bool:
    """A legal ROS name (the empty name, "this namespace", is legal)."""
    return name == "" or (_LEGAL.fullmatch(name) is not None and "//" not in name)


def is_legal_base_name(name: str) -> bool:
    """A legal base name: one path element, e.g. a topic's last part."""
    return _BASE.fullmatch(name) is not None


class PropositionNameError(UserError):
    """Propositions whose names cannot be ROS topic names (exit ``Exit.BAD_INPUT``)."""

    code = Exit.BAD_INPUT


def check_proposition_names(names: Iterable[str], source: str) -> None:
    """Refuse propositions that are not legal ROS base names, naming every one of them.

    The executor publishes and subscribes ``inputs/<p>`` and ``outputs/<p>``; rospy would refuse
    ``see-person`` or ``stop.now`` only later, deep in a callback.
    """
    bad = [n for n in names if not is_legal_base_name(n)]
    if bad:
        shown = ", ".join(repr(n) for n in bad)
        raise PropositionNameError(
            f"{source}: proposition name(s) {shown} cannot be ROS topic names (use letters, digits and _, "
            "starting with a letter); rename them for the ROS tools (synthesize accepts them)")


def load_spec_for_ros(path: str, error: type[UserError]) -> Spec:
    """The spec at ``path`` for a ROS tool: its propositions must be ROS base names
    (``check_proposition_names``). A spec that cannot be read or parsed is one ``error`` (the
    caller's class: the executor and the launch generator each have their own)."""
    try:
        spec = load_spec(path)
    except SpecError as err:
        raise error(str(err)) from None
    except OSError as err:
        raise error(f"{path}: cannot read spec: {err.strerror or err}") from None
    check_proposition_names([*spec.inputs, *spec.outputs], path)
    return spec


__all__ = ["PropositionNameError", "check_proposition_names", "is_legal_base_name", "is_legal_name",
           "load_spec_for_ros"]
