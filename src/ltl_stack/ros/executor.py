"""The controller node (thesis §3.5.1, Figs. 3.2–3.3): ``rosrun ltl_stack controller_executor SPEC [MAPPING]``.

It synthesizes the spec (or loads a saved strategy JSON), subscribes to every input proposition's
``std_msgs/Bool`` topic and publishes every output proposition's topic (latched), plus ``~valuation``
(``ltl_stack/PropositionValuation``, inputs then outputs) and ``~state`` (``ltl_stack/ControllerState``).

The ROS-free logic is ``ltl_stack.runtime.controller.Controller``; this module only wires it:

* stepping happens in the subscriber callback that changed the input valuation (under the
  controller's lock), and the changed outputs are published from there at once;
* optional fixed-rate stepping (``--rate``) for specs that progress without input changes;
* the ready handshake: the timer ``--ready-timeout`` reports (log + ``/diagnostics``) the inputs that
  have never reported, and keeps waiting;
* run/pause: service ``~set_running`` (``std_srvs/SetBool``) and topic ``~running`` (``std_msgs/Bool``);
  pausing drives every output false;
* an environment-assumption violation is logged with the broken env-safety clauses (text, file:line),
  published on ``/diagnostics``, and outputs are held or driven false (``--on-violation``);
* a warning when an input topic has more than one publisher (one input node per input topic).

Exit codes: 0 shut down normally (or ``--check`` passed), 2 bad spec/mapping/strategy/arguments,
3 the spec is unrealizable.
"""
from __future__ import annotations

import argparse
import json
import sys
import threading
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ltl_stack.runtime.controller import HOLD, VIOLATION_POLICIES, Controller, Update
from ltl_stack.runtime.mapping import (
    INPUT,
    OUTPUT,
    MappingError,
    check_mapping,
    load_mapping,
    resolve_topics,
)
from ltl_stack.runtime.mapping import (
    Mapping as PropositionMapping,
)

EXIT_OK = 0
EXIT_BAD_INPUT = 2
EXIT_UNREALIZABLE = 3
NODE_NAME = "controller_executor"


class ExecutorError(Exception):
    """A problem the user can fix (bad file, bad argument); ``code`` is the exit code."""

    def __init__(self, message: str, code: int = EXIT_BAD_INPUT):
        super().__init__(message)
        self.code = code


@dataclass
class Options:
    """Settings of the node: a CLI flag wins over the ``~param`` of the same name, then the default."""

    namespace: str | None = None
    robotics_semantics: bool = True
    cooperative: bool = True
    strategy: str | None = None
    init_props: str = ""
    rate: float = 0.0
    ready_timeout: float = 10.0
    on_violation: str = HOLD
    start_paused: bool = False
    publisher_check_period: float = 2.0
    violation_grace: float = 0.2
    settle_steps: int = 16


PARAM_DEFAULTS = Options()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="controller_executor",
        description="Run a synthesized GR(1) controller as a ROS node (thesis 3.5.1): input propositions "
                    "arrive as std_msgs/Bool topics, output propositions leave as latched std_msgs/Bool topics.",
        epilog="Every option also reads the private parameter of the same name (~rate, ~on_violation, ...); "
               "a flag on the command line wins. Exit codes: 0 normal shutdown or --check passed; 2 bad spec, "
               "mapping, strategy file or argument; 3 unrealizable spec.")
    parser.add_argument("spec", help="specification (.slugsin or structured)")
    parser.add_argument("mapping", nargs="?", help="proposition mapping YAML (default: every proposition on its "
                                                   "default topic /<ns>/inputs/<p>, /<ns>/outputs/<p>)")
    parser.add_argument("--namespace", help="scenario namespace of the proposition topics "
                                            "(default: from the mapping's topics, else the spec's file name)")
    parser.add_argument("--robotics-semantics", dest="robotics_semantics", action="store_true", default=None,
                        help="every position satisfying env_init & sys_init must be winning (default)")
    parser.add_argument("--no-robotics-semantics", dest="robotics_semantics", action="store_false",
                        help="slugs' default initial-state semantics")
    parser.add_argument("--cooperative", dest="cooperative", action="store_true", default=None,
                        help="cooperative strategy: prefer moves that help the environment meet its goals (default)")
    parser.add_argument("--no-cooperative", dest="cooperative", action="store_false")
    parser.add_argument("--strategy", metavar="FILE", help="load a saved strategy JSON instead of synthesizing")
    parser.add_argument("--init-props", metavar="a=1,b=0", help="initial values of inputs (used until their "
                        "topic reports) and outputs (constrain the initial state); true and false values")
    parser.add_argument("--rate", type=float, metavar="HZ", help="also step at this rate (default 0: only on "
                                                                 "input changes)")
    parser.add_argument("--ready-timeout", type=float, metavar="S", help="report inputs that have not "
                        "published after S seconds, and again every S seconds (default 10; 0 = never)")
    parser.add_argument("--on-violation", choices=VIOLATION_POLICIES, help="outputs after an environment-"
                        "assumption violation: hold the last safe valuation (default) or drive all false")
    parser.add_argument("--start-paused", action="store_true", default=None, help="start paused")
    parser.add_argument("--publisher-check-period", type=float, metavar="S",
                        help="how often to look for extra publishers on input topics (default 2; 0 = never)")
    parser.add_argument("--settle-steps", type=int, metavar="N",
                        help="after a step, keep stepping with unchanged inputs while the state changes, at most "
                             "N times (default 16), so the robot starts its next move without waiting for an input "
                             "change; 0 takes exactly one step per input change")
    parser.add_argument("--violation-grace", type=float, metavar="S",
                        help="report a violation only when the inputs stay inadmissible this long (default 0.2): "
                             "one sensor change often arrives as several topic messages, e.g. leaving one region "
                             "and entering the next; the output policy applies at once either way")
    parser.add_argument("--check", action="store_true", help="load, validate and synthesize, print a summary "
                        "and exit without ROS")
    parser.add_argument("--json", action="store_true", help="machine-readable output: the --check summary, or "
                        "one JSON line per state change on stdout")
    return parser


# --- ROS-free preparation ---------------------------------------------------------------------

@dataclass
class Prepared:
    spec: Any
    mapping: PropositionMapping | None
    namespace: str
    input_topics: dict[str, str]
    output_topics: dict[str, list[str]]
    warnings: list[str] = field(default_factory=list)


def prepare(spec_path: str, mapping_path: str | None, namespace: str | None) -> Prepared:
    """Load and cross-check the spec and mapping; raises ExecutorError naming what is wrong."""
    from ltl_stack.spec import load_spec
    from ltl_stack.spec.errors import SpecError

    try:
        spec = load_spec(spec_path)
    except SpecError as err:
        raise ExecutorError(str(err)) from None
    except OSError as err:
        raise ExecutorError(f"{spec_path}: cannot read spec: {err.strerror or err}") from None
    mapping = None
    warnings: list[str] = []
    if mapping_path:
        try:
            mapping = load_mapping(mapping_path)
        except MappingError as err:
            raise ExecutorError(str(err)) from None
        issues = check_mapping(mapping, spec.inputs, spec.outputs)
        errors = [str(i) for i in issues if i.severity == "error"]
        if errors:
            raise ExecutorError("the mapping does not fit the spec:\n  " + "\n  ".join(errors))
        warnings = [str(i) for i in issues if i.severity != "error"]
    ns = (namespace or (mapping.scenario_namespace() if mapping else None) or Path(spec_path).stem).strip("/")
    in_topics, out_topics = resolve_topics(mapping, spec.inputs, spec.outputs, ns)
    return Prepared(spec, mapping, ns, in_topics, out_topics, warnings)


def parse_init_props(text: str, spec: Any) -> dict[str, bool]:
    from ltl_stack.spec.valuation import parse_valuation

    try:
        return parse_valuation(text or "", known=list(spec.propositions))
    except ValueError as err:
        raise ExecutorError(f"--init-props: {err}") from None


def build_strategy(spec: Any, options: Options, log=print) -> Any:
    """Synthesize (or load) the strategy the controller steps."""
    if options.strategy:
        from ltl_stack.runtime.explicit import AutomatonStrategy
        from ltl_stack.synthesis import Automaton

        try:
            automaton = Automaton.load(options.strategy, inputs=list(spec.inputs))
        except (OSError, ValueError, KeyError, TypeError) as err:
            raise ExecutorError(f"{options.strategy}: cannot load strategy: {err}") from None
        if set(automaton.inputs) != set(spec.inputs) or set(automaton.outputs) != set(spec.outputs):
            raise ExecutorError(f"{options.strategy}: the strategy's propositions (inputs {automaton.inputs}, "
                                f"outputs {automaton.outputs}) differ from the spec's (inputs {spec.inputs}, "
                                f"outputs {spec.outputs})")
        log(f"loaded strategy {options.strategy}: {len(automaton.states)} states")
        return AutomatonStrategy(automaton, spec)
    from ltl_stack.synthesis import synthesize

    log(f"synthesizing {spec.source} (robotics semantics: {options.robotics_semantics}, "
        f"cooperative: {options.cooperative}) ...")
    result = synthesize(spec, robotics_semantics=options.robotics_semantics, cooperative=options.cooperative)
    if not result.realizable:
        raise ExecutorError(f"{spec.source}: the specification is unrealizable"
                            f"{' with robotics semantics' if options.robotics_semantics else ''}; "
                            "nothing to execute (python -m ltl_stack.synthesis.explain tells why)",
                            EXIT_UNREALIZABLE)
    log(f"synthesized in {result.seconds:.3f} s")
    return result.strategy


# --- the node ---------------------------------------------------------------------------------

class ExecutorNode:
    """The ROS wiring around a Controller. Create after ``rospy.init_node``."""

    def __init__(self, controller: Controller, prepared: Prepared, options: Options, json_lines: bool = False):
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray
        from std_msgs.msg import Bool
        from std_srvs.srv import SetBool

        from ltl_stack.msg import ControllerState, PropositionValuation

        self.rospy = rospy
        self.controller = controller
        self.prepared = prepared
        self.options = options
        self.json_lines = json_lines
        self.Bool = Bool
        self.name = rospy.get_name()
        self._last_violation_key: tuple | None = None
        self._warned_publishers: dict[str, tuple[str, ...]] = {}
        self._started_at = time.monotonic()
        self.output_pubs = {prop: [rospy.Publisher(t, Bool, queue_size=10, latch=True, tcp_nodelay=True)
                                   for t in topics]
                            for prop, topics in prepared.output_topics.items()}
        self.state_pub = rospy.Publisher("~state", ControllerState, queue_size=10, latch=True)
        self.valuation_pub = rospy.Publisher("~valuation", PropositionValuation, queue_size=10, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        self.ControllerState = ControllerState
        with controller.lock:
            self._publish(controller.set_running(not options.start_paused), force_outputs=True)
        self.subscribers = [rospy.Subscriber(topic, Bool, self._on_input, callback_args=prop, queue_size=10,
                                             tcp_nodelay=True)
                            for prop, topic in prepared.input_topics.items()]
        self.service = rospy.Service("~set_running", SetBool, self._on_set_running)
        self.running_sub = rospy.Subscriber("~running", Bool, self._on_running_topic, queue_size=10)
        self.tick_timer = self.ready_timer = self.publisher_timer = None
        if options.rate > 0:
            self.tick_timer = rospy.Timer(rospy.Duration(1.0 / options.rate), self._on_tick)
        if options.ready_timeout > 0 and not controller.ready:
            self.ready_timer = rospy.Timer(rospy.Duration(options.ready_timeout), self._on_ready_timeout)
        if options.publisher_check_period > 0:
            self.publisher_timer = rospy.Timer(rospy.Duration(options.publisher_check_period),
                                               lambda _event: self.check_publishers())
        rospy.on_shutdown(self._on_shutdown)
        rospy.loginfo("%s: %d inputs (%s), %d outputs (%s); %s", self.name, len(prepared.input_topics),
                      ", ".join(prepared.input_topics.values()) or "none", len(prepared.output_topics),
                      ", ".join(t for ts in prepared.output_topics.values() for t in ts) or "none",
                      "paused" if options.start_paused else "waiting for every input to report")
        if controller.ready:
            with controller.lock:
                self._publish(controller.advance())

    # callbacks (each runs in a rospy thread; the controller's lock orders steps and publications)
    def _on_input(self, msg, prop: str) -> None:
        with self.controller.lock:
            was_ready = self.controller.ready
            update = self.controller.report(prop, msg.data)
            self._publish(update)
            if not was_ready and self.controller.ready:
                self.rospy.loginfo("%s: every input has reported", self.name)
                if self.ready_timer is not None:
                    self.ready_timer.shutdown()

    def _on_tick(self, _event) -> None:
        with self.controller.lock:
            self._publish(self.controller.tick())

    def _on_set_running(self, request):
        from std_srvs.srv import SetBoolResponse

        self.set_running(request.data)
        return SetBoolResponse(success=True, message="running" if request.data else "paused")

    def _on_running_topic(self, msg) -> None:
        self.set_running(msg.data)

    def set_running(self, running: bool) -> None:
        with self.controller.lock:
            changed = running != self.controller.running
            self._publish(self.controller.set_running(running), force_state=changed)
        if changed:
            self.rospy.loginfo("%s: %s", self.name, "running" if running else "paused: every output is false")

    def _on_ready_timeout(self, _event) -> None:
        missing = self.controller.missing_inputs()
        if not missing:
            return
        waited = time.monotonic() - self._started_at
        topics = ", ".join(f"{p} ({self.prepared.input_topics[p]})" for p in missing)
        text = (f"no message after {waited:.0f} s from input(s) {topics}; not stepping until every input "
                "has reported once — is each input proposition node running?")
        self.rospy.logerr("%s: %s", self.name, text)
        self._diagnose(1, "inputs", text, [("silent_inputs", " ".join(missing))])

    def _on_shutdown(self) -> None:
        # Leave the robot idle: drive every output false on the way out.
        for pubs in self.output_pubs.values():
            for pub in pubs:
                try:
                    pub.publish(self.Bool(False))
                except Exception:  # noqa: BLE001 - shutting down; nothing left to report to
                    pass

    def check_publishers(self) -> list[str]:
        """Warn about input topics with more than one publisher; returns the warnings issued now."""
        import rosgraph

        try:
            publishers, _, _ = rosgraph.Master(self.name).getSystemState()
        except Exception as err:  # noqa: BLE001 - the master may be going away
            self.rospy.logdebug("%s: cannot ask the master for publishers: %s", self.name, err)
            return []
        by_topic = {topic: tuple(sorted(nodes)) for topic, nodes in publishers}
        issued = []
        for prop, topic in self.prepared.input_topics.items():
            nodes = by_topic.get(topic, ())
            if len(nodes) > 1 and self._warned_publishers.get(topic) != nodes:
                text = (f"input {prop!r}: topic {topic} has {len(nodes)} publishers ({', '.join(nodes)}); "
                        "an input topic should have exactly one input proposition node (thesis 3.5.1)")
                self.rospy.logwarn("%s: %s", self.name, text)
                self._diagnose(1, "input publishers", text, [("topic", topic), ("publishers", " ".join(nodes))])
                issued.append(text)
            self._warned_publishers[topic] = nodes
        return issued

    # publishing
    def _publish(self, update: Update, force_outputs: bool = False, force_state: bool = False) -> None:
        changed = update.outputs if force_outputs else update.changed_outputs
        for prop, value in changed.items():
            msg = self.Bool(value)
            for pub in self.output_pubs[prop]:
                pub.publish(msg)
        if changed or update.stepped or force_state or force_outputs or update.violation is not None:
            self._publish_state(update)
        if update.stepped:
            self._report_step(update)
        if update.violation is not None:
            if self.options.violation_grace > 0:
                timer = threading.Timer(self.options.violation_grace, self._confirm_violation,
                                        args=(update, _key(self.controller.readings)))
                timer.daemon = True
                timer.start()
            else:
                self._report_violation(update)
        elif self._last_violation_key is not None and self.controller.violation is None:
            self._last_violation_key = None
            self.rospy.loginfo("%s: inputs admissible again; continuing", self.name)
            self._diagnose(0, "environment assumptions", "inputs admissible again", [])
        if update.error:
            self.rospy.logerr("%s: %s (waiting for the inputs to change)", self.name, update.error)

    def _publish_state(self, update: Update) -> None:
        from ltl_stack.ros.valuation import valuation_to_msg

        stamp = self.rospy.Time.now()
        readings = self.controller.readings
        inputs = {p: readings.get(p, False) for p in self.controller.inputs}
        msg = self.ControllerState()
        msg.header.stamp = stamp
        state = update.state
        msg.state_id = state.id if state is not None else -1
        msg.goal_index = state.goal if state is not None else -1
        msg.inputs = valuation_to_msg(inputs, stamp)
        msg.outputs = valuation_to_msg(update.outputs, stamp)
        msg.running = self.controller.running
        self.state_pub.publish(msg)
        self.valuation_pub.publish(valuation_to_msg({**inputs, **update.outputs}, stamp))

    def _report_step(self, update: Update) -> None:
        from ltl_stack.spec.valuation import format_valuation

        state = update.state
        self.rospy.loginfo("%s: %s state %d (goal %d): inputs %s -> outputs %s", self.name,
                           "initial" if update.started else "step to", state.id, state.goal,
                           format_valuation(state.inputs), format_valuation(update.outputs))
        if self.json_lines:
            print(json.dumps({"event": "start" if update.started else "step", "state": state.id, "goal": state.goal,
                              "inputs": dict(state.inputs), "outputs": update.outputs}), flush=True)

    def _confirm_violation(self, update: Update, key: tuple) -> None:
        """Report ``update``'s violation if the same inputs are still inadmissible after the grace time."""
        with self.controller.lock:
            if self.controller.violation is not None and _key(self.controller.readings) == key:
                self._report_violation(update)

    def _report_violation(self, update: Update) -> None:
        from ltl_stack.spec.valuation import format_valuation

        violation = update.violation
        readings = self.controller.readings
        key = _key(readings)
        if key == self._last_violation_key:
            return
        self._last_violation_key = key
        clauses = [f"{c.location}: {c.text}" for c in violation.clauses] or ["(no single clause)"]
        meanings = [_english(c) for c in violation.clauses]
        shown = [f"{c} ({m})" if m else c for c, m in zip(clauses, meanings + [""] * len(clauses), strict=False)]
        policy = "holding the last safe outputs" if self.options.on_violation == HOLD else "all outputs false"
        text = (f"environment assumption violated by inputs {format_valuation(readings)} from state "
                f"{update.state.id}: {'; '.join(shown)}; {policy}, waiting for admissible inputs")
        self.rospy.logerr("%s: %s", self.name, text)
        values = [("clause", c) for c in clauses] + [("meaning", m) for m in meanings if m] + [
            ("inputs", format_valuation(readings)), ("state", str(update.state.id)),
            ("policy", self.options.on_violation)]
        self._diagnose(2, "environment assumptions", text, values)
        if self.json_lines:
            print(json.dumps({"event": "violation", "state": update.state.id, "inputs": readings,
                              "clauses": clauses, "outputs": update.outputs}), flush=True)

    def _diagnose(self, level: int, what: str, message: str, values: Sequence[tuple[str, str]]) -> None:
        from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

        status = DiagnosticStatus(level=level, name=f"{self.name}: {what}", message=message, hardware_id=self.name,
                                  values=[KeyValue(k, v) for k, v in values])
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.rospy.Time.now()
        self.diag_pub.publish(array)


def _key(readings: Mapping[str, bool]) -> tuple:
    return tuple(sorted(readings.items()))


def _english(clause: Any) -> str:
    """The clause in Structured English, or "" when it cannot be rendered."""
    try:
        from ltl_stack.spec.english import clause_to_english

        return clause_to_english(clause, "env_safety")
    except Exception:  # noqa: BLE001 - a rendering problem must not hide the violation itself
        return ""


def _merge_options(args: argparse.Namespace, get_param) -> Options:
    """CLI flag if given, else ``~param``, else the default."""
    values = {}
    for name, default in vars(PARAM_DEFAULTS).items():
        cli = getattr(args, name, None)
        values[name] = cli if cli is not None else get_param(f"~{name}", default)
    if isinstance(values["init_props"], Mapping):
        values["init_props"] = ",".join(f"{k}={int(bool(v))}" for k, v in values["init_props"].items())
    options = Options(**values)
    if options.on_violation not in VIOLATION_POLICIES:
        raise ExecutorError(f"on_violation must be one of {', '.join(VIOLATION_POLICIES)}, got {options.on_violation!r}")
    for name in ("rate", "ready_timeout", "publisher_check_period", "violation_grace", "settle_steps"):
        value = getattr(options, name)
        if not isinstance(value, int | float) or value < 0:
            raise ExecutorError(f"{name} must be a number >= 0, got {value!r}")
    return options


def _check(args: argparse.Namespace) -> int:
    """``--check``: everything up to the strategy, no ROS."""
    prepared = prepare(args.spec, args.mapping, args.namespace)
    options = _merge_options(args, lambda _name, default: default)
    init = parse_init_props(options.init_props, prepared.spec)
    for warning in prepared.warnings:
        print(warning, file=sys.stderr)
    strategy = build_strategy(prepared.spec, options, log=lambda text: print(text, file=sys.stderr))
    controller = Controller(strategy, on_violation=options.on_violation, init_props=init,
                            settle_steps=options.settle_steps)
    summary = {"spec": str(args.spec), "mapping": args.mapping, "namespace": prepared.namespace,
               "inputs": prepared.input_topics, "outputs": prepared.output_topics,
               "warnings": prepared.warnings, "init_props": init, "ready": controller.ready}
    if controller.ready:
        update = controller.advance()
        summary["initial_state"] = None if update.state is None else {
            "id": update.state.id, "goal": update.state.goal, "inputs": dict(update.state.inputs),
            "outputs": dict(update.state.outputs)}
        if update.error:
            summary["error"] = update.error
    if args.json:
        print(json.dumps(summary, indent=2))
    if summary.get("error"):
        raise ExecutorError(f"--init-props: {summary['error']}")
    if not args.json:
        ins = ", ".join(f"{p} <- {t}" for p, t in prepared.input_topics.items()) or "none"
        outs = ", ".join(f"{p} -> {' '.join(ts)}" for p, ts in prepared.output_topics.items()) or "none"
        print(f"ok: namespace /{prepared.namespace}; inputs: {ins}; outputs: {outs}")
    return EXIT_OK


def main(argv: Sequence[str] | None = None) -> int:
    import rospy

    raw = list(sys.argv if argv is None else ["controller_executor", *argv])
    args = build_parser().parse_args(rospy.myargv(raw)[1:])
    try:
        if args.check:
            return _check(args)
        prepared = prepare(args.spec, args.mapping, args.namespace)
    except ExecutorError as err:
        print(f"controller_executor: error: {err}", file=sys.stderr)
        return err.code
    for warning in prepared.warnings:
        print(f"controller_executor: warning: {warning}", file=sys.stderr)
    rospy.init_node(NODE_NAME)
    try:
        options = _merge_options(args, rospy.get_param)
        init = parse_init_props(options.init_props, prepared.spec)
        strategy = build_strategy(prepared.spec, options, log=lambda text: rospy.loginfo("%s: %s", rospy.get_name(), text))
        controller = Controller(strategy, on_violation=options.on_violation, init_props=init,
                                running=True, settle_steps=options.settle_steps)
    except ExecutorError as err:
        print(f"controller_executor: error: {err}", file=sys.stderr)
        rospy.signal_shutdown("bad configuration")
        return err.code
    ExecutorNode(controller, prepared, options, json_lines=args.json)
    rospy.spin()
    return EXIT_OK


__all__ = ["ExecutorError", "ExecutorNode", "Options", "build_parser", "build_strategy", "main", "prepare",
           "INPUT", "OUTPUT"]
