"""Conversion between ``ltl_stack/PropositionValuation`` messages and plain dicts, and the one decoding of
a ``ControllerState`` (its valuations, a trace step)."""
from __future__ import annotations

from collections.abc import Mapping

import rospy

from ltl_stack.msg import PropositionValuation
from ltl_stack.runtime.runs.trace import TraceStep


def valuation_to_msg(valuation: Mapping[str, bool], stamp: rospy.Time | None = None,
                     frame_id: str = "") -> PropositionValuation:
    """A message with ``keys``/``values`` in the mapping's order."""
    msg = PropositionValuation()
    msg.header.stamp = stamp if stamp is not None else rospy.Time.now()
    msg.header.frame_id = frame_id
    msg.keys = list(valuation)
    msg.values = [bool(v) for v in valuation.values()]
    return msg


class MalformedValuation(ValueError):
    """A valuation message that cannot be read (its parallel arrays disagree in length); the text
    says which and how, in one line."""


def msg_to_valuation(msg: PropositionValuation, what: str = "PropositionValuation") -> dict[str, bool]:
    """The dict of a message; ``MalformedValuation`` when its parallel arrays disagree in length
    (a message of another publisher than ours: every reader refuses it in one line)."""
    if len(msg.keys) != len(msg.values):
        raise MalformedValuation(f"{what} has {len(msg.keys)} keys but {len(msg.values)} values")
    return dict(zip(msg.keys, (bool(v) for v in msg.values)))


def state_valuations(msg) -> tuple[dict[str, bool], dict[str, bool]]:
    """(inputs, outputs) of a ``ControllerState``: the one decoding of every reader of ``~state``
    (controller_trace, check_run, controller_trace --bag, map_markers, story_environment);
    ``MalformedValuation`` naming the field otherwise."""
    return msg_to_valuation(msg.inputs, "inputs"), msg_to_valuation(msg.outputs, "outputs")


def step_of(msg, start: float) -> TraceStep:
    """A ``TraceStep`` of a ControllerState message, timed from ``start`` (seconds);
    ``MalformedValuation`` when its inputs or outputs cannot be read."""
    inputs, outputs = state_valuations(msg)
    return TraceStep(time=msg.header.stamp.to_sec() - start, state_id=msg.state_id, goal=msg.goal_index,
                     inputs=inputs, outputs=outputs, running=msg.running,
                     settling=bool(getattr(msg, "settling", False)))
