"""The README's demo: thesis Example 8 (clean and patrol) end to end on a simulated youBot.

Starts a private rosmaster on a free port, launches ``clean_and_patrol.launch`` (the simulated
robot, its navigation and manipulation servers, a scripted camera, every proposition node and the
controller executor, which synthesizes the spec at start-up), prints the controller's trace — what it
senses, what it does, what changed — and stops everything after the strategy has cycled through all
its goals the given number of times (for a spec without goals: ``--duration`` seconds after the
controller's first state). For clean_and_patrol it also tells the thesis' story (Fig. 3.10 a-d,
``sim.narration``) from the trace and runs until the story is complete. Exit
code 0 when it did, 1 when it did not in time.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.sim.narration import CleanAndPatrolStory
from ltl_stack.sim.session import RosSession
from ltl_stack.spec import load_spec

SCENARIOS = {
    "clean_and_patrol": "Thesis Example 8 (Fig. 3.10): start in topLane and patrol the four lanes; on the "
                        "second time in bottomLane the camera sees an object there: stop, pick it up, carry "
                        "it to rightGround, drop it, patrol again.",
    "simple": "Thesis Example 7: always move; stop when a person is sensed (move and stop are then "
              "true together, the conflict of Fig. 3.1).",
}


def package_dir() -> Path:
    """The ltl_stack package folder (where config/ and launch/ are)."""
    return Path(__file__).resolve().parents[3]


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "demo", __doc__.splitlines()[0], exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT),
        epilog="Exit 1: the goal cycles did not complete within --timeout (the launch log is shown).")
    parser.add_argument("--scenario", choices=sorted(SCENARIOS), default="clean_and_patrol")
    parser.add_argument("--cycles", type=cli.positive_int, default=2, help="goal cycles to run (default: %(default)s)")
    parser.add_argument("--timeout", type=cli.positive_float, default=240.0, metavar="S",
                        help="give up after S seconds (default: %(default)s)")
    parser.add_argument("--duration", type=cli.positive_float, default=12.0, metavar="S",
                        help="for a spec without system goals: run this many seconds from the controller's first "
                             "state (default: %(default)s)")
    parser.add_json("the trace, one object per line,")
    parser.add_argument("--launch-arg", action="append", default=[], metavar="NAME:=VALUE", type=_launch_arg,
                        help="extra roslaunch argument, e.g. speed:=2.0 (repeatable)")
    return parser


def _launch_arg(text: str) -> str:
    name, sep, _ = text.partition(":=")
    if not sep or not name.isidentifier():
        raise argparse.ArgumentTypeError(f"{text!r} is not NAME:=VALUE")
    return text


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return cli.run("demo", lambda: run(args))


def run(args: argparse.Namespace) -> int:
    """Launch the scenario and follow its trace; ``Exit.NEGATIVE`` when it did not finish in time."""
    config = package_dir() / "config" / args.scenario
    spec_files = sorted(config.glob("*.structuredslugs")) + sorted(config.glob("*.slugsin"))
    if not spec_files:
        raise UserError(f"no spec in {config}")
    goal_count = len(load_spec(spec_files[0]).sys_liveness)
    has_goals = goal_count > 0
    goals = goal_count or 1

    def say(text: str) -> None:
        cli.say("demo", text)

    with RosSession() as ros:
        say(SCENARIOS[args.scenario])
        say(f"private rosmaster at {ros.uri}; launching {args.scenario}.launch")
        log_path = ros.workdir / "roslaunch.log"
        launch = ros.start(["roslaunch", "ltl_stack", f"{args.scenario}.launch", *args.launch_arg],
                           stdout=open(log_path, "wb"))  # noqa: SIM115 - closed with the process
        for key in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME"):
            os.environ[key] = ros.env[key]
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

        from ltl_stack.ros.controller_trace import ControllerTrace

        rospy.init_node("demo_trace", anonymous=True, disable_signals=True)
        problems: list[str] = []

        def on_diagnostics(msg: DiagnosticArray) -> None:
            for status in msg.status:
                if status.level >= DiagnosticStatus.ERROR:
                    problems.append(status.message)
                    if args.json:
                        print(json.dumps({"event": "diagnostic", "message": status.message}), flush=True)
                    else:
                        cli.warn("demo", f"controller reports: {status.message}")

        rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics)
        trace = ControllerTrace(f"/{args.scenario}/controller_executor/state", goals, args.json)
        # clean_and_patrol: the thesis' story (Fig. 3.10) told from the trace; the run also waits for it
        story = CleanAndPatrolStory() if args.scenario == "clean_and_patrol" else None
        read = 0  # trace steps the story has read
        if has_goals:
            say(f"synthesizing and starting; the run ends after {args.cycles} cycle(s) through {goals} goals")
        else:
            say(f"synthesizing and starting; the spec has no goals, the run ends after {args.duration:.0f} s")
        started = time.monotonic()
        first_state = None  # --duration counts from here: start-up takes long on a busy machine
        reached = False
        while time.monotonic() - started < args.timeout and launch.poll() is None:
            cycles_done = has_goals and trace.wait_cycles(args.cycles, 1.0 if story is None else 0.5)
            if story is not None:
                read = _tell(story, trace.steps, read, args.json)
            if cycles_done and (story is None or story.complete):
                reached = True
                break
            if cycles_done:
                time.sleep(0.2)
            if not has_goals:
                time.sleep(0.2)
                if trace.steps and first_state is None:
                    first_state = time.monotonic()
                if first_state is not None and time.monotonic() - first_state >= args.duration:
                    reached = True
                    break
        elapsed = time.monotonic() - started
        rospy.signal_shutdown("demo finished")
        summary = {"event": "summary", "scenario": args.scenario, "cycles": trace.cycles.completed,
                   "states": len(trace.steps), "seconds": round(elapsed, 1), "problems": len(problems),
                   "ok": reached}
        if story is not None:
            summary["story"] = [c.key for c in story.chapters]
        if args.json:
            print(json.dumps(summary), flush=True)
        elif reached:
            cycles = f"{trace.cycles.completed} goal cycle(s), " if has_goals else ""
            say(f"done: {cycles}{len(trace.steps)} controller states, {elapsed:.1f} s, "
                f"{len(problems)} problem(s) reported")
        if not reached:
            if launch.poll() is not None:
                why = f"roslaunch exited with code {launch.returncode} after {elapsed:.0f} s"
            elif story is not None and trace.cycles.completed >= args.cycles:
                why = f"the story did not reach '{story.next_key}' within {args.timeout:.0f} s"
            elif has_goals:
                why = f"{args.cycles} goal cycle(s) not completed within {args.timeout:.0f} s"
            else:
                why = f"the controller did not start within {args.timeout:.0f} s"
            launch_log = log_path.read_text(errors="replace").splitlines()
            print("\n".join(launch_log[-30:]), file=sys.stderr)
            cli.error("demo", f"{why} (the last lines of the launch log are above)")
            return Exit.NEGATIVE
    return Exit.OK


def _tell(story: CleanAndPatrolStory, steps: list, read: int, json_lines: bool) -> int:
    """Feed the story the trace steps after ``read`` and print each part it completes; the new count."""
    new = steps[read:]
    for step in new:
        for chapter in story.feed(step):
            if json_lines:
                print(json.dumps(chapter.to_dict()), flush=True)
            else:
                print(f"[{chapter.time:7.2f}s] *** Fig. {chapter.figure}: {chapter.text}", flush=True)
    return read + len(new)


if __name__ == "__main__":
    sys.exit(main())
