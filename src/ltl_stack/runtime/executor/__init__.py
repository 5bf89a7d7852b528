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

from typing import TYPE_CHECKING

from ltl_stack.lazy import lazy_exports

if TYPE_CHECKING:  # pragma: no cover - for type checkers and readers only
    from ltl_stack.runtime.executor.controller import ALL_FALSE, HOLD, Controller, Update, ViolationPolicy
    from ltl_stack.runtime.executor.explicit import AutomatonStrategy, ExplicitState
    from ltl_stack.runtime.executor.freshness import Freshness, freshness_bounds, unknown_text
    from ltl_stack.runtime.executor.node_mode import Mode
    from ltl_stack.runtime.executor.node_reports import (
        ERROR,
        INITIAL_STATUSES,
        MODE_LEVELS,
        OK,
        USER_ABORT,
        WARN,
        NodeReports,
        Status,
        aborted_report,
        counters_event,
        current_mode,
        liveness_refusal,
        mode_text,
        readings_key,
        step_report,
        strategy_source,
        violation_report,
        waiting_text,
    )
    from ltl_stack.runtime.executor.options import (
        EFFECTIVE_OPTIONS,
        EXECUTOR_PARAMS,
        Options,
        add_option_arguments,
        effective_params,
    )
    from ltl_stack.runtime.executor.output_guard import (
        Guarded,
        OutputGuard,
        nearest_safe_outputs,
        safe_initial_outputs,
    )
    from ltl_stack.runtime.executor.recovery import RecoveringStrategy
    from ltl_stack.runtime.executor.running_spec import RunningSpec, read_spec
    from ltl_stack.runtime.executor.setup import (
        NODE_NAME,
        ExecutorError,
        Prepared,
        build_strategy,
        check_characterized_spec,
        check_summary,
        load_inputs,
        make_controller,
        merge_options,
        params_lookup,
        parse_init_props,
        prepare,
        scenario_namespace,
    )

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

__all__ = ["ALL_FALSE", "AutomatonStrategy", "Controller", "EFFECTIVE_OPTIONS", "ERROR", "EXECUTOR_PARAMS",
    "ExecutorError", "ExplicitState", "Freshness", "Guarded", "HOLD", "INITIAL_STATUSES", "MODE_LEVELS", "Mode",
    "NODE_NAME", "NodeReports", "OK", "Options", "OutputGuard", "Prepared", "RecoveringStrategy", "RunningSpec",
    "Status", "USER_ABORT", "Update", "ViolationPolicy", "WARN", "aborted_report", "add_option_arguments",
    "build_strategy", "check_characterized_spec", "check_summary", "counters_event", "current_mode",
    "effective_params", "freshness_bounds", "liveness_refusal", "load_inputs", "make_controller", "merge_options",
    "mode_text", "nearest_safe_outputs", "params_lookup", "parse_init_props", "prepare", "read_spec",
    "readings_key", "safe_initial_outputs", "scenario_namespace", "step_report", "strategy_source", "unknown_text",
    "violation_report", "waiting_text"]

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
