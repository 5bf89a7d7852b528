"""The executor's modes are one enum (``runtime.executor.node_mode.Mode``): every place that shows or grades a
mode knows each of them, and the docs name each."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from ltl_stack.gui.controller_model import MODES
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.executor.node_reports import ERROR, MODE_LEVELS, OK, current_mode, mode_text
from ltl_stack.runtime.runs.map_view import mode_label

REPO = Path(__file__).resolve().parents[3]


def test_every_mode_has_a_level_a_text_and_a_colour():
    values = {m.value for m in Mode}
    assert set(MODE_LEVELS) == values, set(MODE_LEVELS) ^ values
    assert set(MODES) == values, set(MODES) ^ values
    assert (MODE_LEVELS[Mode.NORMAL.value], MODE_LEVELS[Mode.ABORTED.value]) == (OK, ERROR)
    for mode in Mode:
        assert mode_text(mode.value, "hold", True, "by the user").startswith(mode.value.split("_")[0]), mode


def test_the_node_reports_only_modes_of_the_enum():
    values = {m.value for m in Mode}
    seen = {current_mode(aborted, violation, resilient, recovered, unknown)
            for aborted in (False, True) for violation in (False, True) for recovered in (False, True)
            for unknown in (False, True) for resilient in (None, *sorted(values - {"holding", "inputs_unknown"}))}
    assert seen == values, seen ^ values


@pytest.mark.parametrize("doc", ["README.md", "docs/resilience.md", "docs/executor.md"])
def test_the_docs_name_every_mode(doc):
    text = REPO.joinpath(doc).read_text(encoding="utf-8")
    missing = [m.value for m in Mode if not re.search(rf"\b{m.value}\b", text)]
    assert not missing, f"{doc} does not name the modes {missing}"


def test_a_mode_label_is_its_value_in_words():
    assert mode_label(Mode.WAITING_FOR_USER.value) == "waiting for user"
    assert mode_label(Mode.NORMAL.value, running=False) == "paused"
