"""Bases for proposition nodes: the ROS programs a proposition topic is mapped to (thesis 3.5.1).

An *input proposition node* turns sensing into a ``std_msgs/Bool`` that it publishes on the input
proposition topic, at a steady rate and at once on every change. An *output proposition node*
subscribes to an output proposition topic and reacts to its edges: it starts its behaviour on the
rising edge, may act periodically while the value is true, stops on the falling edge, and does
nothing while false. On shutdown it drives its behaviour off.

Deadman: the controller executor republishes every output topic at a steady rate (its heartbeat,
``--heartbeat``). An output node that heard its topic once and then hears nothing for ``~deadman``
seconds (default 1; 0: off) — a partition, a dead executor, a lost link — goes to its safe state,
the falling-edge behaviour (zero velocity, goal cancelled, ``~on_false`` published), says so once
(WARN and a /diagnostics status) and follows the topic again from its next message, as the
cmd_vel timeouts of twist_mux and of base drivers do.

The proposition topic comes from the ``~proposition_topic`` parameter, or else from the relative
name ``proposition`` (remap it: ``proposition:=/ns/outputs/move``).

The ROS-free parts live in the runtime layer: parameters and their checks in
``ltl_stack.runtime.config.node_params``, edges and staleness in ``ltl_stack.runtime.propositions.edges``.
"""
from __future__ import annotations

import io
import struct
import sys
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import genpy
import roslib.message
import rospy
import rostopic
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import Bool

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.msg import PropositionValuation
from ltl_stack.ros.master import init_node, private_params
from ltl_stack.ros.master_watch import MasterWatch
from ltl_stack.ros.valuation import valuation_to_msg
from ltl_stack.runtime.config.node_params import (
    Bound,
    NodeConfigError,
    Param,
    coerce_param,
    describe_params,
    params_help,
    shown,
    split_param_args,
)
from ltl_stack.runtime.propositions.edges import FALLING, RISING, EdgeDetector, StaleWatch

#: Exit code of a node whose parameters are wrong (missing file, bad value, unknown type).
EXIT_BAD_CONFIG = Exit.BAD_INPUT


def parse_node_cli(prog: str, kind: str, description: str, params: Sequence[Param],
                   argv: Sequence[str]) -> None:
    """Handle ``--help`` and ``--json`` of a node script; return to let the node run otherwise.

    Both exit 0 before the node touches ROS. ``argv`` must already be stripped of ROS remappings
    (``rospy.myargv``).
    """
    epilog = ("private parameters (set as _name:=value, or from a launch file / mapping):\n"
              + params_help(params))
    parser = cli.ToolParser(prog=prog, description=description, epilog=epilog,
                            exit_codes=(Exit.OK, Exit.BAD_INPUT))
    parser.add_argument("--json", action="store_true",
                        help="print this node's kind and parameters as JSON and exit")
    args = parser.parse_args(list(argv))
    if args.json:
        cli.print_json(describe_params(kind, description, params))
        sys.exit(0)


def read_params(params: Sequence[Param], node: str = "") -> dict[str, Any]:
    """Read each ``~name`` (or the first alias that is set), coerced to its type."""
    values: dict[str, Any] = {}
    given = private_params()  # one call, with a timeout (rospy's has_param/get_param have none)
    for p in params:
        value = None
        found = False
        for name in (p.name, *p.aliases):
            if name in given:
                value = given[name]
                found = True
                break
        if not found:
            value = p.default
        values[p.name] = coerce_param(p, value, node or rospy.get_name())
    return values


def proposition_topic(config: dict[str, Any], default: str = "proposition") -> str:
    """The proposition topic: ``~proposition_topic`` if set, else the (remappable) relative name."""
    return rospy.resolve_name(str(config.get("proposition_topic") or default))


def message_class(type_name: str, what: str = "message") -> type:
    """The Python class of a message type given as ``pkg/Type`` or ``pkg.msg.Type``."""
    text = type_name.strip()
    if ".msg." in text:
        text = text.replace(".msg.", "/")
    cls = None
    try:
        cls = roslib.message.get_message_class(text) if "/" in text else None
    except (ValueError, ImportError):
        cls = None
    if cls is None:
        raise NodeConfigError(f"unknown {what} type {type_name!r} (expected pkg/Type, e.g. std_msgs/Bool)")
    return cls


def fill_message(cls: type, fields: dict[str, Any], what: str = "message") -> Any:
    """A ``cls`` message with ``fields`` set (nested dicts for nested messages, as rostopic pub)."""
    msg = cls()
    try:
        genpy.message.fill_message_args(msg, [fields])
        msg.serialize(io.BytesIO())  # a field of the wrong type ({data: notabool}) fails here, not at publish
    except (genpy.MessageException, genpy.SerializationError, ValueError, TypeError, KeyError, AttributeError,
            struct.error) as error:
        raise NodeConfigError(f"{what} {shown(fields)} does not fit {cls._type}: {_first_line(error)}") from None
    return msg


def _first_line(error: Exception) -> str:
    text = str(error).strip().splitlines()
    return text[0] if text else type(error).__name__


def wait_for_topic_class(topic: str, poll: float = 0.2) -> type | None:
    """Block until ``topic`` is advertised and return its message class (None on shutdown)."""
    while not rospy.is_shutdown():
        try:
            cls, _, _ = rostopic.get_topic_class(topic, blocking=False)
        except rostopic.ROSTopicException:
            cls = None
        if cls is not None:
            return cls
        rospy.sleep(poll)
    return None


def wait_until_sent(pub: rospy.Publisher, timeout: float = 1.0) -> bool:
    """Wait, at most ``timeout`` s, until every connection of ``pub`` has sent what was published.

    A publisher with ``queue_size`` sends from one thread per connection. On shutdown rospy closes
    the connections right after the shutdown hooks, so a message still queued there (set_velocity's
    zero Twist when the node is killed) was lost on a busy machine and the robot kept its last
    command. rospy has no public flush: this looks at its queued connection's queue and whether its
    sending thread is back waiting (``rospy.impl.tcpros_pubsub.QueuedConnection``); a connection
    without them sends synchronously. True when all was sent in time."""
    deadline = time.monotonic() + timeout
    while True:
        if all(_sent(c) for c in list(pub.impl.connections)):
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.002)


def _sent(connection: Any) -> bool:
    queue = connection.__dict__.get("_queue")
    if queue is None:
        return True
    condition = connection.__dict__.get("_cond_data_available")
    waiting = getattr(condition, "_waiters", None)
    return not queue and (waiting is None or len(waiting) > 0 or bool(connection.done))


class PropositionPublisher:
    """Publishes one Boolean proposition: latched, at once on change, and again every 1/rate s."""

    def __init__(self, topic: str, rate: float = 10.0, initial: bool | None = False) -> None:
        self._bool = Bool
        self._lock = threading.Lock()
        self._value = initial
        self.topic = topic
        self._pub = rospy.Publisher(topic, Bool, queue_size=10, latch=True)
        if initial is not None:
            self._pub.publish(Bool(data=bool(initial)))
        self._timer = rospy.Timer(rospy.Duration(1.0 / rate), self._tick) if rate > 0 else None

    @property
    def value(self) -> bool | None:
        return self._value

    def set(self, value: bool) -> bool:
        """Set the proposition; publish now if it changed. Return whether it changed."""
        value = bool(value)
        with self._lock:
            changed = value != self._value
            self._value = value
            if changed:
                self._pub.publish(self._bool(data=value))
        return changed

    def _tick(self, _event: Any) -> None:
        self.republish()

    def republish(self) -> None:
        """Publish the value again (the periodic republication; a node with many propositions
        makes them with ``rate=0`` and calls this from one timer of its own)."""
        with self._lock:
            if self._value is not None:
                self._pub.publish(self._bool(data=self._value))

    def close(self) -> None:
        if self._timer is not None:
            self._timer.shutdown()


class PropositionGroup:
    """Several propositions of one node that change together (a robot's regions, exactly one true; a
    world's sensors): each on its own ``std_msgs/Bool`` topic, republished by one timer, and their
    whole valuation on ``~valuation`` (``ltl_stack/PropositionValuation``, latched; keys: the resolved
    topics) whenever a proposition is first published or changes, before the Bool topics. The executor
    reads ``<node>/valuation`` of a node the mapping gives several inputs, so one change of several
    propositions is one update, however far apart a slow link delivers the Bool messages
    (docs/several_machines.md)."""

    def __init__(self, rate: float = 10.0, topic: str = "~valuation") -> None:
        self._lock = threading.Lock()
        self.publishers: dict[str, PropositionPublisher] = {}
        self._valuation = rospy.Publisher(topic, PropositionValuation, queue_size=10, latch=True)
        self._timer = rospy.Timer(rospy.Duration(1.0 / rate), self._republish) if rate > 0 else None

    def add(self, topic: str, initial: bool | None = False) -> PropositionPublisher:
        """The Bool publisher of one more proposition (published as ``initial`` unless None)."""
        resolved = rospy.resolve_name(topic)
        with self._lock:
            if resolved not in self.publishers:
                if initial is not None:  # a listener that connects now gets the valuation (latched) first
                    self._valuation.publish(valuation_to_msg({**self.values(), resolved: bool(initial)}))
                self.publishers[resolved] = PropositionPublisher(resolved, rate=0.0, initial=initial)
            return self.publishers[resolved]

    def values(self) -> dict[str, bool]:
        """The propositions' current values by topic (those published at least once)."""
        return {t: bool(p.value) for t, p in self.publishers.items() if p.value is not None}

    def set_many(self, values: Mapping[str, bool]) -> bool:
        """Set several propositions at once (topics as ``add`` takes them; new ones are added): when any
        changed, one ``~valuation`` with every proposition, then the Bools, false ones first (a listener of
        the Bool topics never sees two regions at once). Return whether any changed."""
        wanted = {rospy.resolve_name(t): bool(v) for t, v in values.items()}
        for topic in wanted:
            if topic not in self.publishers:
                self.add(topic, initial=None)
        with self._lock:
            if all(self.publishers[t].value is v for t, v in wanted.items()):
                return False
            whole = {**self.values(), **wanted}
            self._valuation.publish(valuation_to_msg(whole))
            for topic, value in sorted(wanted.items(), key=lambda item: item[1]):
                self.publishers[topic].set(value)
        return True

    def _republish(self, _event: Any) -> None:
        for output in list(self.publishers.values()):
            output.republish()

    def close(self) -> None:
        if self._timer is not None:
            self._timer.shutdown()


@dataclass
class NodeSpec:
    """What a node script needs to know about its node: name, kind, text and parameters."""

    name: str
    kind: str
    description: str
    params: list[Param] = field(default_factory=list)


#: Parameters every input node reads.
INPUT_PARAMS = [
    Param("proposition_topic", "", "topic of the input proposition (default: relative name 'proposition')",
          ros_name=True),
    Param("rate", 10.0, "republish the Boolean this often (Hz; 0: only on change); it is also published at "
          "once on change", bound=Bound.RATE_OR_ZERO),
    Param("init_value", False, "value published before the first sensing arrives"),
    Param("stale_after", 0.0, "seconds without sensing after which ~stale_value is published "
          "until sensing resumes (0: never)", bound=Bound.NON_NEGATIVE),
    Param("stale_value", False, "value published while the sensing is stale"),
]

#: Parameters every output node reads.
OUTPUT_PARAMS = [
    Param("proposition_topic", "", "topic of the output proposition (default: relative name 'proposition')",
          ros_name=True),
    Param("rate", 10.0, "how often (Hz) the behaviour acts while the proposition is true", bound=Bound.RATE),
    Param("deadman", 1.0, "seconds without a message on the proposition topic (the executor republishes it "
          "every --heartbeat s) after which the node goes to its safe state, the falling-edge behaviour, "
          "until messages return (0: off)", bound=Bound.PERIOD_OR_ZERO),
]


class InputPropositionNode:
    """Base of input proposition nodes: subclasses call ``self.set_value(bool)`` from sensing."""

    def __init__(self, config: dict[str, Any]) -> None:
        self.config = config
        self.output = PropositionPublisher(proposition_topic(config), rate=config["rate"],
                                           initial=config["init_value"])
        after = float(config.get("stale_after", 0.0))
        self.stale = StaleWatch(after, time.monotonic())
        self._sensing_lock = threading.Lock()  # a stale value never overwrites fresh sensing
        self._stale_timer = rospy.Timer(rospy.Duration(min(after / 4, 0.1)), self._check_stale) \
            if after > 0 else None

    def set_value(self, value: bool) -> None:
        """Publish the sensed value (and end a stale period)."""
        with self._sensing_lock:
            if self.stale.seen(time.monotonic()):
                rospy.loginfo("%s: sensing resumed", rospy.get_name())
            if self.output.set(value):
                rospy.logdebug("%s: %s -> %s", rospy.get_name(), self.output.topic, bool(value))

    def _check_stale(self, _event: Any) -> None:
        with self._sensing_lock:
            if self.stale.check(time.monotonic()):
                value = bool(self.config["stale_value"])
                rospy.logwarn("%s: no sensing for %.2f s: publishing %s on %s until it resumes",
                              rospy.get_name(), self.stale.after, value, self.output.topic)
                self.output.set(value)

    def spin(self) -> None:
        rospy.spin()
        if self._stale_timer is not None:
            self._stale_timer.shutdown()
        self.output.close()


class TopicMessageSensor(InputPropositionNode):
    """An input node whose value comes from each message on ``~topic``, of the class ``~type`` names or,
    when empty, of the type the master reports (waited for in ``spin``). Subclasses check that a class
    has what they read (``check``: ``NodeConfigError`` naming the parameter), compute the value of a
    message (``value``) and say what they read in the one error line logged when a message cannot be
    read (``what``)."""

    def __init__(self, config: dict[str, Any]) -> None:
        self.cls = message_class(config["type"]) if config["type"] else None
        if self.cls is not None:
            self.check(self.cls)
        self._warned = False
        super().__init__(config)

    def check(self, cls: type) -> None:
        raise NotImplementedError

    def value(self, msg: Any) -> bool:
        raise NotImplementedError

    def what(self) -> str:
        return self.config["topic"]

    def spin(self) -> None:
        cls = self.cls or wait_for_topic_class(rospy.resolve_name(self.config["topic"]))
        if cls is None:
            return
        if self.cls is None:
            self.check(cls)  # the type the master reports
        rospy.Subscriber(self.config["topic"], cls, self._on_msg, queue_size=10)
        super().spin()

    def _on_msg(self, msg: Any) -> None:
        """A message whose value cannot be read (an index past the end of its array) says nothing
        about the proposition: it takes ``~stale_value``, as when sensing stops, never keeps the last
        value (one error line per run of such messages)."""
        try:
            value = self.value(msg)
        except (LookupError, TypeError, ValueError) as error:
            if not self._warned:
                rospy.logerr("%s: %s: %s (publishing ~stale_value %s until a message can be read)",
                             rospy.get_name(), self.what(), error, bool(self.config["stale_value"]))
                self._warned = True
            with self._sensing_lock:
                self.output.set(bool(self.config["stale_value"]))
            return
        self._warned = False
        self.set_value(value)


class OutputPropositionNode:
    """Base of output proposition nodes.

    Subclasses override ``on_rising`` (start the behaviour), ``while_true`` (called every 1/rate s
    while the proposition is true, after the rising edge), ``on_falling`` (stop the behaviour) and
    ``on_shutdown`` (the node stops while active; by default ``on_falling``). The hooks run under one
    lock, so they never overlap.
    """

    def __init__(self, config: dict[str, Any]) -> None:
        self.config = config
        self.edges = EdgeDetector(False)
        self._lock = threading.RLock()
        self._stopped = False
        self.topic = proposition_topic(config)
        after = float(config.get("deadman", 0.0))
        self.deadman = StaleWatch(after, time.monotonic())
        self._heard = False  # the deadman is armed by the first message: before it the node is idle anyway
        self._diag = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=2) if after > 0 else None
        rospy.on_shutdown(self._on_shutdown)
        self._sub = rospy.Subscriber(self.topic, Bool, self._on_value, queue_size=10)
        self._deadman_timer = rospy.Timer(rospy.Duration(min(after / 5, 0.1)), self._check_deadman) \
            if after > 0 else None

    @property
    def active(self) -> bool:
        return self.edges.value

    # Hooks for subclasses.
    def on_rising(self) -> None:
        """Start the behaviour."""

    def while_true(self) -> None:
        """Act again while the proposition stays true."""

    def on_falling(self) -> None:
        """Stop the behaviour."""

    def on_shutdown(self) -> None:
        """Stop the behaviour because the node stops (rospy's client shutdown hook: topics and
        services still work here, and are closed right after)."""
        self.on_falling()

    def publishers(self) -> list[rospy.Publisher]:
        """The node's command publishers: on shutdown the node waits (at most 1 s) until what
        ``on_shutdown`` published on them has been sent (``wait_until_sent``)."""
        return []

    def _on_value(self, msg: Any) -> None:
        with self._lock:
            if self._stopped:
                return
            self._heard = True
            if self.deadman.seen(time.monotonic()):
                rospy.loginfo("%s: %s heard again: following the controller", rospy.get_name(), self.topic)
                self._deadman_status(DiagnosticStatus.OK, f"{self.topic} heard again: following the controller")
            edge = self.edges.update(msg.data)
            if edge == RISING:
                rospy.loginfo("%s: %s rose", rospy.get_name(), self.topic)
                self.on_rising()
            elif edge == FALLING:
                rospy.loginfo("%s: %s fell", rospy.get_name(), self.topic)
                self.on_falling()

    def _check_deadman(self, _event: Any) -> None:
        """No message for ``~deadman`` s: the safe state (the falling-edge behaviour), said once."""
        with self._lock:
            if self._stopped or not self._heard or not self.deadman.check(time.monotonic()):
                return
            text = (f"no message on {self.topic} for {self.deadman.after:g} s (the controller's heartbeat): "
                    f"{'stopping, ' if self.edges.value else ''}safe state until it returns")
            rospy.logwarn("%s: %s", rospy.get_name(), text)
            self._deadman_status(DiagnosticStatus.WARN, text)
            if self.edges.value:
                self.edges.update(False)
                self.on_falling()

    def _deadman_status(self, level: int, text: str) -> None:
        if self._diag is None:
            return
        name = rospy.get_name()
        status = DiagnosticStatus(level=level, name=f"{name}: deadman", message=text, hardware_id=name)
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        try:
            self._diag.publish(array)
        except rospy.ROSException:  # shutting down
            pass

    def _on_shutdown(self, _reason: str = "") -> None:
        with self._lock:
            if self.edges.value and not self._stopped:
                self.edges.update(False)
                self.on_shutdown()
                for pub in self.publishers():
                    if not wait_until_sent(pub):
                        rospy.logwarn("%s: the stop message on %s may not have been sent", rospy.get_name(),
                                      pub.resolved_name)
            self._stopped = True

    def spin(self) -> None:
        rate = rospy.Rate(self.config["rate"])
        while not rospy.is_shutdown():
            with self._lock:
                if self.edges.value and not self._stopped:
                    self.while_true()
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break


def run_node(spec: NodeSpec, build: Callable[[dict[str, Any]], Any],
             argv: Sequence[str] | None = None) -> None:
    """Entry point shared by the node scripts: CLI, ``init_node``, params, build, spin.

    A ``NodeConfigError`` (at start-up, or in ``spin`` once e.g. a topic's type is known) ends the node
    with one ``[FATAL]`` line naming the parameter and exit code ``Exit.BAD_INPUT``; a master that does
    not answer the start-up parameter read within ``ros.master.STARTUP_TIMEOUT`` s, with one line naming
    it and ``Exit.NO_ROS``. A ``MasterWatch`` registers the node again when the master restarts.
    """
    args = rospy.myargv(argv=list(sys.argv if argv is None else argv))
    parse_node_cli(spec.name, spec.kind, spec.description, spec.params, args[1:])
    node_argv, refused = split_param_args(list(sys.argv if argv is None else argv))
    try:
        init_node(spec.name, argv=node_argv, anonymous=False)
    except UserError as error:
        cli.error(spec.name, str(error))
        sys.exit(int(error.code))
    try:
        if refused:
            raise NodeConfigError(f"{rospy.get_name()}: {refused}")
        config = read_params(spec.params)
        node = build(config)
        MasterWatch()
        getattr(node, "spin", rospy.spin)()  # a node without a loop of its own (an action server) just spins
    except NodeConfigError as error:
        rospy.logfatal(str(error))
        rospy.signal_shutdown("bad parameters")
        sys.exit(int(EXIT_BAD_CONFIG))
    except UserError as error:  # the master did not answer a start-up read (ros.master.read_param)
        cli.error(spec.name, str(error))
        rospy.signal_shutdown("no master")
        sys.exit(int(error.code))
