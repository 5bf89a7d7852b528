"""ROS names without ROS: the same verdicts as rosgraph.names, and propositions the ROS tools refuse."""
from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.runtime.config.ros_names import (
    PropositionNameError,
    check_proposition_names,
    is_legal_base_name,
    is_legal_name,
)


@pytest.mark.parametrize("name, legal", [
    ("", True), ("cmd_vel", True), ("/robot1/cmd_vel", True), ("~state", True), ("a/b_2", True),
    ("see-person", False), ("stop.now", False), ("x@0.0.3", False), ("2fast", False), ("a//b", False),
    ("cmd vel", False), ("_hidden", False),
])
def test_legal_names(name, legal):
    assert is_legal_name(name) is legal, name


@given(st.text(alphabet="ab_/~-.@1 ", max_size=8))
def test_agrees_with_rosgraph(name):
    rosgraph_names = pytest.importorskip("rosgraph.names")
    assert is_legal_name(name) == rosgraph_names.is_legal_name(name), name
    assert is_legal_base_name(name) == (rosgraph_names.is_legal_base_name(name) and name != ""), name


def test_illegal_proposition_names_are_all_named():
    with pytest.raises(PropositionNameError) as err:
        check_proposition_names(["person", "see-person", "stop.now", "x@0.0.3"], "spec.structuredslugs")
    text = str(err.value)
    assert text.startswith("spec.structuredslugs: ") and "'see-person', 'stop.now', 'x@0.0.3'" in text, text
    assert "'person'" not in text and err.value.code == Exit.BAD_INPUT
    check_proposition_names(["person", "move_2"], "ok")
