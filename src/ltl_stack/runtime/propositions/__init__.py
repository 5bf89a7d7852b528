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

from ltl_stack.lazy import lazy_exports

#: The public API: each name and the module that defines it.
_EXPORTS = {
    "edges": ("FALLING", "RISING", "Edge", "EdgeDetector", "StaleWatch"),
    "sensing": ("COMPARISONS", "ThresholdComparator", "check_field_path", "extract_field", "field_path_text",
        "parse_field_path", "pose_xy"),
    "predicate": ("OPS", "Condition", "MessagePredicate"),
    "regions": ("Region", "RegionMap", "RegionsError", "normalize_name"),
    "localization": ("RegionPose", "RegionTracker", "region_goal"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
