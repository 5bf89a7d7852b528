"""``action_proposition``: the activation–completion pattern (thesis 4.3) over actionlib.

An action proposition ``a`` is true while the controller *activates* action ``a``; its completion
proposition (``finished a``, the thesis' ``a_ac`` / ``loc_rc`` inputs) becomes true once the action has
*completed*. This node links the two to any actionlib server:

- rising edge of the activation topic: send a goal (built from ``~goal``) to ``~action``;
- result SUCCEEDED (and, if set, the result field ``~result_field`` true): completion := true;
- result aborted or rejected while still activated: send the goal again after ``~retry_delay``;
- falling edge: cancel the goal if it is still running, and completion := false;
- shutdown while activated: cancel the goal and wait (``~cancel_timeout``) until the server ends it.

The completion is published latched on ``~completion_topic`` (default: relative name
``completion``), at once on change and every 1/``~rate`` s. A goal that cannot be sent yet, because
the server is not up, is sent as soon as it is.
"""
from __future__ import annotations

import time
from collections import deque
from typing import Any

import rospy
from actionlib_msgs.msg import GoalStatus

from ltl_stack.ros.action_client import SimpleActionClient
from ltl_stack.ros.proposition_node import (
    OUTPUT_PARAMS,
    Bound,
    NodeConfigError,
    NodeSpec,
    OutputPropositionNode,
    Param,
    PropositionPublisher,
    fill_message,
    message_class,
    run_node,
)
from ltl_stack.runtime.config.node_params import shown
from ltl_stack.runtime.propositions.sensing import check_field_path, extract_field, parse_field_path

#: Result field that says "completed" for the action types ltl_stack knows.
DEFAULT_RESULT_FIELDS = {"ltl_stack/Proposition": "completed", "ltl_stack/Navigate": "reached"}
#: failed goals of one activation that are each reported; after them, one line every REPORT_PERIOD s
#: (a server that aborts at once would otherwise fill the log at 1/~retry_delay lines a second)
WARN_FAILURES = 3
REPORT_PERIOD = 60.0
#: actionlib_msgs/GoalStatus values, for log lines.
STATE_NAMES = {0: "PENDING", 1: "ACTIVE", 2: "PREEMPTED", 3: "SUCCEEDED", 4: "ABORTED", 5: "REJECTED",
               6: "PREEMPTING", 7: "RECALLING", 8: "RECALLED", 9: "LOST"}
#: Goal fields used when ``~goal`` is empty.
DEFAULT_GOALS = {"ltl_stack/Proposition": {"activate": True}}

ACTION_PROPOSITION = NodeSpec(
    name="action_proposition",
    kind="output",
    description="Activation-completion over actionlib: on the rising edge send a goal to ~action, "
                "publish the completion proposition when it succeeds, cancel and reset on the falling edge.",
    params=[
        *OUTPUT_PARAMS,
        Param("action", "", "action server name, e.g. /pick or /navigate", kind=str, required=True, ros_name=True),
        Param("action_type", "ltl_stack/Proposition", "action type, e.g. ltl_stack/Navigate, "
              "move_base_msgs/MoveBase (the 'Action' suffix is optional)"),
        Param("goal", {}, "goal fields, e.g. {region: kitchen} (default for Proposition: {activate: true})"),
        Param("completion_topic", "completion", "topic of the completion proposition (std_msgs/Bool)",
              required=True, ros_name=True),
        Param("result_field", "", "result field that must also be true (default: completed for "
              "ltl_stack/Proposition, reached for ltl_stack/Navigate, none otherwise)"),
        Param("retry_delay", 1.0, "resend an aborted or rejected goal after this long while activated "
              "(s; negative: never)"),
        Param("reset_on_deactivate", True, "set the completion false on the falling edge"),
        Param("cancel_timeout", 5.0, "on shutdown with a goal running: wait at most this long (s) for the "
              "server to confirm the cancel before the node's connections close", bound=Bound.POSITIVE),
    ],
)


def normalize_action_type(type_name: str) -> str:
    """``pkg/Name`` from ``pkg/NameAction``, ``pkg.msg.NameAction`` or ``pkg/Name``."""
    text = type_name.strip().replace(".msg.", "/")
    if text.endswith("Action"):
        text = text[: -len("Action")]
    return text


def action_classes(type_name: str) -> tuple[type, type, type]:
    """(Action, Goal, Result) message classes of an action type; NodeConfigError if unknown."""
    base = normalize_action_type(type_name)
    try:
        return (message_class(base + "Action", "action"), message_class(base + "Goal", "action"),
                message_class(base + "Result", "action"))
    except NodeConfigError:
        raise NodeConfigError(f"unknown action type {type_name!r} (expected pkg/Name, e.g. "
                              "ltl_stack/Proposition)") from None


def build_goal(goal_cls: type, fields: dict[str, Any]) -> Any:
    """A goal message with ``fields`` set (nested dicts for nested messages)."""
    return fill_message(goal_cls, fields, "~goal")


class ActionProposition(OutputPropositionNode):
    def __init__(self, config: dict[str, Any]) -> None:
        name = rospy.get_name()
        try:
            action_cls, goal_cls, result_cls = action_classes(config["action_type"])
            kind = normalize_action_type(config["action_type"])
            fields = config["goal"] or DEFAULT_GOALS.get(kind, {})
            self.goal = build_goal(goal_cls, fields)
            result_field = config["result_field"] or DEFAULT_RESULT_FIELDS.get(kind, "")
            self.result_steps = parse_field_path(result_field) if result_field else []
            if self.result_steps:
                check_field_path(result_cls(), self.result_steps, result_cls._type)
        except (NodeConfigError, ValueError, LookupError) as error:
            raise NodeConfigError(f"{name}: {error}") from None
        self.client = SimpleActionClient(config["action"], action_cls)
        self.completion = PropositionPublisher(rospy.resolve_name(config["completion_topic"]),
                                               rate=config["rate"], initial=False)
        self.generation = 0
        self.done: deque = deque()
        self.in_flight = False
        self.retry_at: float | None = None
        self.failures = 0  # goals of this activation that ended without success
        self.reported_at = 0.0  # when failures were last reported (after the first WARN_FAILURES)
        super().__init__(config)

    # Hooks of the output base (called under its lock).
    def on_rising(self) -> None:
        self.generation += 1
        self.retry_at = None
        self.failures = 0
        self.completion.set(False)
        self._send_if_ready()

    def while_true(self) -> None:
        while self.done:
            self._on_done(*self.done.popleft())
        if self.in_flight or self.completion.value:
            return
        if self.retry_at is not None and time.monotonic() < self.retry_at:
            return
        self._send_if_ready()

    def on_falling(self) -> None:
        self.generation += 1
        if self.in_flight:
            rospy.loginfo("%s: cancelling the goal on %s", rospy.get_name(), self.config["action"])
            self.client.cancel_goal()
            self.in_flight = False
        if self.config["reset_on_deactivate"]:
            self.completion.set(False)

    def on_shutdown(self) -> None:
        """Cancel as on the falling edge, then wait (``~cancel_timeout`` at most) until the server has
        ended the goal: rospy closes the node's connections right after the shutdown hooks, and a
        cancel still queued for sending would be lost, leaving the action running."""
        running = self.in_flight
        self.on_falling()
        if running and not self.client.wait_for_result(rospy.Duration(self.config["cancel_timeout"])):
            rospy.logwarn("%s: %s did not confirm the cancel within %.1f s", rospy.get_name(),
                          self.config["action"], self.config["cancel_timeout"])

    def _send_if_ready(self) -> None:
        if self.in_flight or not self.client.wait_for_server(rospy.Duration(0.01)):
            return
        generation = self.generation
        self.in_flight = True
        self.retry_at = None
        if self.failures < WARN_FAILURES:
            rospy.loginfo("%s: sending a goal to %s", rospy.get_name(), self.config["action"])
        # actionlib calls done_cb holding its own lock; queue the result and handle it in while_true
        # (under the node's lock), so the two locks are never taken in opposite orders.
        self.client.send_goal(self.goal, done_cb=lambda state, result: self.done.append(
            (generation, state, result, self.client.get_goal_status_text())))

    def _on_done(self, generation: int, state: int, result: Any, text: str) -> None:
        if generation != self.generation:
            return  # a goal of an earlier activation
        self.in_flight = False
        if state == GoalStatus.SUCCEEDED and self._result_ok(result):
            rospy.loginfo("%s: %s completed", rospy.get_name(), self.config["action"])
            self.completion.set(True)
            return
        delay = self.config["retry_delay"]
        self.failures += 1
        now = time.monotonic()
        if self.failures <= WARN_FAILURES or now - self.reported_at >= REPORT_PERIOD:
            self.reported_at = now
            more = (f" (goal {self.failures} of this activation; from now on one line every "
                    f"{REPORT_PERIOD:g} s)" if self.failures >= WARN_FAILURES else "")
            rospy.logwarn("%s: goal on %s ended %s (%s)%s%s", rospy.get_name(), self.config["action"],
                          STATE_NAMES.get(state, str(state)), shown(text),
                          f"; retrying in {delay:.1f} s" if delay >= 0 else "", more)
        self.retry_at = now + delay if delay >= 0 else float("inf")

    def _result_ok(self, result: Any) -> bool:
        if not self.result_steps:
            return True
        try:
            return bool(extract_field(result, self.result_steps))
        except LookupError:
            return False

    def spin(self) -> None:
        super().spin()
        self.completion.close()


def action_proposition_main() -> None:
    run_node(ACTION_PROPOSITION, ActionProposition)
