"""The mapping format and the ROS conventions, ROS-free: what a user writes beside a spec and what
every node is configured with.

- ``mapping``: the proposition mapping YAML (thesis §3.5.1, Figs. 3.2-3.3): read, checked, written;
- ``mapping_edit``: edited node rows written back into a mapping file, the rest kept;
- ``node_params``: the ``~private`` parameters of every node, with types and bounds;
- ``ros_names``: legal ROS names, checked without ROS, and a spec checked against them;
- ``launch``: the ``generate_launch`` tool (a roslaunch file for a mapping).

Users: the executor's setup, the ROS nodes, the graph analysis (``analysis``), the mapping panel.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from ltl_stack.lazy import lazy_exports

#: The public API: each name and the module that defines it.
_EXPORTS = {
    "mapping": ("INPUT", "OUTPUT", "Mapping", "MappingError", "MappingIssue", "NodeEntry", "check_mapping",
        "default_topic", "format_mapping", "load_mapping", "misfit", "parse_mapping", "resolve_name",
        "resolve_node_name", "resolve_topics", "valuation_topics"),
    "mapping_edit": ("EditedRow", "rows_text", "text_digest"),
    "node_params": ("Bound", "NodeConfigError", "Param", "coerce_param", "describe_params", "params_help", "shown",
        "split_param_args"),
    "ros_names": ("PropositionNameError", "check_proposition_names", "is_legal_base_name", "is_legal_name",
        "load_spec_for_ros"),
    "launch": ("LaunchError", "generate_launch"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
