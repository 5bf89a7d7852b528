"""A small actionlib server for the ``ltl_stack/Proposition`` action, and a command-line client.

The server stands for any low-level behaviour that takes time: when a goal activates it, it reports
progress for ``~duration`` seconds and then succeeds with ``completed=True``; a goal with
``activate=False`` succeeds at once with ``completed=False``; a cancel preempts it. It is what the
activation–completion pattern (thesis section 4.3) talks to when no real robot is there, and a
readable example of a SimpleActionServer.
"""
from __future__ import annotations

import json
import sys
import threading
from typing import Any

import actionlib
import rospy

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.msg import PropositionAction, PropositionFeedback, PropositionGoal, PropositionResult
from ltl_stack.ros.action_client import SimpleActionClient
from ltl_stack.ros.master import init_node, master_uri, ros_name, wait_for_master
from ltl_stack.ros.proposition_node import NodeSpec, Param, run_node
from ltl_stack.runtime.config.node_params import Bound

TIMED_PROPOSITION_SERVER = NodeSpec(
    name="timed_proposition_server",
    kind="tool",
    description="An ltl_stack/Proposition action server that completes each activating goal after "
                "~duration seconds (feedback at ~feedback_rate), for trying the activation-completion "
                "pattern without a robot.",
    params=[
        Param("action", "proposition", "the action name (relative names resolve in the node's namespace)",
              kind=str, required=True, ros_name=True),
        Param("duration", 1.0, "seconds from activation to completion", bound=Bound.NON_NEGATIVE),
        Param("feedback_rate", 10.0, "feedback messages per second while a goal runs", bound=Bound.RATE),
    ],
)


class TimedPropositionServer:
    """Completes each activating goal after ``duration`` seconds, with feedback at ``feedback_rate``."""

    def __init__(self, name: str, duration: float = 1.0, feedback_rate: float = 10.0):
        self.duration = duration
        self.feedback_rate = feedback_rate
        self.server = actionlib.SimpleActionServer(name, PropositionAction, execute_cb=self.execute,
                                                   auto_start=False)
        self.server.start()

    def execute(self, goal: PropositionGoal) -> None:
        if not goal.activate:
            self.server.set_succeeded(PropositionResult(completed=False), "not activated")
            return
        start = rospy.get_time()
        rate = rospy.Rate(self.feedback_rate)
        while not rospy.is_shutdown():
            if self.server.is_preempt_requested():
                self.server.set_preempted(PropositionResult(completed=False), "cancelled")
                return
            elapsed = rospy.get_time() - start
            if elapsed >= self.duration:
                break
            self.server.publish_feedback(PropositionFeedback(progress=elapsed / self.duration))
            rate.sleep()
        self.server.publish_feedback(PropositionFeedback(progress=1.0))
        self.server.set_succeeded(PropositionResult(completed=True), "completed")

    def spin(self) -> None:
        """Serve until shutdown (``run_node`` calls this once the server is built)."""
        rospy.spin()


def _build_server(config: dict[str, Any]) -> TimedPropositionServer:
    """Start the server (``run_node`` has checked the parameters against their ``Param``)."""
    name = rospy.get_name()
    action, duration, rate = config["action"], config["duration"], config["feedback_rate"]
    server = TimedPropositionServer(action, duration, rate)
    rospy.loginfo("%s: action %s ready (%.2f s per goal)", name, rospy.resolve_name(action), duration)
    return server


def server_main(argv: list[str] | None = None) -> int:
    """Entry point of ``timed_proposition_server`` (params ``~action``, ``~duration``, ``~feedback_rate``).

    ``--help`` and ``--json`` describe it and exit without starting a node.
    """
    run_node(TIMED_PROPOSITION_SERVER, _build_server, argv)
    return Exit.OK


def client_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "send_proposition_goal", "Send one ltl_stack/Proposition goal and print its feedback and result.",
        exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT, Exit.NO_ROS))
    parser.add_argument("action", type=ros_name, help="action name, e.g. /pickup_server")
    parser.add_argument("--deactivate", action="store_true", help="send activate=false")
    parser.add_argument("--cancel-after", type=cli.non_negative_float, default=0.0, metavar="S",
                        help="cancel the goal after S seconds (default 0: never)")
    parser.add_argument("--master-uri", metavar="URI",
                        help="the ROS master (default: __master:= or $ROS_MASTER_URI)")
    parser.add_argument("--timeout", type=cli.positive_float, default=30.0, metavar="S",
                        help="seconds to wait for the master, the server and the result (default: %(default)s)")
    parser.add_json("feedback and result, one object per line,")
    return parser


def client_main(argv: list[str] | None = None) -> int:
    """Entry point of ``send_proposition_goal``: send one goal, print feedback and the result."""
    args = client_parser().parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    return cli.run("send_proposition_goal", lambda: _send_goal(args))


def _send_goal(args) -> int:
    wait_for_master(master_uri(args.master_uri), args.timeout)
    init_node("send_proposition_goal", anonymous=True)

    printing = threading.Lock()  # feedback arrives on actionlib's thread, the result on ours

    def show(kind: str, **fields: object) -> None:
        if args.json:
            line = json.dumps({"event": kind, **fields})
        else:
            line = f"{kind}: " + ", ".join(f"{k}={v}" for k, v in fields.items())
        with printing:  # one write per line: two threads' lines never run together
            sys.stdout.write(line + "\n")
            sys.stdout.flush()

    client = SimpleActionClient(args.action, PropositionAction)
    if not client.wait_for_server(rospy.Duration(args.timeout)):
        raise UserError(f"no action server at {rospy.resolve_name(args.action)} (waited {args.timeout:g} s)",
                            Exit.NO_ROS)
    client.send_goal(PropositionGoal(activate=not args.deactivate),
                     feedback_cb=lambda fb: show("feedback", progress=round(fb.progress, 3)))
    if args.cancel_after > 0 and not client.wait_for_result(rospy.Duration(args.cancel_after)):
        client.cancel_goal()
    finished = client.wait_for_result(rospy.Duration(args.timeout))
    result = client.get_result()
    state = actionlib.GoalStatus.to_string(client.get_state()) if finished else "TIMEOUT"
    completed = bool(result.completed) if result is not None else False
    show("result", state=state, completed=completed)
    return Exit.OK if completed else Exit.NEGATIVE
