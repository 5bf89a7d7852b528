"""What the executor node publishes in each mode and phase, free of ROS (thesis ch. 4, Lemma 1(a)).

The node (``ltl_stack.ros.executor``) only wires these decisions to topics and /diagnostics.
"""
from __future__ import annotations

import os
from typing import Any


def strategy_source(original: str, resilient: Any | None) -> tuple[str, int]:
    """``~state``'s ``spec_file`` and ``strategy_generation``: the file the running strategy was
    synthesized from and how many strategies were put in place after the one of start-up.

    ``resilient`` is the node's ``BackgroundResilience`` (None without characterization). After a
    resynthesis or an adoption the running spec is the characterized/adopted file, "" when it was
    not written to one (no path, or the write failed)."""
    if resilient is None or resilient.counters.resyntheses == 0:
        return (os.path.abspath(original) if original else ""), 0
    path = resilient.characterizer.path
    written = path is not None and getattr(resilient, "write_error", None) is None
    return (os.path.abspath(path) if written else ""), resilient.counters.resyntheses


__all__ = ["strategy_source"]
