"""Bases for proposition nodes: the ROS programs a proposition topic is mapped to (thesis 3.5.1).

An *input proposition node* turns sensing into a ``std_msgs/Bool`` that it publishes on the input
proposition topic, at a steady rate and at once on every change. An *output proposition node*
subscribes to an output proposition topic and reacts to its edges: it starts its behaviour on the
rising edge, may act periodically while the value is true, stops on the falling edge, and does
nothing while false. On shutdown it drives its behaviour off.

The proposition topic comes from the ``~proposition_topic`` parameter, or else from the relative
name ``proposition`` (remap it: ``proposition:=/ns/outputs/move``).

``EdgeDetector``, ``StaleWatch``, ``Param`` and ``coerce_param`` are ROS-free, and ``rospy`` is
imported only inside the ROS parts, so this module imports (and is unit-tested) without a master.
"""
from __future__ import annotations

import argparse
import json
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

RISING = "rising"
FALLING = "falling"

#: Exit code of a node whose parameters are wrong (missing file, bad value, unknown type).
EXIT_BAD_CONFIG = 2


class NodeConfigError(Exception):
    """A parameter of a proposition node is missing or wrong; the message names it."""


class EdgeDetector:
    """Turns a stream of Booleans into rising/falling edges. The value starts false."""

    def __init__(self, initial: bool = False) -> None:
        self.value = bool(initial)

    def update(self, value: bool) -> str | None:
        """Record ``value``; return RISING, FALLING or None when it did not change."""
        value = bool(value)
        if value == self.value:
            return None
        self.value = value
        return RISING if value else FALLING


class StaleWatch:
    """Tells when sensing has not arrived for ``after`` seconds (times are passed in, so the logic
    runs without ROS). ``after <= 0`` disables it: nothing is ever stale."""

    def __init__(self, after: float, now: float) -> None:
        self.after = float(after)
        self._last = now
        self.stale = False
        self._lock = threading.Lock()

    def seen(self, now: float) -> bool:
        """Record fresh sensing; return whether it ends a stale period."""
        with self._lock:
            self._last = now
            ended, self.stale = self.stale, False
        return ended

    def check(self, now: float) -> bool:
        """Return True exactly once when the sensing becomes stale."""
        with self._lock:
            if self.after <= 0 or self.stale or now - self._last < self.after:
                return False
            self.stale = True
            return True


@dataclass(frozen=True)
class Param:
    """One ``~private`` parameter of a node: its name, default, meaning and legacy aliases.

    ``kind`` is the expected type (float, int, str, bool, list, dict); it defaults to the type of
    ``default``. ``required`` parameters have no default.
    """

    name: str
    default: Any = None
    doc: str = ""
    aliases: tuple[str, ...] = ()
    kind: type | None = None
    required: bool = False

    @property
    def type(self) -> type | None:
        if self.kind is not None:
            return self.kind
        return None if self.default is None else type(self.default)


def coerce_param(param: Param, value: Any, node: str = "") -> Any:
    """Convert a parameter value to ``param.type``; raise NodeConfigError naming it otherwise."""
    want = param.type
    where = f"{node}: " if node else ""
    if want is None or value is None:
        return value
    if want is bool:
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in ("true", "false", "1", "0", "yes", "no"):
            return value.strip().lower() in ("true", "1", "yes")
        if isinstance(value, int):
            return bool(value)
    elif want in (float, int):
        if isinstance(value, bool):
            raise NodeConfigError(f"{where}parameter ~{param.name} must be a number, got {value!r}")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise NodeConfigError(
                f"{where}parameter ~{param.name} must be a number, got {value!r}") from None
        if want is int:
            if number != int(number):
                raise NodeConfigError(f"{where}parameter ~{param.name} must be an integer, got {value!r}")
            return int(number)
        return number
    elif want is str:
        if isinstance(value, (str, int, float)) and not isinstance(value, bool):
            return str(value)
    elif want is list:
        if isinstance(value, (list, tuple)):
            return list(value)
        if isinstance(value, str):
            return value.split()
    elif want is dict:
        if isinstance(value, dict):
            return value
    raise NodeConfigError(f"{where}parameter ~{param.name} must be a {want.__name__}, got {value!r}")


def describe_params(kind: str, description: str, params: Sequence[Param]) -> dict:
    """The machine-readable description of a node (what ``--json`` prints)."""
    return {
        "kind": kind,
        "description": description,
        "params": [
            {"name": p.name, "default": p.default, "required": p.required,
             "aliases": list(p.aliases), "doc": p.doc}
            for p in params
        ],
    }


def parse_node_cli(prog: str, kind: str, description: str, params: Sequence[Param],
                   argv: Sequence[str]) -> None:
    """Handle ``--help`` and ``--json`` of a node script; return to let the node run otherwise.

    ``argv`` must already be stripped of ROS remappings (``rospy.myargv``).
    """
    lines = [f"  _{p.name}:=<{p.type.__name__ if p.type else 'value'}>"
             f"{'  (required)' if p.required else f'  (default {p.default!r})'}"
             f"{'  aliases: ' + ', '.join(p.aliases) if p.aliases else ''}\n      {p.doc}"
             for p in params]
    epilog = ("private parameters (set as _name:=value, or from a launch file / mapping):\n"
              + "\n".join(lines)
              + f"\n\nexit codes: 0 shut down normally, {EXIT_BAD_CONFIG} bad parameters")
    parser = argparse.ArgumentParser(prog=prog, description=description, epilog=epilog,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", action="store_true",
                        help="print this node's kind and parameters as JSON and exit")
    args = parser.parse_args(list(argv))
    if args.json:
        print(json.dumps(describe_params(kind, description, params), indent=2))
        sys.exit(0)


# --------------------------------------------------------------------------------------------------
# ROS part. rospy is imported inside functions so the module imports without ROS.
# --------------------------------------------------------------------------------------------------

def read_params(params: Sequence[Param], node: str = "") -> dict[str, Any]:
    """Read each ``~name`` (or the first alias that is set), coerced to its type."""
    import rospy

    values: dict[str, Any] = {}
    for p in params:
        value = None
        found = False
        for name in (p.name, *p.aliases):
            if rospy.has_param("~" + name):
                value = rospy.get_param("~" + name)
                found = True
                break
        if not found:
            if p.required:
                raise NodeConfigError(f"{node or rospy.get_name()}: parameter ~{p.name} is required")
            value = p.default
        values[p.name] = coerce_param(p, value, node or rospy.get_name())
    return values


def proposition_topic(default: str = "proposition") -> str:
    """The proposition topic: ``~proposition_topic`` if set, else the (remappable) relative name."""
    import rospy

    name = rospy.get_param("~proposition_topic", "") or default
    return rospy.resolve_name(str(name))


def message_class(type_name: str, what: str = "message") -> type:
    """The Python class of a message type given as ``pkg/Type`` or ``pkg.msg.Type``."""
    import roslib.message

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
    import genpy

    msg = cls()
    try:
        genpy.message.fill_message_args(msg, [fields])
    except (genpy.MessageException, ValueError, TypeError, KeyError, AttributeError) as error:
        raise NodeConfigError(f"{what} {fields!r} does not fit {cls._type}: {error}") from None
    return msg


def wait_for_topic_class(topic: str, poll: float = 0.2) -> type | None:
    """Block until ``topic`` is advertised and return its message class (None on shutdown)."""
    import rospy
    import rostopic

    while not rospy.is_shutdown():
        try:
            cls, _, _ = rostopic.get_topic_class(topic, blocking=False)
        except rostopic.ROSTopicException:
            cls = None
        if cls is not None:
            return cls
        rospy.sleep(poll)
    return None


class PropositionPublisher:
    """Publishes one Boolean proposition: latched, at once on change, and again every 1/rate s."""

    def __init__(self, topic: str, rate: float = 10.0, initial: bool | None = False) -> None:
        import rospy
        from std_msgs.msg import Bool

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
        with self._lock:
            if self._value is not None:
                self._pub.publish(self._bool(data=self._value))

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
    Param("proposition_topic", "", "topic of the input proposition (default: relative name 'proposition')"),
    Param("rate", 10.0, "republish the Boolean this often (Hz); it is also published at once on change"),
    Param("init_value", False, "value published before the first sensing arrives"),
    Param("stale_after", 0.0, "seconds without sensing after which ~stale_value is published "
          "until sensing resumes (0: never)"),
    Param("stale_value", False, "value published while the sensing is stale"),
]

#: Parameters every output node reads.
OUTPUT_PARAMS = [
    Param("proposition_topic", "", "topic of the output proposition (default: relative name 'proposition')"),
    Param("rate", 10.0, "how often (Hz) the behaviour acts while the proposition is true"),
]


class InputPropositionNode:
    """Base of input proposition nodes: subclasses call ``self.set_value(bool)`` from sensing."""

    def __init__(self, config: dict[str, Any]) -> None:
        import rospy

        self.config = config
        self.output = PropositionPublisher(proposition_topic(), rate=config["rate"],
                                           initial=config["init_value"])
        after = float(config.get("stale_after", 0.0))
        if after < 0:
            raise NodeConfigError(f"{rospy.get_name()}: ~stale_after must be >= 0 (got {after})")
        self.stale = StaleWatch(after, time.monotonic())
        self._sensing_lock = threading.Lock()  # a stale value never overwrites fresh sensing
        self._stale_timer = rospy.Timer(rospy.Duration(min(after / 4, 0.1)), self._check_stale) \
            if after > 0 else None

    def set_value(self, value: bool) -> None:
        """Publish the sensed value (and end a stale period)."""
        import rospy

        with self._sensing_lock:
            if self.stale.seen(time.monotonic()):
                rospy.loginfo("%s: sensing resumed", rospy.get_name())
            if self.output.set(value):
                rospy.logdebug("%s: %s -> %s", rospy.get_name(), self.output.topic, bool(value))

    def _check_stale(self, _event: Any) -> None:
        import rospy

        with self._sensing_lock:
            if self.stale.check(time.monotonic()):
                value = bool(self.config["stale_value"])
                rospy.logwarn("%s: no sensing for %.2f s: publishing %s on %s until it resumes",
                              rospy.get_name(), self.stale.after, value, self.output.topic)
                self.output.set(value)

    def spin(self) -> None:
        import rospy

        rospy.spin()
        if self._stale_timer is not None:
            self._stale_timer.shutdown()
        self.output.close()


class OutputPropositionNode:
    """Base of output proposition nodes.

    Subclasses override ``on_rising`` (start the behaviour), ``while_true`` (called every 1/rate s
    while the proposition is true, after the rising edge) and ``on_falling`` (stop the behaviour;
    also called on shutdown while active). The hooks run under one lock, so they never overlap.
    """

    def __init__(self, config: dict[str, Any]) -> None:
        import rospy
        from std_msgs.msg import Bool

        self.config = config
        self.edges = EdgeDetector(False)
        self._lock = threading.RLock()
        self._stopped = False
        self.topic = proposition_topic()
        rospy.on_shutdown(self._on_shutdown)
        self._sub = rospy.Subscriber(self.topic, Bool, self._on_value, queue_size=10)

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

    def _on_value(self, msg: Any) -> None:
        import rospy

        with self._lock:
            if self._stopped:
                return
            edge = self.edges.update(msg.data)
            if edge == RISING:
                rospy.loginfo("%s: %s rose", rospy.get_name(), self.topic)
                self.on_rising()
            elif edge == FALLING:
                rospy.loginfo("%s: %s fell", rospy.get_name(), self.topic)
                self.on_falling()

    def _on_shutdown(self, _reason: str = "") -> None:
        with self._lock:
            if self.edges.value and not self._stopped:
                self.edges.update(False)
                self.on_falling()
            self._stopped = True

    def spin(self) -> None:
        import rospy

        rate = rospy.Rate(self.config["rate"]) if self.config["rate"] > 0 else None
        while not rospy.is_shutdown():
            with self._lock:
                if self.edges.value and not self._stopped:
                    self.while_true()
            try:
                if rate is not None:
                    rate.sleep()
                else:
                    rospy.sleep(0.1)
            except rospy.ROSInterruptException:
                break


def run_node(spec: NodeSpec, build: Callable[[dict[str, Any]], Any],
             argv: Sequence[str] | None = None) -> None:
    """Entry point shared by the node scripts: CLI, ``init_node``, params, build, spin.

    A ``NodeConfigError`` ends the node with one ``logfatal`` line and exit code 2.
    """
    import rospy

    args = rospy.myargv(argv=list(sys.argv if argv is None else argv))
    parse_node_cli(spec.name, spec.kind, spec.description, spec.params, args[1:])
    rospy.init_node(spec.name, anonymous=False)
    try:
        config = read_params(spec.params)
        node = build(config)
    except NodeConfigError as error:
        rospy.logfatal(str(error))
        rospy.signal_shutdown("bad parameters")
        sys.exit(EXIT_BAD_CONFIG)
    node.spin()
