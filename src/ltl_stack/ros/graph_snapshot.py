"""Snapshot of a live ROS master's computation graph (thesis 3.5.2), through rosgraph's master API.

Reads ``getSystemState`` (publishers, subscribers, services) and ``getTopicTypes``; it does not
register a node, so the snapshot does not contain the tool itself.
"""
from __future__ import annotations

import http.client
import xmlrpc.client
from datetime import datetime, timezone

import rosgraph.masterapi

from ltl_stack.analysis.snapshot import Snapshot, SnapshotError
from ltl_stack.errors import Exit
from ltl_stack.ros.master import check_master_uri, master_call
from ltl_stack.ros.master import master_uri as resolve_master_uri

CALLER_ID = "/ltl_stack_analyze_graph"


def take_snapshot(master_uri: str | None = None, timeout: float = 5.0) -> Snapshot:
    """Nodes, topics (with types), publishers, subscribers and services of the master at ``master_uri``.

    ``master_uri`` defaults to ``__master:=`` or ``$ROS_MASTER_URI``. A malformed URI is a
    ``UserError`` (exit 2); a master that does not answer within ``timeout`` seconds is a
    ``SnapshotError`` with ``Exit.NO_ROS``.
    """
    # a URI given here is for this snapshot only: never put in the process's environment (a panel's
    # Master field must not move the whole rqt process to another master)
    uri = check_master_uri(master_uri) if master_uri is not None else resolve_master_uri(None)
    try:
        publishers, subscribers, services = master_call("getSystemState", caller=CALLER_ID, uri=uri, timeout=timeout)
        topic_types = master_call("getTopicTypes", caller=CALLER_ID, uri=uri, timeout=timeout)
    except (OSError, http.client.HTTPException, xmlrpc.client.Error, rosgraph.masterapi.MasterException) as e:
        raise SnapshotError(f"cannot read the graph from the ROS master at {uri}: {e}", Exit.NO_ROS) from None
    taken = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    return Snapshot.from_system_state(publishers, subscribers, services, topic_types, master=uri, taken=taken)
