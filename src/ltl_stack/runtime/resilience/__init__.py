"""Resilient execution (thesis ch. 4), ROS-free: the executor when the environment breaks its
assumptions, and the robots that negotiate.

- ``characterize``: the runtime monitor and environment characterization (Alg. 2 and 3);
- ``resilient_executor``: the resynthesis off the stepping thread;
- ``characterized_english``: the characterized spec of an English spec, in English;
- ``story`` and ``resilience_table``: the scripted environments of Examples 10-12 and the §4.10.4
  comparison that plays them in process;
- ``negotiation``: integrative negotiation between two robots (§4.8, Alg. 4), a package with its own API.

Names of the modules above are imported on first use (``ltl_stack.lazy``): importing one module of the
group does not import the others.
"""
from __future__ import annotations

from ltl_stack.lazy import lazy_exports

#: The public API: each name and the module that defines it.
_EXPORTS = {
    "characterize": ("Characterizer", "Counters", "Event", "ExecutionAborted", "Negotiate", "NegotiationAbort",
        "Observation", "ResilientStrategy", "Threshold"),
    "resilient_executor": ("BackgroundResilience", "Busy", "NotReady", "thread_runner"),
    "characterized_english": ("english_text", "is_english"),
    "story": ("Story", "StoryError", "StoryPlayer", "load_story", "parse_story", "region_of"),
    "resilience_table": ("run_example", "table"),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)

__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)
