"""The modes of the controller executor, declared once. ROS-free and light (no synthesis import), so
that every display of a mode (the GUI, the trace, RViz markers) can name them."""
from __future__ import annotations

from enum import Enum


class Mode(Enum):
    """What the controller executor is doing: the ``mode`` of ``~state`` and of its "mode" status on
    /diagnostics (``runtime.executor.node_reports.current_mode``), spelled by its value everywhere (the GUI, the
    trace, docs/executor.md). A resilient strategy takes NORMAL, RECOVERING, CHARACTERIZING,
    WAITING_FOR_USER and ABORTED itself; the node adds HOLDING (a violation no recovery move answers)
    and INPUTS_UNKNOWN (stale inputs)."""

    NORMAL = "normal"
    RECOVERING = "recovering"
    HOLDING = "holding"
    CHARACTERIZING = "characterizing"
    WAITING_FOR_USER = "waiting_for_user"
    INPUTS_UNKNOWN = "inputs_unknown"
    ABORTED = "aborted"


__all__ = ["Mode"]
