"""Goal building and action-type lookup of action_proposition (no master needed, but the package's
generated messages, which only a built catkin workspace has: hence not a unit test)."""
from __future__ import annotations

import pytest

from ltl_stack import msg
from ltl_stack.ros.action_proposition import action_classes, build_goal, normalize_action_type
from ltl_stack.ros.proposition_node import NodeConfigError


@pytest.mark.parametrize("text", ["ltl_stack/Navigate", "ltl_stack/NavigateAction", "ltl_stack.msg.NavigateAction"])
def test_normalize_action_type(text):
    assert normalize_action_type(text) == "ltl_stack/Navigate"


def test_action_classes_of_our_actions():
    action, goal, result = action_classes("ltl_stack/Proposition")
    assert (action, goal, result) == (msg.PropositionAction, msg.PropositionGoal, msg.PropositionResult)


def test_unknown_action_type_is_a_config_error():
    with pytest.raises(NodeConfigError, match="unknown action type 'nav_msgs/Nothing'"):
        action_classes("nav_msgs/Nothing")


def test_build_goal_sets_fields_and_rejects_unknown_ones():
    goal = build_goal(msg.NavigateGoal, {"region": "kitchen", "x": 1})
    assert (goal.region, goal.x, goal.y) == ("kitchen", 1.0, 0.0), goal
    assert build_goal(msg.PropositionGoal, {"activate": True}).activate is True
    with pytest.raises(NodeConfigError, match="does not fit ltl_stack/NavigateGoal"):
        build_goal(msg.NavigateGoal, {"room": "kitchen"})
