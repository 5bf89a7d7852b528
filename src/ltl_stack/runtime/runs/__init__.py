"""A run of the controller, ROS-free: how it reads, whether it kept its spec, how RViz shows it.

- ``trace``: readable traces of the executor's ``~state`` (the ``controller_trace`` tool);
- ``conformance``: whether a recorded run kept its spec (the ``check_run`` tool);
- ``map_view``: the region map, the robot's region and its goal region, as ``ros.markers`` draws them.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ltl_stack.lazy import lazy_exports

if TYPE_CHECKING:  # pragma: no cover - for type checkers and readers only
    from ltl_stack.runtime.runs.conformance import check_run
    from ltl_stack.runtime.runs.map_view import (
        CURRENT,
        HEADING,
        IDLE,
        fill_triangles,
        heading_regions,
        mode_label,
        region_from_inputs,
        region_shapes,
        valuation_text,
    )
    from ltl_stack.runtime.runs.trace import GoalCycles, TraceStep, describe

_EXPORTS = {
    "trace": ("GoalCycles", "TraceStep", "describe"),
    "conformance": ("check_run",),
    "map_view": ("CURRENT", "HEADING", "IDLE", "fill_triangles", "heading_regions", "mode_label",
        "region_from_inputs", "region_shapes", "valuation_text"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = ["CURRENT", "GoalCycles", "HEADING", "IDLE", "TraceStep", "check_run", "describe", "fill_triangles",
    "heading_regions", "mode_label", "region_from_inputs", "region_shapes", "valuation_text"]

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
