"""A.2 adapter: the topics and actions of a running ROS master, with their types (thesis §2.5.1).

Topics come from the master's topic/type table (publishers and subscribers both register types).
An action ``ns`` shows up as the five topics ``ns/goal``, ``ns/cancel``, ``ns/status``,
``ns/feedback`` and ``ns/result``; it is listed once, as ``ns`` with type ``pkg/XAction``.
"""
from __future__ import annotations

import os

from ltl_stack.transfer.errors import TransferError

ACTION_SUFFIXES = ("goal", "cancel", "status", "feedback", "result")


def actions_from_topics(topics: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Actions (name, 'pkg/XAction') implied by the topic table: ``ns/goal`` of type ``pkg/XActionGoal``."""
    by_name = dict(topics)
    actions = []
    for name, msg_type in topics:
        if name.endswith("/goal") and msg_type.endswith("ActionGoal"):
            ns = name[: -len("/goal")]
            if all(f"{ns}/{suffix}" in by_name for suffix in ("status", "result")):
                actions.append((ns, msg_type[: -len("Goal")]))
    return sorted(actions)


def list_live_channels(master_uri: str | None = None, timeout: float = 3.0) -> list[tuple[str, str]]:
    """(name, type) of every topic and action on the master (``ROS_MASTER_URI`` unless given)."""
    import socket

    import rosgraph

    uri = master_uri or os.environ.get("ROS_MASTER_URI")
    if not uri:
        raise TransferError("ROS_MASTER_URI is not set; start a master or drop --live", "<environment>")
    master = rosgraph.Master("/ltl_stack_code_transfer", master_uri=uri)
    old = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout)
    try:
        topics = [(name, msg_type) for name, msg_type in master.getTopicTypes()]
    except (OSError, rosgraph.MasterException) as err:
        raise TransferError(f"cannot reach the ROS master: {err}", uri) from None
    finally:
        socket.setdefaulttimeout(old)
    return sorted(topics) + actions_from_topics(topics)
