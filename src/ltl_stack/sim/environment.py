"""``scripted_environment``: raise sensor events on a schedule read from YAML (see ``schedule.py``).

Each event publishes one message, latched, on its topic: a person shows up, an object appears, a
door closes. Sensor proposition nodes (or the controller's inputs directly) listen to these topics,
so a scenario or a test sees the same environment every time. The name of each event is also
published on ``~fired`` (std_msgs/String) when it fires. Events with ``when:`` wait for a message
on a topic the node subscribes to (the robot's second time in a region, say).
"""
from __future__ import annotations

import threading
import time
from typing import Any

from ltl_stack.ros.proposition_node import (
    NodeConfigError,
    NodeSpec,
    Param,
    fill_message,
    message_class,
    run_node,
)
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.sim.schedule import ScheduleError, Scheduler, load_schedule

SCRIPTED_ENVIRONMENT = NodeSpec(
    name="scripted_environment",
    kind="sim",
    description="Publish scripted sensor events (latched) at the times a YAML schedule gives.",
    params=[
        Param("schedule", "", "YAML schedule file (events: [{at, topic, value, type, name}])",
              aliases=("file",), kind=str, required=True),
        Param("time_scale", 1.0, "simulated seconds per wall-clock second", bound=Bound.POSITIVE),
        Param("wait_for_subscribers", 0.0, "wait up to this long (s) for every topic to have a "
              "subscriber before the clock starts (0: start at once)", bound=Bound.NON_NEGATIVE),
        Param("rate", 50.0, "how often (Hz) to check for due events", bound=Bound.RATE),
        Param("start_on", "", "start the clock once each of these topics (space-separated, relative to the "
              "node's namespace) has had a message; a controller's ~state (ltl_stack/ControllerState) counts "
              "once the controller has started (state_id >= 0: every input reported), so a controller on "
              "another host that starts later misses no event; empty: do not wait", kind=str),
    ],
)


class ScriptedEnvironment:
    def __init__(self, config: dict[str, Any]) -> None:
        import rospy
        from std_msgs.msg import String

        name = rospy.get_name()
        try:
            self.schedule = load_schedule(config["schedule"])
        except ScheduleError as error:
            raise NodeConfigError(f"{name}: {error}") from None
        self.config = config
        self.publishers = {}
        for topic, type_name in self.schedule.topics().items():
            try:
                cls = message_class(type_name)
            except NodeConfigError as error:
                raise NodeConfigError(f"{name}: {self.schedule.source}: topic {topic}: {error}") from None
            self.publishers[topic] = (rospy.Publisher(topic, cls, queue_size=10, latch=True), cls)
        self.messages = {}
        for event in self.schedule.events:
            cls = self.publishers[event.topic][1]
            try:
                self.messages[id(event)] = fill_message(cls, event.fields, "value")
            except NodeConfigError as error:
                raise NodeConfigError(f"{name}: {self.schedule.source}:{event.line}: {error}") from None
        self.fired_pub = rospy.Publisher("~fired", String, queue_size=100, latch=True)
        self._string = String
        self.scheduler = Scheduler(self.schedule)
        self._lock = threading.Lock()
        self._start: float | None = None
        self._subscribers = []
        for trigger in self.schedule.triggers():
            try:
                cls = message_class(trigger.type)
                fill_message(cls, trigger.fields, "when: value")  # names a field the message lacks?
            except NodeConfigError as error:
                raise NodeConfigError(f"{name}: {self.schedule.source}: 'when' topic {trigger.topic}: "
                                      f"{error}") from None
            if not any(s.resolved_name == rospy.resolve_name(trigger.topic) for s in self._subscribers):
                self._subscribers.append(rospy.Subscriber(trigger.topic, cls, self._on_message,
                                                          callback_args=trigger.topic, queue_size=100))

    def _elapsed(self) -> float:
        """Schedule seconds since the clock started (0 before)."""
        if self._start is None:
            return 0.0
        return (time.monotonic() - self._start) * self.config["time_scale"]

    def _on_message(self, message: Any, topic: str) -> None:
        import rospy

        with self._lock:
            for trigger in self.scheduler.observe(topic, message, self._elapsed()):
                rospy.loginfo("%s: %s changed to %s (time %d): 'when' events start", rospy.get_name(),
                              trigger.topic, trigger.fields, trigger.count)

    def _wait_for_subscribers(self) -> None:
        import rospy

        deadline = time.monotonic() + self.config["wait_for_subscribers"]
        while not rospy.is_shutdown() and time.monotonic() < deadline:
            if all(pub.get_num_connections() > 0 for pub, _ in self.publishers.values()):
                return
            rospy.sleep(0.05)
        missing = [t for t, (pub, _) in self.publishers.items() if pub.get_num_connections() == 0]
        if missing:
            rospy.logwarn("%s: starting although nobody listens to %s", rospy.get_name(), ", ".join(missing))

    def _wait_for_start_messages(self, topics: list[str]) -> None:
        """Return once every topic of ``topics`` has had a message that starts the clock
        (``starts_clock``), or on shutdown."""
        import rospy

        names = [rospy.resolve_name(t) for t in topics]
        waiting = set(names)
        told: set[str] = set()
        cond = threading.Condition()

        def heard(msg: Any, name: str) -> None:
            with cond:
                if name not in waiting:
                    return
                if not starts_clock(msg):
                    if name not in told:  # once per topic
                        told.add(name)
                        rospy.loginfo("%s: %s: the controller has not started yet (waiting for every input to "
                                      "report); the clock waits", rospy.get_name(), name)
                    return
                waiting.discard(name)
                cond.notify_all()

        rospy.loginfo("%s: waiting for the first message on %s to start the clock", rospy.get_name(),
                      ", ".join(names))
        subscribers = [rospy.Subscriber(n, rospy.AnyMsg, heard, callback_args=n, queue_size=10) for n in names]
        with cond:
            while waiting and not rospy.is_shutdown():
                cond.wait(0.5)
        for sub in subscribers:
            sub.unregister()

    def spin(self) -> None:
        import rospy

        if self.config["wait_for_subscribers"] > 0:
            self._wait_for_subscribers()
        if self.config["start_on"].split():
            self._wait_for_start_messages(self.config["start_on"].split())
        with self._lock:
            self._start = time.monotonic()
        rate = rospy.Rate(self.config["rate"])
        rospy.loginfo("%s: playing %d events from %s", rospy.get_name(), len(self.schedule.events),
                      self.schedule.source)
        while not rospy.is_shutdown():
            with self._lock:
                elapsed = self._elapsed()
                due = self.scheduler.due(elapsed)
            for event in due:
                self.publishers[event.topic][0].publish(self.messages[id(event)])
                self.fired_pub.publish(self._string(data=event.name))
                rospy.loginfo("%s: t=%.2f %s", rospy.get_name(), elapsed, event.name)
            with self._lock:
                finished = self.scheduler.finished()
            if finished:
                rospy.loginfo("%s: schedule done; keeping the latched topics up", rospy.get_name())
                rospy.spin()
                return
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                return


def starts_clock(msg: Any) -> bool:
    """Whether a message (``rospy.AnyMsg``) on a ``start_on`` topic starts the clock: any message,
    except a controller's ``~state`` before its controller has started (``state_id`` < 0)."""
    header = getattr(msg, "_connection_header", None) or {}
    if header.get("type") != "ltl_stack/ControllerState":
        return True
    from ltl_stack.msg import ControllerState

    state = ControllerState()
    try:
        state.deserialize(msg._buff)
    except Exception:  # noqa: BLE001 - another version of the message: do not hold the clock for it
        return True
    return state.state_id >= 0


def scripted_environment_main() -> None:
    run_node(SCRIPTED_ENVIRONMENT, ScriptedEnvironment)
