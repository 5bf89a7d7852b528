"""``controller_trace``: print a running controller's state changes, readable or as JSON lines.

Subscribes to the executor's ``~state`` (``ltl_stack/ControllerState``) and prints one line per new
state: what the controller senses, what it does and what changed. With ``--cycles N`` it exits after
the strategy has gone N times through all system goals (the spec tells how many there are).
"""
from __future__ import annotations

import argparse
import json
import sys
import threading

from ltl_stack.runtime.trace import GoalCycles, TraceStep, describe

EXIT_OK, EXIT_TIMEOUT, EXIT_BAD_INPUT, EXIT_NO_MASTER = 0, 1, 2, 3


def step_of(msg, start: float) -> TraceStep:
    """A ``TraceStep`` of a ControllerState message, timed from ``start`` (seconds)."""
    from ltl_stack.ros.valuation import msg_to_valuation

    return TraceStep(time=msg.header.stamp.to_sec() - start, state_id=msg.state_id, goal=msg.goal_index,
                     inputs=msg_to_valuation(msg.inputs), outputs=msg_to_valuation(msg.outputs),
                     running=msg.running)


class ControllerTrace:
    """Collects and prints the state changes of one controller (needs an initialised rospy node)."""

    def __init__(self, topic: str, goals: int | None = None, json_lines: bool = False, out=sys.stdout):
        import rospy

        from ltl_stack.msg import ControllerState

        self.goals = goals
        self.json_lines = json_lines
        self.out = out
        self.steps: list[TraceStep] = []
        self.cycles = GoalCycles(goals) if goals else None
        self.changed = threading.Condition()
        self._start = rospy.get_time()
        self._sub = rospy.Subscriber(topic, ControllerState, self._on_state, queue_size=100)

    def _on_state(self, msg) -> None:
        if msg.state_id < 0:
            return
        step = step_of(msg, self._start)
        previous = self.steps[-1] if self.steps else None
        if previous is not None and (previous.state_id, previous.running) == (step.state_id, step.running):
            return
        with self.changed:
            self.steps.append(step)
            cycle_done = self.cycles.update(step.goal) if self.cycles else False
            if self.json_lines:
                print(json.dumps({"event": "state", **step.to_dict()}), file=self.out, flush=True)
            else:
                print(describe(previous, step, self.goals), file=self.out, flush=True)
                if cycle_done:
                    print(f"[{step.time:7.2f}s] --- goal cycle {self.cycles.completed} complete ---",
                          file=self.out, flush=True)
            self.changed.notify_all()

    def wait_cycles(self, cycles: int, timeout: float) -> bool:
        """Block until ``cycles`` goal cycles completed (True) or ``timeout`` seconds passed (False)."""
        import rospy

        end = rospy.get_time() + timeout
        with self.changed:
            while self.cycles is not None and self.cycles.completed < cycles:
                left = end - rospy.get_time()
                if left <= 0 or rospy.is_shutdown():
                    return False
                self.changed.wait(min(left, 0.5))
        return True


def main(argv: list[str] | None = None) -> int:
    import rospy

    from ltl_stack.ros.proposition_tools import wait_for_master

    parser = argparse.ArgumentParser(
        prog="controller_trace", description="Print a running controller's state changes.",
        epilog="Exit codes: 0 done (or interrupted), 1 --cycles not reached within --timeout, "
               "2 bad spec, 3 no ROS master.")
    parser.add_argument("topic", nargs="?", default="controller_executor/state",
                        help="the executor's ~state topic (default: %(default)s, relative to the namespace)")
    parser.add_argument("--spec", help="the controller's spec, to number goals as 'k/n' and count cycles")
    parser.add_argument("--cycles", type=int, default=0, help="exit after N cycles through all goals (needs --spec)")
    parser.add_argument("--timeout", type=float, default=0.0, help="with --cycles: give up after S seconds")
    parser.add_argument("--json", action="store_true", help="one JSON object per state")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    goals = None
    if args.spec:
        from ltl_stack.spec import load_spec
        from ltl_stack.spec.errors import SpecError

        try:
            goals = max(1, len(load_spec(args.spec).sys_liveness))
        except SpecError as err:
            print(f"controller_trace: {err}", file=sys.stderr)
            return EXIT_BAD_INPUT
    if args.cycles and goals is None:
        print("controller_trace: --cycles needs --spec", file=sys.stderr)
        return EXIT_BAD_INPUT
    if not wait_for_master(10.0):
        print("controller_trace: no ROS master at $ROS_MASTER_URI", file=sys.stderr)
        return EXIT_NO_MASTER
    rospy.init_node("controller_trace", anonymous=True)
    trace = ControllerTrace(args.topic, goals, args.json)
    if args.cycles:
        reached = trace.wait_cycles(args.cycles, args.timeout or float("inf"))
        return EXIT_OK if reached else EXIT_TIMEOUT
    rospy.spin()
    return EXIT_OK
