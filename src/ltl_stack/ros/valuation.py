"""Conversion between ``ltl_stack/PropositionValuation`` messages and plain dicts."""
from __future__ import annotations

from collections.abc import Mapping

import rospy

from ltl_stack.msg import PropositionValuation


def valuation_to_msg(valuation: Mapping[str, bool], stamp: rospy.Time | None = None,
                     frame_id: str = "") -> PropositionValuation:
    """A message with ``keys``/``values`` in the mapping's order."""
    msg = PropositionValuation()
    msg.header.stamp = stamp if stamp is not None else rospy.Time.now()
    msg.header.frame_id = frame_id
    msg.keys = list(valuation)
    msg.values = [bool(v) for v in valuation.values()]
    return msg


def msg_to_valuation(msg: PropositionValuation) -> dict[str, bool]:
    """The dict of a message; ValueError when its parallel arrays disagree in length."""
    if len(msg.keys) != len(msg.values):
        raise ValueError(f"PropositionValuation has {len(msg.keys)} keys but {len(msg.values)} values")
    return dict(zip(msg.keys, (bool(v) for v in msg.values)))
