"""A.2 adapter: the topics and actions of a running ROS master, with their types (thesis §2.5.1).

Topics come from the master's topic/type table (publishers and subscribers both register types).
An action ``ns`` shows up as the five topics ``ns/goal``, ``ns/cancel``, ``ns/status``,
``ns/feedback`` and ``ns/result``; it is listed once, as ``ns`` with type ``pkg/XAction``
(``ltl_stack.transfer.channels.channel_listing``). ``scripts/ros_code_transfer`` passes
``list_live_channels`` to the transfer's command line, which does not import ROS itself.
"""
from __future__ import annotations

import http.client
import os
import xmlrpc.client

import rosgraph

from ltl_stack.errors import Exit
from ltl_stack.ros.master import master_call
from ltl_stack.transfer.channels import actions_from_topics, channel_listing
from ltl_stack.transfer.errors import TransferError

__all__ = ["actions_from_topics", "list_live_channels"]


def list_live_channels(master_uri: str | None = None, timeout: float = 3.0) -> list[tuple[str, str]]:
    """(name, type) of every topic and action on the master (``ROS_MASTER_URI`` unless given).

    No master (unset or unreachable) is a ``TransferError`` with ``Exit.NO_ROS``.
    """
    uri = master_uri or os.environ.get("ROS_MASTER_URI")
    if not uri:
        raise TransferError("ROS_MASTER_URI is not set; start a master or drop --live", "<environment>",
                            code=Exit.NO_ROS)
    try:
        topics = [(name, msg_type) for name, msg_type in master_call("getTopicTypes", caller="/ltl_stack_code_transfer",
                                                                     uri=uri, timeout=timeout)]
    except (OSError, http.client.HTTPException, xmlrpc.client.Error, rosgraph.MasterException) as err:
        raise TransferError(f"cannot reach the ROS master: {err}", uri, code=Exit.NO_ROS) from None
    return channel_listing(topics)
