"""What the executor publishes in each mode and phase (``runtime.modes``), no ROS."""
from __future__ import annotations

import os

from ltl_stack.runtime.modes import strategy_source
from ltl_stack.runtime.resilient_executor import BackgroundResilience
from ltl_stack.spec import parse_structured

PROBE = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
        "[SYS_TRANS]\nperson' -> stop'\n"


def test_strategy_source_names_the_original_then_the_written_spec_and_counts_generations(tmp_path):
    assert strategy_source("probe.structuredslugs", None) == (os.path.abspath("probe.structuredslugs"), 0)
    written = tmp_path / "ch.structuredslugs"
    rs = BackgroundResilience(parse_structured(PROBE, "probe.structuredslugs"), lock=None, path=written)
    assert strategy_source("probe.structuredslugs", rs) == (os.path.abspath("probe.structuredslugs"), 0)
    rs.counters.resyntheses = 2
    assert strategy_source("probe.structuredslugs", rs) == (str(written), 2)
    rs.write_error = "cannot write"
    assert strategy_source("probe.structuredslugs", rs) == ("", 2)
