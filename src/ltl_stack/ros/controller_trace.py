"""``controller_trace``: print a running controller's state changes, readable or as JSON lines.

Subscribes to the executor's ``~state`` (``ltl_stack/ControllerState``) and prints one line per new
state: what the controller senses, what it does and what changed; and one line per change of the
resilience mode (normal, recovering, holding, characterizing, waiting_for_user, aborted; thesis ch. 4)
and per resynthesis (EC1/EC2/user counters), with the violated environment-safety clauses; and each
finished integrative negotiation (the executor's ``~negotiations``: with whom, the clauses sent and
received in words, the outcome; thesis §4.8, docs/negotiation.md). With ``--cycles N`` it exits after
the strategy has gone N times through all system goals (the spec tells how many there are). With
``--bag FILE`` it replays the states recorded in a rosbag instead (no master needed).
"""
from __future__ import annotations

import json
import sys
import threading

import rospy
from std_msgs.msg import String

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.msg import ControllerState
from ltl_stack.ros.master import init_node, master_uri, ros_name, wait_for_master
from ltl_stack.ros.valuation import MalformedValuation, step_of
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.resilience.negotiation import report_lines
from ltl_stack.runtime.runs.trace import GoalCycles, TraceStep, describe
from ltl_stack.spec import load_spec

#: seconds to wait for the master before giving up with Exit.NO_ROS
MASTER_WAIT = 10.0


class ControllerTrace:
    """Collects and prints the state changes of one controller (needs an initialised rospy node)."""

    def __init__(self, topic: str, goals: int | None = None, json_lines: bool = False, out=sys.stdout):
        self.goals = goals
        self.json_lines = json_lines
        self.out = out
        self.steps: list[TraceStep] = []
        self.mode = Mode.NORMAL.value
        self.resyntheses = (0, 0, 0, 0)
        self.cycles = GoalCycles(goals) if goals else None
        self.changed = threading.Condition()
        self._start = rospy.get_time()
        self._sub = rospy.Subscriber(topic, ControllerState, self._on_state, queue_size=100)
        self.negotiations: set[tuple[str, str]] = set()
        self.malformed = 0  # state messages that could not be read (skipped, the first one reported)
        self._topic = topic
        resolved = rospy.resolve_name(topic)
        self._negotiation_sub = rospy.Subscriber(resolved.rsplit("/", 1)[0] + "/negotiations", String,
                                                 self._on_negotiations, queue_size=10)

    def _on_negotiations(self, msg) -> None:
        """One block per negotiation that ended, and again when its outcome changes (an unconfirmed
        adoption confirmed later); the executor republishes every report each time."""
        for report in json.loads(msg.data):
            key = (report["session"], str(report.get("case")))
            if report.get("outcome") is None or key in self.negotiations:
                continue
            self.negotiations.add(key)
            if self.json_lines:
                print(json.dumps({"event": "negotiation", **{k: report.get(k) for k in (
                    "peer", "session", "initiator", "case", "outcome", "reason", "sent", "received", "dropped")}}),
                    file=self.out, flush=True)
            else:
                when = rospy.get_time() - self._start
                first, *rest = report_lines(report)
                print(f"[{when:7.2f}s] {first}", file=self.out, flush=True)
                for line in rest:
                    print(f"{' ' * 11}{line}", file=self.out, flush=True)

    def _on_state(self, msg) -> None:
        self._resilience(msg)
        if msg.state_id < 0:
            return
        try:
            step = step_of(msg, self._start)
        except MalformedValuation as err:
            self.malformed += 1
            if self.malformed == 1:
                cli.warn("controller_trace", f"{self._topic}: skipping a state message that cannot be read: {err}")
            return
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

    def _resilience(self, msg) -> None:
        """A line when the mode or the resynthesis counters change."""
        mode = msg.mode or Mode.NORMAL.value
        counts = (msg.resyntheses, msg.resyntheses_ec1, msg.resyntheses_ec2, msg.resyntheses_user)
        if (mode, counts) == (self.mode, self.resyntheses):
            return
        when = msg.header.stamp.to_sec() - self._start
        lines = []
        if counts != self.resyntheses:
            new = [name for name, now, before in zip(("EC1", "EC2", "user"), counts[1:], self.resyntheses[1:]) if now > before]
            lines.append(f"resynthesized ({', '.join(new) or 'negotiation'}): {counts[0]} resynthes"
                          f"{'i' if counts[0] == 1 else 'e'}s (EC1 {counts[1]}, EC2 {counts[2]}, user {counts[3]})")
        if mode != self.mode:
            violated = f"; violated: {'; '.join(msg.violated_clauses)}" if msg.violated_clauses else ""
            lines.append(f"mode {self.mode} -> {mode}{violated}")
        with self.changed:
            self.mode, self.resyntheses = mode, counts
            for line in lines:
                if self.json_lines:
                    print(json.dumps({"event": "mode", "time": round(when, 3), "mode": mode,
                                      "resyntheses": counts[0], "ec1": counts[1], "ec2": counts[2],
                                      "user": counts[3], "unrealizable": msg.unrealizable,
                                      "violated": list(msg.violated_clauses), "text": line}),
                          file=self.out, flush=True)
                else:
                    print(f"[{when:7.2f}s] *** {line}", file=self.out, flush=True)

    def wait_cycles(self, cycles: int, timeout: float) -> bool:
        """Block until ``cycles`` goal cycles completed (True) or ``timeout`` seconds passed (False)."""
        end = rospy.get_time() + timeout
        with self.changed:
            while self.cycles is not None and self.cycles.completed < cycles:
                left = end - rospy.get_time()
                if left <= 0 or rospy.is_shutdown():
                    return False
                self.changed.wait(min(left, 0.5))
        return True


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "controller_trace", "Print a running controller's state changes.",
        exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT, Exit.NO_ROS),
        epilog="Exit 0 also when interrupted; 1 means --cycles were not reached within --timeout.")
    parser.add_argument("topic", nargs="?", default="controller_executor/state", type=ros_name,
                        help="the executor's ~state topic (default: %(default)s, relative to the namespace)")
    parser.add_argument("--spec", help="the controller's spec, to number goals as 'k/n' and count cycles")
    parser.add_argument("--cycles", type=cli.non_negative_int, default=0,
                        help="exit after N cycles through all goals (needs --spec)")
    parser.add_argument("--timeout", type=cli.non_negative_float, default=0.0, metavar="S",
                        help="with --cycles: give up after S seconds (default 0: never)")
    parser.add_argument("--master-uri", metavar="URI",
                        help="the ROS master (default: __master:= or $ROS_MASTER_URI)")
    parser.add_argument("--bag", metavar="FILE",
                        help="replay the states recorded in this rosbag (TOPIC, or the only "
                             "ltl_stack/ControllerState topic in it) instead of listening to a master")
    parser.add_json("each state, one object per line,")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    return cli.run("controller_trace", lambda: _trace(args))


def _trace(args) -> int:
    goals = max(1, len(load_spec(args.spec).sys_liveness)) if args.spec else None
    if args.cycles and goals is None:
        raise UserError("--cycles needs --spec")
    if args.bag:
        return replay_bag(args, goals)
    wait_for_master(master_uri(args.master_uri), MASTER_WAIT)
    init_node("controller_trace", anonymous=True)
    trace = ControllerTrace(args.topic, goals, args.json)
    if args.cycles:
        reached = trace.wait_cycles(args.cycles, args.timeout or float("inf"))
        return Exit.OK if reached else Exit.NEGATIVE
    rospy.spin()
    return Exit.OK


def replay_bag(args, goals: int | None) -> int:
    """Print the states recorded in ``args.bag`` as a live trace would; with ``--cycles``, exit 1 when
    the recording holds fewer goal cycles."""
    from ltl_stack.ros.check_run import open_states, trace_steps

    topic = None if args.topic == "controller_executor/state" else "/" + args.topic.lstrip("/")
    with open_states(args.bag, topic) as (topic, messages):
        return _replay(args, goals, trace_steps(messages, args.bag, topic))


def _replay(args, goals: int | None, steps) -> int:
    cycles = GoalCycles(goals) if goals else None
    previous = None
    for step in steps:
        if previous is not None and (previous.state_id, previous.running) == (step.state_id, step.running):
            continue
        cycle_done = cycles.update(step.goal) if cycles else False
        if args.json:
            print(json.dumps({"event": "state", **step.to_dict()}), flush=True)
        else:
            print(describe(previous, step, goals), flush=True)
            if cycle_done:
                print(f"[{step.time:7.2f}s] --- goal cycle {cycles.completed} complete ---", flush=True)
        previous = step
        if args.cycles and cycles is not None and cycles.completed >= args.cycles:
            return Exit.OK
    return Exit.NEGATIVE if args.cycles else Exit.OK
