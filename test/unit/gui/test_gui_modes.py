"""The controller view names and colours every mode the executor reports on ``~state``."""
from __future__ import annotations


def test_every_executor_mode_has_a_text_and_colour_in_the_controller_view():
    from ltl_stack.gui.controller_model import MODES
    from ltl_stack.runtime.executor.node_reports import MODE_LEVELS

    assert set(MODES) == set(MODE_LEVELS)
    assert all(text and colour for text, colour in MODES.values())
