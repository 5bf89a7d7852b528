"""The controller executor's core, ROS-free: what ``ltl_stack.ros.executor`` wires to topics (thesis
§3.5.1, ch. 4).

- ``controller``: the ``Controller`` (stepping, pause, the violation policy);
- ``node_mode``: the enum of the node's modes, declared once;
- ``output_guard``: the outputs published while no strategy move is taken, kept safe (Lemma 1(a));
- ``node_reports``: the node's mode, its /diagnostics words and levels, what each update publishes;
- ``freshness``: how old an input reading may be before it counts as unknown;
- ``explicit`` and ``recovery``: stepping a saved automaton; recovery moves after a violation (§4.6);
- ``options``: the executor's options, each declared once; ``setup``: spec, mapping and strategy
  before ROS starts; ``running_spec``: what the executor runs, as it tells viewers.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from ltl_stack.lazy import lazy_exports

#: The public API: each name and the module that defines it.
_EXPORTS = {
    "controller": ("ALL_FALSE", "HOLD", "Controller", "Update", "ViolationPolicy"),
    "node_mode": ("Mode",),
    "output_guard": ("Guarded", "OutputGuard", "nearest_safe_outputs", "safe_initial_outputs"),
    "node_reports": ("ERROR", "INITIAL_STATUSES", "MODE_LEVELS", "OK", "USER_ABORT", "WARN", "NodeReports",
        "Status", "aborted_report", "counters_event", "current_mode", "liveness_refusal", "mode_text",
        "readings_key", "step_report", "strategy_source", "violation_report", "waiting_text"),
    "freshness": ("Freshness", "freshness_bounds", "unknown_text"),
    "explicit": ("AutomatonStrategy", "ExplicitState"),
    "recovery": ("RecoveringStrategy",),
    "options": ("EFFECTIVE_OPTIONS", "EXECUTOR_PARAMS", "Options", "add_option_arguments", "effective_params"),
    "setup": ("NODE_NAME", "ExecutorError", "Prepared", "build_strategy", "check_characterized_spec",
        "check_summary", "load_inputs", "make_controller", "merge_options", "params_lookup", "parse_init_props",
        "prepare", "scenario_namespace"),
    "running_spec": ("RunningSpec", "read_spec"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
