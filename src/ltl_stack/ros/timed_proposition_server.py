"""A small actionlib server for the ``ltl_stack/Proposition`` action, and a command-line client.

The server stands for any low-level behaviour that takes time: when a goal activates it, it reports
progress for ``~duration`` seconds and then succeeds with ``completed=True``; a goal with
``activate=False`` succeeds at once with ``completed=False``; a cancel preempts it. It is what the
activation–completion pattern (thesis section 4.3) talks to when no real robot is there, and a
readable example of a SimpleActionServer.
"""
from __future__ import annotations

import argparse
import json
import sys
import threading

import actionlib
import rospy

from ltl_stack.msg import PropositionAction, PropositionFeedback, PropositionGoal, PropositionResult
from ltl_stack.ros.proposition_tools import wait_for_master

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_NO_MASTER = 0, 1, 2, 3


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


def server_main(argv: list[str] | None = None) -> int:
    """Entry point of ``timed_proposition_server`` (params: ``~action``, ``~duration``)."""
    rospy.myargv(argv if argv is not None else sys.argv)
    rospy.init_node("timed_proposition_server")
    name = rospy.get_param("~action", "proposition")
    duration = float(rospy.get_param("~duration", 1.0))
    TimedPropositionServer(name, duration)
    rospy.loginfo("timed_proposition_server: action %s ready (%.2f s per goal)", rospy.resolve_name(name),
                  duration)
    rospy.spin()
    return EXIT_OK


def client_main(argv: list[str] | None = None) -> int:
    """Entry point of ``send_proposition_goal``: send one goal, print feedback and the result."""
    parser = argparse.ArgumentParser(
        prog="send_proposition_goal",
        description="Send one ltl_stack/Proposition goal and print its feedback and result.",
        epilog="Exit codes: 0 completed, 1 not completed (cancelled, aborted, timed out), "
               "3 no master or no action server.")
    parser.add_argument("action", help="action name, e.g. /pickup_server")
    parser.add_argument("--deactivate", action="store_true", help="send activate=false")
    parser.add_argument("--cancel-after", type=float, default=0.0, metavar="S",
                        help="cancel the goal after S seconds")
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds to wait for server and result")
    parser.add_argument("--json", action="store_true", help="print JSON lines")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    if not wait_for_master(args.timeout):
        print("send_proposition_goal: no ROS master at $ROS_MASTER_URI", file=sys.stderr)
        return EXIT_NO_MASTER
    rospy.init_node("send_proposition_goal", anonymous=True)

    printing = threading.Lock()  # feedback arrives on actionlib's thread, the result on ours

    def show(kind: str, **fields: object) -> None:
        if args.json:
            line = json.dumps({"event": kind, **fields})
        else:
            line = f"{kind}: " + ", ".join(f"{k}={v}" for k, v in fields.items())
        with printing:  # one write per line: two threads' lines never run together
            sys.stdout.write(line + "\n")
            sys.stdout.flush()

    client = actionlib.SimpleActionClient(args.action, PropositionAction)
    if not client.wait_for_server(rospy.Duration(args.timeout)):
        print(f"send_proposition_goal: no action server at {args.action}", file=sys.stderr)
        return EXIT_NO_MASTER
    client.send_goal(PropositionGoal(activate=not args.deactivate),
                     feedback_cb=lambda fb: show("feedback", progress=round(fb.progress, 3)))
    if args.cancel_after > 0 and not client.wait_for_result(rospy.Duration(args.cancel_after)):
        client.cancel_goal()
    finished = client.wait_for_result(rospy.Duration(args.timeout))
    result = client.get_result()
    state = actionlib.GoalStatus.to_string(client.get_state()) if finished else "TIMEOUT"
    completed = bool(result.completed) if result is not None else False
    show("result", state=state, completed=completed)
    return EXIT_OK if completed else EXIT_FAILED
