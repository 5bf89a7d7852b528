"""A run of the controller, ROS-free: how it reads, whether it kept its spec, how RViz shows it.

- ``trace``: readable traces of the executor's ``~state`` (the ``controller_trace`` tool);
- ``conformance``: whether a recorded run kept its spec (the ``check_run`` tool);
- ``map_view``: the region map, the robot's region and its goal region, as ``ros.markers`` draws them.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from ltl_stack.lazy import lazy_exports

#: The public API: each name and the module that defines it.
_EXPORTS = {
    "trace": ("GoalCycles", "TraceStep", "describe"),
    "conformance": ("check_run",),
    "map_view": ("CURRENT", "HEADING", "IDLE", "fill_triangles", "heading_regions", "mode_label",
        "region_from_inputs", "region_shapes", "valuation_text"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
