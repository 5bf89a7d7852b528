"""The cores of the proposition nodes, ROS-free: what ``ltl_stack.ros``'s sensor, detection,
actuator and localization nodes compute (thesis §3.5.1).

- ``edges``: the edges of a Boolean signal and when its sensing went stale;
- ``sensing``: field paths into messages, thresholds with hysteresis, positions of poses;
- ``predicate``: conditions over messages for detection sensors;
- ``regions``: named polygon regions from LTLMoP ``.regions`` files;
- ``localization``: region propositions from poses, region goals for navigation.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ltl_stack.lazy import lazy_exports

if TYPE_CHECKING:  # pragma: no cover - for type checkers and readers only
    from ltl_stack.runtime.propositions.edges import FALLING, RISING, Edge, EdgeDetector, StaleWatch
    from ltl_stack.runtime.propositions.localization import RegionPose, RegionTracker, region_goal
    from ltl_stack.runtime.propositions.predicate import OPS, Condition, MessagePredicate
    from ltl_stack.runtime.propositions.regions import Region, RegionMap, RegionsError, normalize_name
    from ltl_stack.runtime.propositions.sensing import (
        COMPARISONS,
        ThresholdComparator,
        check_field_path,
        extract_field,
        field_path_text,
        parse_field_path,
        pose_xy,
    )

_EXPORTS = {
    "edges": ("FALLING", "RISING", "Edge", "EdgeDetector", "StaleWatch"),
    "sensing": ("COMPARISONS", "ThresholdComparator", "check_field_path", "extract_field", "field_path_text",
        "parse_field_path", "pose_xy"),
    "predicate": ("OPS", "Condition", "MessagePredicate"),
    "regions": ("Region", "RegionMap", "RegionsError", "normalize_name"),
    "localization": ("RegionPose", "RegionTracker", "region_goal"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = ["COMPARISONS", "Condition", "Edge", "EdgeDetector", "FALLING", "MessagePredicate", "OPS", "RISING",
    "Region", "RegionMap", "RegionPose", "RegionTracker", "RegionsError", "StaleWatch", "ThresholdComparator",
    "check_field_path", "extract_field", "field_path_text", "normalize_name", "parse_field_path", "pose_xy",
    "region_goal"]

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
