"""The controller node (thesis §3.5.1, Figs. 3.2–3.3): ``rosrun ltl_stack controller_executor SPEC [MAPPING]``.

It synthesizes the spec (or loads a saved strategy JSON), subscribes to every input proposition's
``std_msgs/Bool`` topic and publishes every output proposition's topic (latched), plus ``~valuation``
(``ltl_stack/PropositionValuation``, inputs then outputs) and ``~state`` (``ltl_stack/ControllerState``).

The ROS-free parts are ``ltl_stack.runtime.executor.controller.Controller`` (stepping, pause, violation
policy), ``ltl_stack.runtime.executor.setup`` (options, spec, mapping, topics, strategy) and
``ltl_stack.runtime.executor.node_reports.NodeReports`` (what each update publishes, the counters, the mode, health
and violation reports of ``~state`` and /diagnostics); this module only wires them:

* stepping happens in the subscriber callback that changed the input valuation (under the
  controller's lock); each step's falling outputs are written before its rising ones;
* optional fixed-rate stepping (``--rate``) for specs that progress without input changes;
* the heartbeat: every output topic republished every ``--heartbeat`` s (output nodes' deadman);
* the ready handshake: the timer ``--ready-timeout`` reports the inputs that have never reported;
  from then on those with a freshness bound are unknown (a peer's host down at the start);
* a node owning several inputs (region localization) publishes their valuation at once on
  ``<node>/valuation``; once it has, that message is their reading (one step for one region change)
  and their Bool topics only count for freshness; while that topic is connected but has not spoken
  (its latched message is on its way), their Bools wait for it (at most ``VALUATION_WAIT``);
* freshness (``runtime.executor.freshness``): a timer marks inputs whose last message is older than their
  bound unknown (``Controller.set_unknown``), a message makes them known again;
* run/pause: service ``~set_running`` (``std_srvs/SetBool``) and topic ``~running`` (``std_msgs/Bool``);
* violations are confirmed after ``--violation-grace`` by one worker thread, whatever the input rate;
* ``~effective_options``: the options the node runs with (every one, defaults filled in), so that a
  viewer synthesizes the same automaton;
* ``/diagnostics``: the node's statuses once a second, and at once when one changes;
* a master restart is detected and every topic, service and parameter is registered again;
* resilient execution (thesis ch. 4, docs/resilience.md): recovery moves (``--recovery``, default on),
  environment characterization (``--characterize``; resynthesis in a worker thread, the new strategy
  swapped in under the controller's lock), the services ``~add_env_liveness``
  (``ltl_stack/AddEnvLiveness``) and ``~abort`` (``std_srvs/Trigger``), the mode and counters on
  ``~state`` and ``/diagnostics``;
* the negotiation hook (thesis §4.8, Alg. 3 S.2): ``ExecutorNode(..., negotiate=callable)`` or
  ``main(negotiate=...)``; see ``Negotiate`` and docs/resilience.md "Negotiation hook".
"""
from __future__ import annotations

import argparse
import json
import sys
import threading
import time
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import rosgraph
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from std_msgs.msg import Bool
from std_srvs.srv import SetBool, SetBoolResponse, Trigger, TriggerResponse

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.msg import ControllerSource, ControllerState, PropositionValuation
from ltl_stack.ros.master import init_node, master_call, private_params
from ltl_stack.ros.master_watch import MasterWatch
from ltl_stack.ros.negotiation import NegotiationEndpoint, prepare_negotiation
from ltl_stack.ros.valuation import msg_to_valuation, valuation_to_msg
from ltl_stack.runtime.config.mapping import resolve_topics, valuation_topics
from ltl_stack.runtime.config.node_params import split_param_args
from ltl_stack.runtime.executor.controller import Controller, Update
from ltl_stack.runtime.executor.freshness import Freshness, freshness_bounds, unknown_text
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.executor.node_reports import (
    INITIAL_STATUSES,
    USER_ABORT,
    NodeReports,
    Status,
    aborted_report,
    counters_event,
    readings_key,
    step_report,
    strategy_source,
    waiting_text,
)
from ltl_stack.runtime.executor.options import EFFECTIVE_OPTIONS, add_option_arguments, effective_params
from ltl_stack.runtime.executor.running_spec import RunningSpec, running_spec
from ltl_stack.runtime.executor.setup import (
    NODE_NAME,
    ExecutorError,
    Options,
    Prepared,
    build_strategy,
    check_characterized_spec,
    check_summary,
    load_inputs,
    make_controller,
    merge_options,
    params_lookup,
    parse_init_props,
    prepare,
    scenario_namespace,
)
from ltl_stack.runtime.resilience.characterize import Counters, Event, Negotiate
from ltl_stack.runtime.resilience.negotiation import classes_authenticator, negotiation_classes
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience, thread_runner
from ltl_stack.srv import AddEnvLiveness, AddEnvLivenessResponse
from ltl_stack.synthesis.recovery import StepResult

PROG = "controller_executor"
#: How often the node's statuses are published on /diagnostics (rqt_robot_monitor marks older ones stale).
DIAGNOSTICS_PERIOD = 1.0
#: Pause between a step's falling and rising output edges, so that listeners (one thread per topic in
#: rospy) have handled the falling ones before a rising one arrives.
EDGE_GAP = 0.005
#: How often a violation that outlasts ``--characterize-after-seconds`` without a step is looked for.
POLL_PERIOD = 0.1
#: The longest a grouped input's Bool waits for its node's connected ~valuation to speak (seconds).
VALUATION_WAIT = 2.0


def build_parser() -> cli.ToolParser:
    """The command line: SPEC, MAPPING, one flag per option of ``runtime.executor.options`` and
    ``--check``/``--json``."""
    parser = cli.ToolParser(
        prog=PROG,
        description="Run a synthesized GR(1) controller as a ROS node (thesis 3.5.1): input propositions "
                    "arrive as std_msgs/Bool topics, output propositions leave as latched std_msgs/Bool topics.",
        epilog="Every option also reads the private parameter of the same name (~rate, ~on_violation, ...); "
               "a flag on the command line wins. Every value is checked at start-up. The node publishes the "
               "options it runs with, defaults filled in, as ~effective_options.",
        exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.LIMIT, Exit.UNREALIZABLE))
    parser.add_argument("spec", help="specification (.slugsin or structured)")
    parser.add_argument("mapping", nargs="?", help="proposition mapping YAML (default: every proposition on its "
                                                   "default topic <ns>/inputs/<p>, <ns>/outputs/<p>)")
    add_option_arguments(parser)
    parser.add_argument("--check", action="store_true", help="load, validate and synthesize, print a summary "
                        "and exit without ROS")
    parser.add_argument("--json", action="store_true", help="the --check summary as JSON on stdout; running: "
                        "one JSON line per start/step/violation on stdout")
    return parser


class ViolationConfirmer:
    """One worker thread that reports a violation once the inputs stayed inadmissible for ``grace``
    seconds. A newer violation replaces a pending one, so bursts of inputs never add threads."""

    def __init__(self, grace: float, confirm) -> None:
        self.grace = grace
        self.confirm = confirm
        self._pending: tuple[float, Update, tuple, StepResult | None] | None = None
        self._cond = threading.Condition()
        self._thread = threading.Thread(target=self._run, name="violation_grace", daemon=True)
        self._thread.start()

    def schedule(self, update: Update, key: tuple, result: StepResult | None = None) -> None:
        with self._cond:
            self._pending = (time.monotonic() + self.grace, update, key, result)
            self._cond.notify()

    def _run(self) -> None:
        while not rospy.is_shutdown():
            with self._cond:
                if self._pending is None:
                    self._cond.wait(0.5)
                    continue
                due, update, key, result = self._pending
                left = due - time.monotonic()
                if left > 0:
                    self._cond.wait(left)
                    continue
                self._pending = None
            self.confirm(update, key, result)


class ExecutorNode:
    """The ROS wiring around a Controller. Create after ``rospy.init_node``.

    ``negotiate`` (thesis §4.8, Alg. 3 S.2) is the negotiation hook: a callable
    ``negotiate(strategy, observation) -> Spec | None`` called from the resynthesis worker thread
    (never under the controller's lock) when environment characterization found no realizable
    specification; a realizable spec it returns runs next, None goes to S.1 (the user, as without a
    hook: no peer involved, absent or silent, already negotiated), ``NegotiationAbort`` aborts.
    Without it the node asks the user (``~add_env_liveness``). See docs/resilience.md, "Negotiation hook".
    """

    def __init__(self, controller: Controller, prepared: Prepared, options: Options, json_lines: bool = False,
                 watch_master: bool = True, negotiate: Negotiate | None = None):
        self.controller = controller
        self.prepared = prepared
        self.options = options
        self.json_lines = json_lines
        self.name = rospy.get_name()
        #: the decisions: what to publish, counters, mode, health and violation reports
        self.reports = NodeReports(controller, options.on_violation.value, options.recovery, prepared.input_topics,
                                   options.ready_timeout)
        self.resilient: BackgroundResilience | None = self.reports.resilient
        if self.resilient is not None:
            self.resilient.runner = thread_runner
            self.resilient.on_installed = self._on_installed
            self.resilient.on_changed = self._on_resilience_changed
            self.resilient.on_event = self._on_resilience_event
        if negotiate is not None:
            self.set_negotiate(negotiate)
        self._window_timer = None
        self._started_at = time.monotonic()
        #: when each output topic was last written (the heartbeat repeats the silent ones)
        self._written: dict[str, float] = {}
        self.freshness = Freshness(freshness_bounds(prepared.mapping, controller.inputs, options.freshness))
        self._statuses: dict[str, DiagnosticStatus] = {}
        self._status_lock = threading.Lock()
        with warnings.catch_warnings():
            # queue_size=None: publish() writes to the sockets in this thread, in call order (see _publish).
            warnings.simplefilter("ignore")
            self.output_pubs = {prop: [rospy.Publisher(t, Bool, queue_size=None, latch=True, tcp_nodelay=True)
                                       for t in topics]
                                for prop, topics in prepared.output_topics.items()}
        self.state_pub = rospy.Publisher("~state", ControllerState, queue_size=10, latch=True)
        # the controller's first state, latched for good: a recorder that connects after the first
        # burst of ~state (the initial state and its settling) still gets it (check_run --from-start)
        self.initial_pub = rospy.Publisher("~initial_state", ControllerState, queue_size=1, latch=True)
        self.valuation_pub = rospy.Publisher("~valuation", PropositionValuation, queue_size=10, latch=True)
        #: what this node runs (latched; again with each new strategy): viewers draw it and see restarts
        self.source_pub = rospy.Publisher("~source", ControllerSource, queue_size=10, latch=True)
        self._started_stamp = rospy.Time.now()
        self._source_key: tuple | None = None
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        self.confirmer = ViolationConfirmer(options.violation_grace, self._confirm_violation) \
            if options.violation_grace > 0 else None
        with controller.lock:
            self._publish(controller.set_running(not options.start_paused), force_outputs=True)
        # before the subscribers: a latched input may arrive (and _on_input run) at once
        self.tick_timer = self.ready_timer = self.publisher_timer = self.poll_timer = None
        #: inputs whose node's ~valuation has spoken: their Bool topics count for freshness only
        self._grouped: set[str] = set()
        #: each grouped input's ~valuation subscriber, and when its Bool was first held back for it
        self._group_of: dict[str, Any] = {}
        self._held_since: dict[str, float] = {}
        self.subscribers = []
        for topic, props in prepared.valuation_topics.items():  # before the Bools, which look them up
            subscriber = rospy.Subscriber(topic, PropositionValuation, self._on_valuation, callback_args=props,
                                          queue_size=10, tcp_nodelay=True)
            self.subscribers.append(subscriber)
            self._group_of.update(dict.fromkeys(props, subscriber))
        self.subscribers += [rospy.Subscriber(topic, Bool, self._on_input, callback_args=prop, queue_size=10,
                                              tcp_nodelay=True)
                             for prop, topic in prepared.input_topics.items()]
        self.service = rospy.Service("~set_running", SetBool, self._on_set_running)
        self.liveness_service = rospy.Service("~add_env_liveness", AddEnvLiveness, self._on_add_env_liveness)
        self.abort_service = rospy.Service("~abort", Trigger, self._on_abort)
        self.running_sub = rospy.Subscriber("~running", Bool, self._on_running_topic, queue_size=10)
        if self.resilient is not None:  # --characterize-after-seconds, and the handover after a negotiation
            self.poll_timer = rospy.Timer(rospy.Duration(POLL_PERIOD), self._on_poll)
        if options.rate > 0:
            self.tick_timer = rospy.Timer(rospy.Duration(1.0 / options.rate), self._on_tick)
        if options.ready_timeout > 0 and not controller.ready:
            self.ready_timer = rospy.Timer(rospy.Duration(options.ready_timeout), self._on_ready_timeout)
        self.heartbeat_timer = rospy.Timer(rospy.Duration(options.heartbeat), lambda _event: self.heartbeat()) \
            if options.heartbeat > 0 else None
        self.freshness_timer = rospy.Timer(rospy.Duration(self.freshness.check_period()),
                                           lambda _event: self.check_freshness()) if self.freshness.active else None
        if options.publisher_check_period > 0:
            self.publisher_timer = rospy.Timer(rospy.Duration(options.publisher_check_period),
                                               lambda _event: self.check_publishers())
        for status in INITIAL_STATUSES:
            self._set_status(status)
        self._update_mode(publish=False)
        self._update_health(publish=False)
        self.diagnostics_timer = rospy.Timer(rospy.Duration(DIAGNOSTICS_PERIOD), lambda _e: self.publish_diagnostics())
        # the options it runs with, defaults filled in, for viewers (before MasterWatch: set again after a restart)
        rospy.set_param("~" + EFFECTIVE_OPTIONS, effective_params(options))
        self.master_watch = MasterWatch(on_restart=self._on_master_restart) if watch_master else None
        rospy.on_shutdown(self._on_shutdown)
        rospy.loginfo("%s: %d inputs (%s), %d outputs (%s); %s", self.name, len(prepared.input_topics),
                      ", ".join(prepared.input_topics.values()) or "none", len(prepared.output_topics),
                      ", ".join(t for ts in prepared.output_topics.values() for t in ts) or "none",
                      "paused" if options.start_paused else "waiting for every input to report")
        if controller.ready:
            with controller.lock:
                self._publish(controller.advance())
        self.publish_diagnostics()

    # callbacks (each runs in a rospy thread; the controller's lock orders steps and publications)
    def _on_input(self, msg: Bool, prop: str) -> None:
        now = time.monotonic()
        self.freshness.seen(prop, now)
        if prop in self._grouped:
            return  # its node's ~valuation carries it (one message for a change of several)
        if self._valuation_on_its_way(prop, now):
            return
        self._report_inputs({prop: msg.data})

    def _valuation_on_its_way(self, prop: str, now: float) -> bool:
        """Whether ``prop``'s node has a ~valuation publisher connected that has not spoken yet: its
        latched message (which carries ``prop``) follows the connection, so this Bool waits for it
        rather than be read apart from the others of its change. Bounded by VALUATION_WAIT seconds,
        for a node that advertises ~valuation but has not published one."""
        subscriber = self._group_of.get(prop)
        if subscriber is None or subscriber.get_num_connections() == 0:
            return False
        since = self._held_since.setdefault(prop, now)
        if now - since <= VALUATION_WAIT:
            return True
        if since >= 0:
            rospy.logwarn("%s: %s's ~valuation is connected but silent after %.0f s; reading its Bool topic",
                          self.name, prop, VALUATION_WAIT)
            self._held_since[prop] = -1.0  # warned once; from now on the Bool is read
        return False

    def _on_valuation(self, msg: PropositionValuation, props: list[str]) -> None:
        """A node owning several inputs sent their valuation at once: one update for all of them,
        and from now on its per-proposition topics only say it is alive."""
        try:
            values = msg_to_valuation(msg)
        except ValueError as err:
            rospy.logwarn_throttle(10, "%s: %s", self.name, err)
            return
        by_topic = {self.prepared.input_topics[p]: p for p in props}
        got = {by_topic[k]: v for k, v in values.items() if k in by_topic}
        if not got:
            return
        now = time.monotonic()
        for prop in got:
            self.freshness.seen(prop, now)
        first = [p for p in got if p not in self._grouped]
        self._grouped.update(got)
        if first:
            rospy.loginfo("%s: inputs %s now come from %s, one message per change (their Bool topics only "
                          "count for freshness)", self.name, ", ".join(first), msg._connection_header["topic"]
                          if getattr(msg, "_connection_header", None) else "their node's ~valuation")
        self._report_inputs(got)

    def _report_inputs(self, values: dict[str, bool]) -> None:
        """Record readings and step (at once, or when the input window closes)."""
        if any(p in self.controller.unknown for p in values):  # known again: resume (check_freshness steps)
            self.controller.record(values)
            self.check_freshness()
            return
        if self.options.input_window > 0:
            with self.controller.lock:
                if self.controller.record(values) and self._window_timer is None:
                    self._window_timer = rospy.Timer(rospy.Duration(self.options.input_window), self._on_window,
                                                     oneshot=True)
            return
        with self.controller.lock:
            was_ready = self.controller.ready
            update = self.controller.report_many(values)
            self._publish(update)
            if not was_ready and self.controller.ready:
                rospy.loginfo("%s: every input has reported", self.name)
                if self.ready_timer is not None:
                    self.ready_timer.shutdown()

    def _on_window(self, _event: Any) -> None:
        """The input window closed: step once with every reading that arrived in it."""
        with self.controller.lock:
            self._window_timer = None
            was_ready = self.controller.ready
            self._publish(self.controller.advance())
            if not was_ready and self.controller.ready:
                rospy.loginfo("%s: every input has reported", self.name)
                if self.ready_timer is not None:
                    self.ready_timer.shutdown()

    def _on_tick(self, _event: Any) -> None:
        with self.controller.lock:
            if self._window_timer is not None:
                return  # readings are arriving: the window's step comes
            self._publish(self.controller.tick())

    def heartbeat(self) -> None:
        """Republish the current value of every output not published for ``--heartbeat`` s (the
        output nodes' deadman listens for it; one that changed meanwhile needs no repeat)."""
        with self.controller.lock:
            outputs = self.controller.outputs_published()
            if outputs is None:
                return
            now = time.monotonic()
            for prop, value in outputs.items():
                if now - self._written.get(prop, 0.0) >= self.options.heartbeat * 0.9:
                    self._write(prop, value, now)

    def _write(self, prop: str, value: bool, now: float) -> None:
        for pub in self.output_pubs[prop]:
            pub.publish(Bool(value))
        self._written[prop] = now

    def check_freshness(self) -> None:
        """Mark the inputs older than their freshness bound unknown, and the others known (the
        controller resumes when none is left); say so on /diagnostics and in the log."""
        with self.controller.lock:
            now = time.monotonic()
            waited = self.options.ready_timeout > 0 and now - self._started_at >= self.options.ready_timeout
            stale = self.freshness.stale(now, self.controller.missing_inputs() if waited else ())
            if stale == self.controller.unknown:
                return
            update = self.controller.set_unknown(stale)
            status = self.reports.unknown_report(update, unknown_text(stale, self.prepared.input_topics,
                                                                      self.freshness, now))
            self._publish(update, force_state=True)
            if update.started and self.ready_timer is not None:
                self.ready_timer.shutdown()
        log = {0: rospy.loginfo, 1: rospy.logwarn}.get(status.level, rospy.logerr)
        log("%s: %s", self.name, status.message)
        self._set_status(status)
        self._update_health()

    def _on_set_running(self, request: Any) -> SetBoolResponse:
        self.set_running(request.data)
        return SetBoolResponse(success=True, message="running" if request.data else "paused")

    def _on_running_topic(self, msg: Bool) -> None:
        self.set_running(msg.data)

    def set_running(self, running: bool) -> None:
        with self.controller.lock:
            changed = running != self.controller.running
            self._publish(self.controller.set_running(running), force_state=changed)
        if changed:
            rospy.loginfo("%s: %s", self.name, "running" if running else "paused: every output is false")

    # resilient execution (thesis ch. 4)
    def set_negotiate(self, negotiate: Negotiate | None) -> bool:
        """Install the negotiation hook (see the class docstring); False when characterization is off."""
        if self.resilient is None:
            rospy.logwarn("%s: a negotiation hook needs environment characterization (--characterize); "
                          "not installed", self.name)
            return False
        with self.controller.lock:
            self.resilient.negotiate = negotiate
        return True

    def _on_add_env_liveness(self, request: Any) -> AddEnvLivenessResponse:
        """Alg. 3 line 6: the user's environment liveness; synthesis runs in this service thread,
        not under the controller's lock."""
        answer = self.reports.add_env_liveness(request.formula, self.options.characterized_spec)
        if answer.log is not None:
            (rospy.logwarn if answer.log[0] == "warn" else rospy.loginfo)("%s: %s", self.name, answer.log[1])
        return AddEnvLivenessResponse(success=answer.success, code=answer.code, mode=answer.mode,
                                      message=answer.message)

    def _on_abort(self, _request: Any) -> TriggerResponse:
        """Abort (Alg. 3 line 11): every output false, the node stays up reporting ERROR."""
        with self.controller.lock:
            refusal = self.reports.abort_refusal()
            if refusal is not None:  # not done again: the tool's exit 1
                return TriggerResponse(success=False, message=refusal)
            if self.resilient is not None:
                self.resilient.abort(USER_ABORT)  # -> _on_resilience_changed aborts the controller
            if self.controller.aborted is None:
                self._abort_controller(USER_ABORT)
        return TriggerResponse(success=True, message="aborted: every output is false")

    def _abort_controller(self, reason: str) -> None:
        """Under the lock: every output false, no more steps, ERROR on /diagnostics."""
        update = self.controller.abort(reason)
        text, event = aborted_report(reason)
        rospy.logerr("%s: %s", self.name, text)
        self._publish(update, force_state=True)
        if self.json_lines:
            print(json.dumps(event), flush=True)

    def _on_poll(self, _event: Any) -> None:
        """--characterize-after-seconds, or the handover after a negotiation: a violation may outlast
        it without any step."""
        if self.resilient.poll():
            with self.controller.lock:
                self._on_resilience_changed()

    def _on_installed(self, state: Any) -> None:
        """A new strategy is in place (under the lock): continue from ``state`` and publish."""
        self._publish(self.controller.restart_from(state), force_state=True)

    def _on_resilience_changed(self) -> None:
        """The resilient strategy's mode changed outside a step (under the lock)."""
        strategy = self.resilient
        if strategy.mode is Mode.ABORTED and self.controller.aborted is None:
            self._abort_controller(getattr(strategy, "_abort_reason", "aborted"))
            return
        if strategy.mode is Mode.WAITING_FOR_USER and strategy.explanation is not None:
            rospy.logwarn("%s: %s", self.name, waiting_text(strategy.explanation))
        self._publish_state(Update(outputs=self.controller.current_outputs(), state=self.controller.state))
        self._update_mode()

    def _on_resilience_event(self, event: Event) -> None:
        rospy.loginfo("%s: [%s] %s", self.name, event.mode.value, event.message)
        if self.json_lines:
            print(json.dumps(counters_event("resilience", self.reports.counters, mode=event.mode.value,
                                            message=event.message, step=event.step)), flush=True)

    def _current_mode(self) -> str:
        return self.reports.current_mode()

    def _counters(self) -> Counters:
        return self.reports.counters

    def _violated_clauses(self) -> list[str]:
        return self.reports.violated_clauses()

    def _update_mode(self, publish: bool = True) -> None:
        """The "mode" status (and the "spec file" one), from ``NodeReports.mode_report``."""
        report = self.reports.mode_report()
        if report.spec_file is not None:
            self._set_status(report.spec_file, publish)
        self._set_status(report.status, publish)
        if report.changed:
            rospy.loginfo("%s: mode %s", self.name, report.mode)
            if self.json_lines:
                print(json.dumps(report.event), flush=True)

    def _on_ready_timeout(self, _event: Any) -> None:
        if self.freshness.active:
            self.check_freshness()  # silent inputs with a freshness bound are unknown from now on
        text = self.reports.silent_inputs(time.monotonic() - self._started_at)
        if text is None:
            return
        rospy.logerr("%s: %s", self.name, text)
        self._update_health()

    def _on_master_restart(self) -> None:
        with self.controller.lock:
            # Latched values live in this node, but republish the state for listeners that lost it.
            self._publish_state(Update(outputs=self.controller.current_outputs(), state=self.controller.state))
        self.publish_diagnostics()

    def _on_shutdown(self) -> None:
        # Leave the robot idle: drive every output false on the way out.
        for pubs in self.output_pubs.values():
            for pub in pubs:
                try:
                    pub.publish(Bool(False))
                except Exception:  # noqa: BLE001 - shutting down; nothing left to report to
                    pass

    def check_publishers(self) -> list[str]:
        """Warn about input topics with more than one publisher; returns the warnings issued now."""
        try:
            publishers = master_call("getSystemState", caller=self.name)[0]
        except Exception as err:  # noqa: BLE001 - the master may be going away
            rospy.logdebug("%s: cannot ask the master for publishers: %s", self.name, err)
            return []
        by_topic = {topic: tuple(sorted(nodes)) for topic, nodes in publishers}
        issued, status = self.reports.publishers(by_topic)
        for text in issued:
            rospy.logwarn("%s: %s", self.name, text)
        self._set_status(status)
        return issued

    # publishing
    def _publish(self, update: Update, force_outputs: bool = False, force_state: bool = False) -> None:
        changed = update.outputs if force_outputs else update.changed_outputs
        # Falling edges first, then (after EDGE_GAP) the rising ones: a listener that merges the output
        # topics in arrival order never sees more true outputs than a state of the strategy has
        # (docs/executor.md; ~valuation is the atomic view).
        falling = [p for p, v in changed.items() if not v]
        rising = [p for p, v in changed.items() if v]
        for prop in falling:
            self._write(prop, False, time.monotonic())
        if falling and rising and EDGE_GAP > 0:
            time.sleep(EDGE_GAP)
        for prop in rising:
            self._write(prop, True, time.monotonic())
        publication = self.reports.publication(update, force_outputs, force_state)
        update = publication.update
        if publication.state:
            self._publish_state(update)
        if publication.step:
            self._report_step(update)
        if publication.violation:
            if self.confirmer is not None:
                self.confirmer.schedule(update, readings_key(self.controller.readings), publication.result)
            else:
                self._report_violation(update, publication.result)
        elif publication.cleared is not None:
            rospy.loginfo("%s: inputs admissible again; continuing", self.name)
            self._set_status(publication.cleared)
        if update.error:
            rospy.logerr("%s: %s (waiting for the inputs to change)", self.name, update.error)
        if publication.health:
            self._update_health()
        if publication.mode:
            self._update_mode()

    def _publish_state(self, update: Update) -> None:
        """``~state``: each state settling went through (its own outputs, which were never sent to
        the output topics: a record of the run then holds every state, and check_run counts the
        goals met there), then the state reached; ``~valuation``: the reached one."""
        stamp = rospy.Time.now()
        if strategy_source(self.prepared.spec_path, self.resilient) != self._source_key:
            self._publish_source(running_spec(self.prepared.spec_path, self.resilient, self.options), stamp)
        readings = self.controller.readings
        inputs = {p: readings.get(p, False) for p in self.controller.inputs}
        for index, state in enumerate(update.passed):
            outputs = {p: bool(state.outputs[p]) if p in state.outputs else False for p in self.controller.outputs}
            msg = self._state_msg(state, inputs, outputs, stamp)
            msg.settling = True
            if update.started and index == 0:
                self.initial_pub.publish(msg)
            self.state_pub.publish(msg)
        msg = self._state_msg(update.state, inputs, update.outputs, stamp)
        if update.started and not update.passed:
            self.initial_pub.publish(msg)
        self.state_pub.publish(msg)
        self.valuation_pub.publish(valuation_to_msg({**inputs, **update.outputs}, stamp))

    def _state_msg(self, state: Any, inputs: dict[str, bool], outputs: dict[str, bool], stamp: Any) -> Any:
        msg = ControllerState()
        msg.header.stamp = stamp
        msg.state_id = state.id if state is not None else -1
        msg.goal_index = state.goal if state is not None else -1
        msg.inputs = valuation_to_msg(inputs, stamp)
        msg.outputs = valuation_to_msg(outputs, stamp)
        msg.running = self.controller.running
        counters = self._counters()
        msg.mode = self._current_mode()
        msg.violations, msg.recovery_steps, msg.unsafe_steps = (counters.violations, counters.recovery_steps,
                                                                counters.unsafe)
        msg.resyntheses, msg.resyntheses_ec1, msg.resyntheses_ec2, msg.resyntheses_user = (
            counters.resyntheses, counters.ec1, counters.ec2, counters.user)
        msg.unrealizable = counters.unrealizable
        msg.negotiations, msg.resyntheses_negotiated = counters.negotiations, counters.negotiated
        msg.violated_clauses = self._violated_clauses()
        msg.spec_file, msg.strategy_generation = strategy_source(self.prepared.spec_path, self.resilient)
        return msg

    def _publish_source(self, source: RunningSpec, stamp: Any) -> None:
        """``~source``: the spec, generation and options of the running strategy (under the lock)."""
        msg = ControllerSource()
        msg.header.stamp = stamp
        msg.started = self._started_stamp
        msg.spec_file, msg.spec_sha256, msg.spec_text = source.spec_file, source.spec_sha256, source.spec_text
        msg.strategy_file, msg.strategy_generation = source.strategy_file, source.generation
        msg.robotics_semantics, msg.cooperative = source.robotics_semantics, source.cooperative
        msg.max_explicit_states = source.max_explicit_states
        self.source_pub.publish(msg)
        self._source_key = (source.spec_file, source.generation)

    def _report_step(self, update: Update) -> None:
        text, event = step_report(update)
        rospy.loginfo("%s: %s", self.name, text)
        if self.json_lines:
            print(json.dumps(event), flush=True)

    def _confirm_violation(self, update: Update, key: tuple, result: StepResult | None = None) -> None:
        """Report ``update``'s violation if the same inputs are still there after the grace time (and,
        unless it was recovered, still inadmissible)."""
        with self.controller.lock:
            if self.reports.still_violated(update, key):
                self._report_violation(update, result)

    def _report_violation(self, update: Update, result: StepResult | None = None) -> None:
        """Once per distinct violation (``NodeReports.violation``): recovered is a WARN naming the broken
        assumptions; otherwise an ERROR, naming also the guarantees no move keeps."""
        report = self.reports.violation(update, result)
        if report is None:
            return
        (rospy.logwarn if update.recovered else rospy.logerr)("%s: %s", self.name, report.text)
        self._set_status(Status(report.level, "environment assumptions", report.text, report.values))
        if self.json_lines:
            print(json.dumps({**report.event, "outputs": update.outputs}), flush=True)

    # diagnostics: one status per concern, all republished every DIAGNOSTICS_PERIOD
    def _update_health(self, publish: bool = True) -> None:
        for status in self.reports.health(time.monotonic() - self._started_at):
            self._set_status(status, publish)

    def _set_status(self, report: Status, publish: bool = True) -> None:
        """Keep ``report`` as the node's status of its concern; send it at once when it changed (unless
        quiet or ``publish`` is False)."""
        status = DiagnosticStatus(level=report.level, name=f"{self.name}: {report.what}", message=report.message,
                                  hardware_id=self.name, values=[KeyValue(k, v) for k, v in report.values])
        with self._status_lock:
            old = self._statuses.get(report.what)
            self._statuses[report.what] = status
        if publish and not report.quiet and (old is None or (old.level, old.message) != (report.level,
                                                                                         report.message)):
            self._send([status])

    def publish_diagnostics(self) -> None:
        """Every status of the node, as rqt_robot_monitor expects them: at least once a second."""
        with self._status_lock:
            statuses = list(self._statuses.values())
        self._send(statuses)

    def _send(self, statuses: list[DiagnosticStatus]) -> None:
        array = DiagnosticArray(status=statuses)
        array.header.stamp = rospy.Time.now()
        try:
            self.diag_pub.publish(array)
        except rospy.ROSException:
            pass  # shutting down


def _cli_values(args: argparse.Namespace) -> dict[str, Any]:
    """The options given on the command line (every flag but the arguments and ``--check``/``--json``)."""
    return {name: value for name, value in vars(args).items() if name not in ("spec", "mapping", "check", "json")}


def _check(args: argparse.Namespace) -> int:
    """``--check``: everything up to the strategy, no ROS."""
    options = merge_options(_cli_values(args))
    check_characterized_spec(options, [args.spec, args.mapping, options.strategy or None])
    prepared = prepare(args.spec, args.mapping, options.namespace, rosgraph.names.get_ros_namespace())
    for warning in prepared.warnings:
        cli.warn(PROG, warning)
    summary = check_summary(args.spec, args.mapping, prepared, options, log=lambda text: cli.say(PROG, text))
    if args.json:
        cli.print_json(summary)
    if summary.get("error"):
        raise ExecutorError(f"--init-props: {summary['error']}")
    if not args.json:
        ins = ", ".join(f"{p} <- {t}" for p, t in prepared.input_topics.items()) or "none"
        outs = ", ".join(f"{p} -> {' '.join(ts)}" for p, ts in prepared.output_topics.items()) or "none"
        print(f"ok: namespace {prepared.namespace}; inputs: {ins}; outputs: {outs}")
    return Exit.OK


def _run(args: argparse.Namespace, negotiate: Negotiate | None = None,
         setup: Callable[[ExecutorNode], None] | None = None) -> int:
    """Load the files (errors before touching ROS), then start the node; errors after ``init_node``
    end in one ``[FATAL]`` line."""
    spec, mapping, warnings_ = load_inputs(args.spec, args.mapping)
    for warning in warnings_:
        cli.warn(PROG, warning)
    node_argv, refused = split_param_args(sys.argv)
    init_node(NODE_NAME, argv=node_argv)
    try:
        if refused:
            raise ExecutorError(refused)
        options = merge_options(_cli_values(args), params_lookup(private_params()))
        check_characterized_spec(options, [args.spec, args.mapping, options.strategy or None])
        namespace = scenario_namespace(options.namespace, rospy.get_namespace(), mapping, args.spec)
        in_topics, out_topics = resolve_topics(mapping, spec.inputs, spec.outputs, namespace.strip("/"))
        prepared = Prepared(spec, mapping, namespace, in_topics, out_topics, warnings_, args.spec,
                            valuation_topics(mapping, spec.inputs, namespace.strip("/")))
        init = parse_init_props(options.init_props, spec)
        strategy = build_strategy(spec, options, log=lambda text: rospy.loginfo("%s: %s", rospy.get_name(), text))
        controller = make_controller(strategy, options, init)
        classes = negotiation_classes(mapping, spec)
        auth = classes_authenticator(classes) if classes is not None else None
    except UserError as err:
        rospy.logfatal("%s", err)
        rospy.signal_shutdown("bad configuration")
        return int(err.code)
    negotiator = None  # the mapping's negotiation: key (docs/negotiation.md), unless a hook is given
    if classes is not None and negotiate is None and setup is None:
        negotiator = prepare_negotiation(classes, controller.strategy, options.negotiation_timeout, auth)
    node = ExecutorNode(controller, prepared, options, json_lines=args.json,
                        negotiate=negotiator.hook if negotiator is not None else negotiate)
    if setup is not None:
        setup(node)
    elif negotiator is not None:
        NegotiationEndpoint(negotiator, node.resilient, controller, timeout=options.negotiation_timeout, auth=auth)
    rospy.spin()
    return Exit.OK


def main(argv: Sequence[str] | None = None, negotiate: Negotiate | None = None,
         setup: Callable[[ExecutorNode], None] | None = None) -> int:
    """The ``controller_executor`` command. Extension points (docs/resilience.md, "Negotiation hook"):
    ``negotiate`` is the negotiation hook (see ``ExecutorNode``); ``setup(node)`` is called once the
    node is up (rospy initialised, controller and services in place), e.g. to start a negotiation
    endpoint on ``node.controller`` and install its hook with ``node.set_negotiate``."""
    raw = list(sys.argv if argv is None else [PROG, *argv])
    args = build_parser().parse_args(rospy.myargv(raw)[1:])
    return cli.run(PROG, lambda: _check(args) if args.check else _run(args, negotiate, setup))


__all__ = ["ExecutorError", "ExecutorNode", "Options", "ViolationConfirmer", "build_parser", "main"]
