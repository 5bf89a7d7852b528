"""The README's demo: thesis Example 8 (clean and patrol) end to end on a simulated youBot.

Starts a private rosmaster on a free port, launches ``clean_and_patrol.launch`` (the simulated
robot, its navigation and manipulation servers, a scripted camera, every proposition node and the
controller executor, which synthesizes the spec at start-up), prints the controller's trace — what it
senses, what it does, what changed — and stops everything after the strategy has cycled through all
its goals the given number of times (for a spec without goals: ``--duration`` seconds after the
controller's first state). For clean_and_patrol it also tells the thesis' story (Fig. 3.10 a-d,
``sim.narration``) from the trace and runs until the story is complete. Exit
code 0 when it did, 1 when it did not in time or a node of the scenario died (roslaunch's
"process has died" line: the node is named as soon as it is reported).

``--scenario NAME`` runs another scenario of the registry ``SCENARIOS`` (``--help`` lists them). A
scenario with a story (thesis Examples 11 and 12: ``config/<example>/story.yaml`` played by the
``story_environment`` node) is narrated instead — what the story does, the controller's mode
changes and resyntheses, the user's steps — and ends when the story is complete. A scenario of
several robots negotiating (thesis Example 13) is narrated from the world's events and the robots'
negotiation reports. Each entry of ``SCENARIOS`` holds its scenario's data; a ``Follower`` (trace,
story or negotiation) tells the run and says when it is complete, in the one loop of ``_follow``.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.runtime.resilience.negotiation import report_lines
from ltl_stack.runtime.resilience.story import load_story, region_of
from ltl_stack.sim.narration import CleanAndPatrolStory
from ltl_stack.sim.session import RosSession
from ltl_stack.spec import load_spec


@dataclass(frozen=True)
class Negotiation:
    """A scenario of several robots negotiating (docs/negotiation.md): narrated from the world's events
    and each robot's negotiation reports, over when ``finished`` says so of the events so far."""

    robots: tuple[tuple[str, str], ...]      # (namespace of a robot in the scenario's, its role)
    events: str                              # the world's event topic, in the scenario's namespace
    finished: Callable[[Sequence[str]], bool]
    goal: str                                # what ends the run, for "the run ends when …"
    done: str                                # the same once it happened, for "done: …"


@dataclass(frozen=True)
class Scenario:
    """One runnable scenario: ``roslaunch ltl_stack <launch> <launch_args>``, and how it is followed:
    from its story (``story``), from its robots' negotiations (``negotiation``), else from the
    controller's trace (goal cycles), told as ``narration`` when it has one."""

    description: str
    launch: str                      # a launch file of launch/
    namespace: str                   # the scenario's namespace: the executor is /<namespace>/controller_executor
    launch_args: tuple[str, ...] = ()
    story: bool = False              # narrated from its story; ends when the story is complete
    config: str | None = None        # folder of config/ with the spec (default: the namespace)
    negotiation: Negotiation | None = None
    #: the thesis' story told from the trace (clean_and_patrol, Fig. 3.10); the run also waits for it
    narration: Callable[[], CleanAndPatrolStory] | None = None


def _alice(what: str, resilience: str) -> Scenario:
    return Scenario(f"Thesis Example 11 (Spec. 6), {what}", "alice.launch", "alice",
                    (f"resilience:={resilience}",), story=True)


def _patrol(what: str, resilience: str) -> Scenario:
    return Scenario(f"Thesis Example 12 (patrol and recycling), {what}", "patrol_recycling.launch",
                    "patrol_recycling", (f"resilience:={resilience}",), story=True)


def _kitchen_finished(events: Sequence[str]) -> bool:
    """Example 13 is over when C has cooked and D, after delivering, is back in company."""
    delivered = next((i for i, text in enumerate(events) if text.startswith("D delivered")), None)
    return ("C cooked the ingredients" in events and delivered is not None
            and "D is in company" in events[delivered + 1:])


KITCHEN = Negotiation((("D", "DeliveryAgent"), ("A", "KitchenAssistant"), ("C", "Chef")), "kitchen_world/events",
                      _kitchen_finished, "C has cooked and D is back in company", "C cooked and D is back in company")

SCENARIOS: dict[str, Scenario] = {
    "clean_and_patrol": Scenario(
        "Thesis Example 8 (Fig. 3.10): start in topLane and patrol the four lanes; on the second time in "
        "bottomLane the camera sees an object there: stop, pick it up, carry it to rightGround, drop it, patrol "
        "again.", "clean_and_patrol.launch", "clean_and_patrol", narration=CleanAndPatrolStory),
    "simple": Scenario(
        "Thesis Example 7: always move; stop when a person is sensed (move and stop are then true together, "
        "the conflict of Fig. 3.1).", "simple.launch", "simple"),
    "alice_ec": _alice(
        "environment characterization only (§4.10.1.1): the broken door is characterized (EC1, then EC2); "
        "the closed door leaves the spec unrealizable, the user adds GF(doorOpen | doorBroken) through "
        "~add_env_liveness, Alice waits and visits storage when the door opens.", "no-recovery characterize"),
    "alice_recovery": _alice(
        "recovery only (§4.10.1.2): with the door broken Alice goes on without resynthesis; with the door "
        "closed she waits in road until it opens.", "recovery no-characterize"),
    "alice_recovery_ec": _alice(
        "recovery + EC (§4.10.2, threshold 120 transitions): the broken door is recovered; the lasting closed "
        "door is characterized, unrealizable, the user adds GF(doorOpen | doorBroken).", "recovery characterize"),
    "patrol_recycling": _patrol(
        "recovery + EC, threshold 150 transitions (§4.10.2): the metal item in paper_deposit and the manager's "
        "early tap are recovered; the alarm with a lasting spill is characterized, unrealizable, the user adds "
        "GF !spill and the robot waits until the spill is gone.", "recovery characterize"),
    "kitchen": Scenario(
        "Thesis Example 13 (§4.10.3): DeliveryAgent D, KitchenAssistant A and Chef C. D is blocked at the closed "
        "door, characterization fails, D negotiates with A (A opens the door when D is in road or storage), D "
        "delivers; C negotiates with A to have the ingredients passed, A passes, C cooks, D returns to company.",
        "kitchen.launch", "kitchen", negotiation=KITCHEN),
    "patrol_recycling_ec": _patrol(
        "environment characterization only: every violation (metal item, alarm + spill, early tap) is "
        "resynthesized; the spill needs the user's GF !spill.", "no-recovery characterize"),
}


#: roslaunch's line for a node process that ended: ``[story_environment-9] process has died [pid 42,
#: exit code 2, cmd …]``, in red (an ANSI colour code before the bracket)
_DIED = re.compile(r"\[(?P<node>[^\[\]\s]+)-\d+\] process has died \[pid \d+, exit code (?P<code>-?\d+)")


class LaunchLog:
    """roslaunch's output, read as it grows: ``died()`` names the first scenario node that ended."""

    def __init__(self, path: Path) -> None:
        self.path, self._offset, self._rest = path, 0, b""

    def died(self) -> str | None:
        """``node <name> died (exit code N)`` once roslaunch reported it, else None."""
        try:
            with open(self.path, "rb") as f:
                f.seek(self._offset)
                chunk = f.read()
        except OSError:
            return None
        self._offset += len(chunk)
        lines = (self._rest + chunk).split(b"\n")
        self._rest = lines.pop()  # an unfinished line is read again with what follows it
        for line in lines:
            m = _DIED.search(line.decode("utf-8", "replace"))
            if m:
                return f"node {m['node']} died (exit code {m['code']})"
        return None


def package_dir() -> Path:
    """The ltl_stack package folder (where config/ and launch/ are)."""
    return Path(__file__).resolve().parents[3]


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "demo", __doc__.splitlines()[0], exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT),
        epilog="Scenarios (--scenario):\n" + "\n".join(f"  {name}: {s.description}" for name, s in SCENARIOS.items())
        + "\n\nExit 1: the goal cycles (or the story) did not complete within --timeout (the launch log is shown).")
    parser.add_argument("--scenario", choices=list(SCENARIOS), default="clean_and_patrol",
                        help="which scenario (default: %(default)s; listed below)")
    parser.add_argument("--cycles", type=cli.positive_int, default=2, help="goal cycles to run (default: %(default)s; clean_and_patrol also runs until its "
                             "Fig. 3.10 story is told)")
    parser.add_argument("--timeout", type=cli.positive_float, default=240.0, metavar="S",
                        help="give up after S seconds (default: %(default)s)")
    parser.add_argument("--duration", type=cli.positive_float, default=12.0, metavar="S",
                        help="for a spec without system goals: run this many seconds from the controller's first "
                             "state (default: %(default)s)")
    parser.add_json("the trace, one object per line,")
    parser.add_argument("--master-uri", metavar="URI",
                        help="run against this master instead of a private one (default: start one on a free port)")
    parser.add_argument("--bag", metavar="FILE",
                        help="record the run in a rosbag: the executor's ~state, the proposition topics, odom and "
                             "tf (check it afterwards with check_run SPEC MAPPING FILE)")
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
    """Launch the scenario and follow its trace; ``Exit.NEGATIVE`` when it did not finish in time.
    With ``--bag`` the path is checked before anything starts and the bag after the run: a run whose
    recording was not written is an error, whatever the run did."""
    bag = bag_path(args.bag) if args.bag else None
    started = time.time()
    code = _run(args)
    if bag is not None:
        written = bag.is_file() and bag.stat().st_mtime >= started - 1 and bag.stat().st_size > 0
        if not written:
            raise UserError(f"--bag {args.bag}: rosbag record did not write the bag (see the launch log)")
    return code


def bag_path(bag: str) -> Path:
    """The bag to record to; UserError before the run when it cannot be written there: no folder, a
    folder that cannot be written, something that is not a regular file (a FIFO, a device, a folder:
    rosbag would replace it), a file that cannot be written, a name not ending in .bag."""
    path = Path(bag).absolute()
    if path.suffix != ".bag":
        raise UserError(f"--bag {bag}: the file name must end in .bag (rosbag record adds it otherwise)")
    if not path.parent.is_dir():
        raise UserError(f"--bag {bag}: no folder {path.parent}")
    if os.path.lexists(path) and not path.is_file():
        raise UserError(f"--bag {bag}: exists and is not a regular file (rosbag record would replace it)")
    if path.is_symlink():
        raise UserError(f"--bag {bag}: is a symbolic link (rosbag record would replace it)")
    try:  # try it: permissions, a read-only file system, /proc (root passes every access() check)
        with tempfile.NamedTemporaryFile(dir=path.parent, prefix=".ltl_stack_probe_", suffix=".bag"):
            pass
        if path.exists():
            with open(path, "ab"):
                pass
    except OSError as error:
        raise UserError(f"--bag {bag}: cannot be written there ({error.strerror or error})") from None
    return path


def _run(args: argparse.Namespace) -> int:
    scenario = SCENARIOS[args.scenario]
    config = package_dir() / "config" / (scenario.config or scenario.namespace)
    spec_files = sorted(config.glob("*.structuredslugs")) + sorted(config.glob("*.slugsin"))
    if not spec_files:
        raise UserError(f"no spec in {config}")
    spec = load_spec(spec_files[0])
    goal_count = len(spec.sys_liveness)
    has_goals = goal_count > 0
    goals = goal_count or 1

    def say(text: str) -> None:
        cli.say("demo", text)

    with RosSession(master_uri=args.master_uri) as ros:
        say(scenario.description)
        say(f"{'private ' if ros.own_master else ''}rosmaster at {ros.uri}; launching "
            f"{' '.join([scenario.launch, *scenario.launch_args])}")
        log_path = ros.workdir / "roslaunch.log"
        if args.bag:
            _record(ros, scenario.namespace, [*spec.inputs, *spec.outputs], args.bag, say)
        out = [f"out:={ros.workdir}"] if scenario.negotiation else []  # the negotiated specs are written there
        launch = ros.start(["roslaunch", "ltl_stack", scenario.launch, *scenario.launch_args, *out, *args.launch_arg],
                           stdout=open(log_path, "wb"))  # noqa: SIM115 - closed with the process
        for key in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME", "ROS_LOG_DIR", "ROS_HOME"):
            if key in ros.env:
                os.environ[key] = ros.env[key]
            else:
                os.environ.pop(key, None)
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

        from ltl_stack.ros.controller_trace import ControllerTrace

        rospy.init_node("demo_trace", anonymous=True, disable_signals=True)
        problems = Problems()

        def on_diagnostics(msg: DiagnosticArray) -> None:
            for status in msg.status:
                if problems.new(status.name, status.level >= DiagnosticStatus.ERROR, status.message):
                    if args.json:
                        print(json.dumps({"event": "diagnostic", "message": status.message}), flush=True)
                    else:
                        cli.warn("demo", f"controller reports: {status.message}")

        rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics)
        if scenario.story:
            follower: Follower = StoryFollower(scenario, args, say)
        elif scenario.negotiation is not None:
            follower = NegotiationFollower(scenario.namespace, scenario.negotiation, args.json)
        else:
            follower = TraceFollower(ControllerTrace(f"/{scenario.namespace}/controller_executor/state", goals,
                                                     args.json), scenario, args, has_goals, goals)
        return _follow(args, follower, launch, log_path, problems, say)


class Problems(list):
    """The errors the controller reported on /diagnostics, each once: the node republishes its
    statuses every second, and an error that stands is one problem, not one a second."""

    def __init__(self) -> None:
        super().__init__()
        self._standing: dict[str, str] = {}  # status name -> its error now standing

    def new(self, name: str, error: bool, message: str) -> bool:
        """Record one status; True when it is an error not reported yet (then it is appended)."""
        if not error:
            self._standing.pop(name, None)
            return False
        if self._standing.get(name) == message:
            return False
        self._standing[name] = message
        self.append(message)
        return True


def _follow(args, follower: Follower, launch, log_path: Path, problems: list[str], say) -> int:
    """The one loop of every scenario: follow it until ``follower`` has seen it complete (Exit.OK), a
    scenario node dies, roslaunch ends or --timeout passes (Exit.NEGATIVE, with the reason)."""
    import rospy

    say(follower.intro())
    started = time.monotonic()
    watch, dead = LaunchLog(log_path), None
    while time.monotonic() - started < args.timeout and launch.poll() is None:
        if follower.wait():
            break
        dead = watch.died()
        if dead:
            break
    follower.finish()
    elapsed = time.monotonic() - started
    dead = dead or watch.died()  # a node that died as the loop ended (roslaunch exited) is the reason to name
    rospy.signal_shutdown("demo finished")
    reached = follower.reached()
    summary = {"event": "summary", "scenario": args.scenario, **follower.summary(reached, elapsed, problems)}
    if args.json:
        print(json.dumps(summary), flush=True)
    elif reached:
        say(f"done: {follower.done(elapsed, problems)}")
    if not reached:
        why = (f"{dead} after {elapsed:.0f} s" if dead
               else f"roslaunch exited with code {launch.returncode} after {elapsed:.0f} s" if launch.poll() is not None
               else follower.unfinished(args.timeout))
        _not_reached(why, log_path)
        return Exit.NEGATIVE
    return Exit.OK


def _record(ros: RosSession, namespace: str, propositions: list[str], bag: str, say) -> None:
    """Start ``rosbag record`` of the scenario's states, propositions, odometry and tf, and wait until it
    has subscribed to the executor's ~state (before the launch: the recording holds the controller's
    first state). The session stops it with SIGINT, which closes the bag."""
    path = bag_path(bag)
    state = f"/{namespace}/controller_executor/state"
    topics = [state, f"/{namespace}/controller_executor/initial_state",
              *(f"/{namespace}/{kind}/{p}" for kind in ("inputs", "outputs") for p in propositions),
              *(f"/{namespace}/{t}" for t in ("odom", "tf", "tf_static", "localized_region")), "/diagnostics"]
    recorder = ros.start(["rosbag", "record", "--quiet", "-O", str(path), "__name:=demo_record", *topics],
                         stdout=subprocess.DEVNULL)
    master = xmlrpc.client.ServerProxy(ros.uri)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and recorder.poll() is None:
        _, subscribers, _ = master.getSystemState("/demo")[2]
        if any(topic == state and "/demo_record" in nodes for topic, nodes in subscribers):
            say(f"recording {path}")
            return
        time.sleep(0.1)
    raise UserError(f"--bag {bag}: rosbag record did not start within 60 s")


def _not_reached(why: str, log_path: Path) -> None:
    """Say why a scenario did not finish, after the last lines of its launch log."""
    print("\n".join(log_path.read_text(errors="replace").splitlines()[-30:]), file=sys.stderr)
    cli.error("demo", f"{why} (the last lines of the launch log are above)")


#: how long (s) the end of a story run waits for the last beat's message and the last ~state to be told (they
#: travel on other connections than story/complete; at once on an idle machine, seconds on a starved one)
CATCH_UP = 60.0
COUNTERS = ("violations", "recovery_steps", "resyntheses", "resyntheses_ec1", "resyntheses_ec2", "resyntheses_user",
            "unrealizable")


class Follower:
    """What the demo watches while a scenario runs, and how it tells it (``_follow`` is the loop)."""

    def intro(self) -> str:
        """What the run waits for, said before it starts."""
        raise NotImplementedError

    def wait(self) -> bool:
        """Wait a moment (about a second at most) for news and tell it; True once the run is complete."""
        raise NotImplementedError

    def finish(self) -> None:
        """After the loop: tell what is still on its way."""

    def reached(self) -> bool:
        """Did the scenario complete?"""
        raise NotImplementedError

    def summary(self, reached: bool, elapsed: float, problems: list[str]) -> dict:
        """The fields of the ``--json`` summary after ``event`` and ``scenario``."""
        raise NotImplementedError

    def done(self, elapsed: float, problems: list[str]) -> str:
        """The last line of a complete run, after ``done:``."""
        raise NotImplementedError

    def unfinished(self, timeout: float) -> str:
        """Why the run is not complete after ``timeout`` s (no node died, roslaunch still runs)."""
        raise NotImplementedError


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


class TraceFollower(Follower):
    """Prints the controller's trace (``ControllerTrace``) until the strategy has cycled through its
    goals ``--cycles`` times (and the scenario's narration is complete), or for a spec without goals
    ``--duration`` seconds from the controller's first state."""

    def __init__(self, trace, scenario: Scenario, args, has_goals: bool, goals: int) -> None:
        self.trace, self.has_goals, self.goals = trace, has_goals, goals
        self.cycles, self.duration, self.json_lines = args.cycles, args.duration, args.json
        self.story = scenario.narration() if scenario.narration is not None else None
        self.read = 0  # trace steps the story has read
        self.first_state: float | None = None  # --duration counts from here: start-up takes long on a busy machine
        self._reached = False

    def intro(self) -> str:
        if self.has_goals:
            return f"synthesizing and starting; the run ends after {self.cycles} cycle(s) through {self.goals} goals"
        return f"synthesizing and starting; the spec has no goals, the run ends after {self.duration:.0f} s"

    def wait(self) -> bool:
        cycles_done = self.has_goals and self.trace.wait_cycles(self.cycles, 1.0 if self.story is None else 0.5)
        if self.story is not None:
            self.read = _tell(self.story, self.trace.steps, self.read, self.json_lines)
        if cycles_done and (self.story is None or self.story.complete):
            self._reached = True
            return True
        if cycles_done:
            time.sleep(0.2)
        if not self.has_goals:
            time.sleep(0.2)
            if self.trace.steps and self.first_state is None:
                self.first_state = time.monotonic()
            if self.first_state is not None and time.monotonic() - self.first_state >= self.duration:
                self._reached = True
                return True
        return False

    def reached(self) -> bool:
        return self._reached

    def summary(self, reached: bool, elapsed: float, problems: list[str]) -> dict:
        summary = {"cycles": self.trace.cycles.completed, "states": len(self.trace.steps),
                   "seconds": round(elapsed, 1), "problems": len(problems), "ok": reached}
        if self.story is not None:
            summary["story"] = [c.key for c in self.story.chapters]
        return summary

    def done(self, elapsed: float, problems: list[str]) -> str:
        cycles = f"{self.trace.cycles.completed} goal cycle(s), " if self.has_goals else ""
        return f"{cycles}{len(self.trace.steps)} controller states, {elapsed:.1f} s, {len(problems)} problem(s) reported"

    def unfinished(self, timeout: float) -> str:
        if self.story is not None and self.trace.cycles.completed >= self.cycles:
            return f"the story did not reach '{self.story.next_key}' within {timeout:.0f} s"
        if self.has_goals:
            return f"{self.cycles} goal cycle(s) not completed within {timeout:.0f} s"
        return f"the controller did not start within {timeout:.0f} s"


class StoryFollower(Follower):
    """Narrates a story scenario: the story node's beats and user steps (``story/fired``), and from the
    executor's ``~state`` where the robot is, the controller's mode and its resyntheses; complete when
    the story node says so (``story/complete``)."""

    def __init__(self, scenario: Scenario, args, say) -> None:
        import rospy
        from std_msgs.msg import Bool, String

        from ltl_stack.msg import ControllerState

        config = package_dir() / "config" / (scenario.config or scenario.namespace)
        self.story = load_story(config / "story.yaml")
        self.json_lines = args.json
        self.say = say
        self.regions = self.story.regions
        self.complete = threading.Event()
        #: the story's beats seen on story/fired ("story: ..."); story/complete is another topic and
        #: may arrive before the last beat's message
        self.beats_told = 0
        self.counters: dict[str, int] = {}
        self.modes: list[str] = []
        self.at: str | None = None
        self.states = 0
        self.last_stamp = None  # of the last ~state told
        self.lock = threading.Lock()
        self.state_topic = f"/{scenario.namespace}/controller_executor/state"
        rospy.Subscriber(f"/{scenario.namespace}/story/fired", String, self._on_fired, queue_size=100)
        rospy.Subscriber(f"/{scenario.namespace}/story/complete", Bool, self._on_complete, queue_size=10)
        rospy.Subscriber(self.state_topic, ControllerState, self._on_state, queue_size=100)

    def intro(self) -> str:
        return f"synthesizing and starting; the run ends when the story's {len(self.story.beats)} beats have played"

    def wait(self) -> bool:
        return self.complete.wait(0.5)

    def finish(self) -> None:
        # the last beat's message travels on story/fired, the completion on story/complete: tell it too
        deadline = time.monotonic() + CATCH_UP
        while self.complete.is_set() and self.beats_told < len(self.story.beats) and time.monotonic() < deadline:
            time.sleep(0.05)
        if self.complete.is_set():
            self.catch_up(CATCH_UP)

    def reached(self) -> bool:
        return self.complete.is_set()

    def summary(self, reached: bool, elapsed: float, problems: list[str]) -> dict:
        with self.lock:
            return {"ok": reached, "seconds": round(elapsed, 1), "states": self.states, "modes": self.modes,
                    "problems": len(problems), **self.counters}

    def done(self, elapsed: float, problems: list[str]) -> str:
        c = self.counters
        return (f"story complete in {elapsed:.1f} s; {c.get('resyntheses', 0)} resynthes(es) "
                f"(EC1 {c.get('resyntheses_ec1', 0)}, EC2 {c.get('resyntheses_ec2', 0)}, "
                f"user {c.get('resyntheses_user', 0)}), {c.get('violations', 0)} violating transitions")

    def unfinished(self, timeout: float) -> str:
        return f"the story did not complete within {timeout:.0f} s"

    def catch_up(self, timeout: float) -> None:
        """Wait (at most ``timeout`` s) until the ~state the executor published last has been told.

        The story's last beat reacts to a ~state (the robot notifying in the office) but travels on
        story/fired, another connection: it can arrive before that state, which would go untold."""
        import rospy

        from ltl_stack.msg import ControllerState

        deadline = time.monotonic() + timeout
        try:
            latest = rospy.wait_for_message(self.state_topic, ControllerState, timeout).header.stamp
        except rospy.ROSException:
            return
        while time.monotonic() < deadline:
            with self.lock:
                if self.last_stamp is not None and self.last_stamp >= latest:
                    return
            time.sleep(0.05)

    def _emit(self, event: dict, text: str) -> None:
        if self.json_lines:
            print(json.dumps(event), flush=True)
        else:
            self.say(text)

    def _on_fired(self, msg) -> None:
        with self.lock:
            self.beats_told += msg.data.startswith("story: ")
            self._emit({"event": "story", "message": msg.data}, msg.data)

    def _on_complete(self, msg) -> None:
        if msg.data:
            self.complete.set()

    def _on_state(self, msg) -> None:
        from ltl_stack.ros.valuation import MalformedValuation, msg_to_valuation

        try:
            inputs = msg_to_valuation(msg.inputs, "inputs")
        except MalformedValuation:  # not our executor's message: nothing to tell
            return
        with self.lock:
            self.states += 1
            self.last_stamp = msg.header.stamp
            at = region_of(inputs, self.regions, "_c")
            if at is not None and at != self.at:
                self.at = at
                self._emit({"event": "at", "region": at}, f"robot: in {at}")
            counters = {k: int(getattr(msg, k, 0)) for k in COUNTERS}
            mode = getattr(msg, "mode", "") or "normal"
            for key in ("resyntheses_ec1", "resyntheses_ec2", "resyntheses_user"):
                if counters[key] > self.counters.get(key, 0):
                    kind = key.rsplit("_", 1)[1].upper() if key != "resyntheses_user" else "the user's liveness"
                    self._emit({"event": "resynthesis", "variant": key.rsplit("_", 1)[1], **counters},
                               f"controller: resynthesized ({kind}); {counters['resyntheses']} so far")
            if counters["unrealizable"] > self.counters.get("unrealizable", 0):
                self._emit({"event": "unrealizable", **counters},
                           "controller: the characterized spec is unrealizable (EC1 and EC2)")
            if not self.modes or mode != self.modes[-1]:
                previous = self.modes[-1] if self.modes else None
                self.modes.append(mode)
                self._emit({"event": "mode", "mode": mode, "previous": previous, **counters},
                           f"controller: mode {previous} -> {mode}" if previous else f"controller: mode {mode}")
            self.counters = counters


_NUMBER_WORDS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine")


class NegotiationFollower(Follower):
    """Narrates several robots negotiating (thesis Example 13): the world's events and each robot's
    negotiation reports (``<robot>/controller_executor/negotiations``: with whom, what was sent and
    received in words, the outcome), until the scenario's ``Negotiation.finished`` holds."""

    def __init__(self, namespace: str, negotiation: Negotiation, json_lines: bool) -> None:
        import rospy
        from std_msgs.msg import String

        self.namespace, self.negotiation, self.json_lines = namespace, negotiation, json_lines
        self.roles = dict(negotiation.robots)
        self.lock = threading.Lock()
        self.done_event = threading.Event()
        self.seen: set[tuple[str, str]] = set()
        self.events: list[str] = []
        self.negotiations = 0
        self.started = time.monotonic()
        rospy.Subscriber(f"/{namespace}/{negotiation.events}", String, self._on_event, queue_size=100)
        for robot in self.roles:
            rospy.Subscriber(f"/{namespace}/{robot}/controller_executor/negotiations", String, self._on_reports,
                             callback_args=robot, queue_size=100)

    def _stamp(self) -> str:
        return f"[{time.monotonic() - self.started:7.2f}s]"

    def _on_event(self, msg) -> None:
        with self.lock:
            text = msg.data
            if self.json_lines:
                print(json.dumps({"event": "world", "text": text}), flush=True)
            else:
                print(f"{self._stamp()} {text}", flush=True)
            self.events.append(text)
            if self.negotiation.finished(self.events):
                self.done_event.set()

    def _on_reports(self, msg, robot: str) -> None:
        with self.lock:
            for report in json.loads(msg.data):
                key = (robot, report["session"])
                if report["outcome"] is None or key in self.seen:
                    continue
                self.seen.add(key)
                if report["initiator"]:
                    self.negotiations += 1
                if self.json_lines:
                    print(json.dumps({"event": "negotiation", "robot": robot, **{k: report[k] for k in (
                        "peer", "session", "case", "outcome", "reason", "sent", "received", "dropped")}}), flush=True)
                    continue
                first, *rest = report_lines(report, f"{self.roles[robot]} ({robot})")
                print(f"{self._stamp()} *** {first}", flush=True)
                for line in rest:
                    print(f"{' ' * 12}{line}", flush=True)
                if report["explanation"]:
                    print(report["explanation"], flush=True)

    def intro(self) -> str:
        count = len(self.roles)
        return (f"synthesizing and starting {_NUMBER_WORDS[count] if count < len(_NUMBER_WORDS) else count} "
                f"controllers; the run ends when {self.negotiation.goal}")

    def wait(self) -> bool:
        return self.done_event.wait(0.5)

    def reached(self) -> bool:
        return self.done_event.is_set()

    def summary(self, reached: bool, elapsed: float, problems: list[str]) -> dict:
        return {"ok": reached, "seconds": round(elapsed, 1), "negotiations": self.negotiations,
                "problems": len(problems)}

    def done(self, elapsed: float, problems: list[str]) -> str:
        return f"{self.negotiations} negotiation(s), {self.negotiation.done} after {elapsed:.1f} s"

    def unfinished(self, timeout: float) -> str:
        return f"the {self.namespace} did not finish within {timeout:.0f} s"


if __name__ == "__main__":
    sys.exit(main())
