"""Snapshot of a live ROS master's computation graph (thesis 3.5.2), through rosgraph's master API.

Reads ``getSystemState`` (publishers, subscribers, services) and ``getTopicTypes``; it does not
register a node, so the snapshot does not contain the tool itself. ``rosgraph`` is imported when
a snapshot is taken, so that the offline analysis works on machines without ROS.
"""
from __future__ import annotations

import os
import socket
from datetime import UTC, datetime

from ltl_stack.analysis.snapshot import Snapshot, SnapshotError

CALLER_ID = "/ltl_stack_analyze_graph"


def take_snapshot(master_uri: str | None = None, timeout: float = 5.0) -> Snapshot:
    """Nodes, topics (with types), publishers, subscribers and services of the master at ``master_uri``.

    ``master_uri`` defaults to ``$ROS_MASTER_URI``. Raises ``SnapshotError`` with a clear message when
    no master answers within ``timeout`` seconds.
    """
    import rosgraph.masterapi

    uri = master_uri or os.environ.get("ROS_MASTER_URI")
    if not uri:
        raise SnapshotError("no ROS master given: set ROS_MASTER_URI or pass --master-uri")
    master = rosgraph.masterapi.Master(CALLER_ID, master_uri=uri)
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(timeout)
    try:
        publishers, subscribers, services = master.getSystemState()
        topic_types = master.getTopicTypes()
    except (OSError, rosgraph.masterapi.MasterException) as e:
        raise SnapshotError(f"cannot read the graph from the ROS master at {uri}: {e}") from None
    finally:
        socket.setdefaulttimeout(previous)
    taken = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return Snapshot.from_system_state(publishers, subscribers, services, topic_types, master=uri, taken=taken)
