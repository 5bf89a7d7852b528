"""``topic_predicate_sensor``: an input proposition true while a message meets conditions.

For detections: "tag 7 closer than 1.5 m" on an AprilTag-style array is
``_type:=ltl_stack/TagDetectionArray _array:=detections _conditions:="['id == 7', 'pose.position within 1.5']"``.
The conditions and their evaluation are ROS-free (``ltl_stack.runtime.predicate``); here the fields are
checked against the message type at start-up (or once the master reports the topic's type).
"""
from __future__ import annotations

from typing import Any

import roslib.message
import rospy

from ltl_stack.ros.proposition_node import (
    INPUT_PARAMS,
    NodeConfigError,
    NodeSpec,
    Param,
    TopicMessageSensor,
    run_node,
)
from ltl_stack.runtime.predicate import OPS, MessagePredicate

TOPIC_PREDICATE_SENSOR = NodeSpec(
    name="topic_predicate_sensor",
    kind="input",
    description="True while a message on ~topic (or an element of its array ~array) meets every one of "
                "~conditions, e.g. a tag id within a distance.",
    params=[
        *INPUT_PARAMS,
        Param("topic", "", "topic to watch", kind=str, required=True, ros_name=True),
        Param("type", "", "its message type, e.g. ltl_stack/TagDetectionArray (default: ask the master)"),
        Param("array", "", "field holding the elements to test, e.g. detections (empty: the message)"),
        Param("conditions", [], "list of '<field> <op> <value>', op one of " + " ".join(OPS)
              + ", e.g. ['id == 7', 'pose.position within 1.5']", kind=list, required=True),
    ],
)


def element_class(cls: type, steps: tuple) -> type | None:
    """The class of the elements of the array field ``steps`` of message class ``cls`` (None when the
    path holds an index and the class cannot be told); LookupError naming a missing field."""
    current = cls
    for position, step in enumerate(steps):
        if isinstance(step, int):
            return None
        slots = list(getattr(current, "__slots__", ()))
        if step not in slots:
            raise LookupError(f"{cls._type} has no field {'.'.join(map(str, steps[:position + 1]))} "
                              f"(fields there: {', '.join(slots) or 'none'})")
        slot_type = current._slot_types[slots.index(step)]
        base = slot_type.split("[", 1)[0]
        if position == len(steps) - 1:
            if "[" not in slot_type:
                raise LookupError(f"{cls._type} field {'.'.join(map(str, steps))} is not an array")
            return roslib.message.get_message_class(base) if "/" in base else None
        current = roslib.message.get_message_class(base if "/" in base else "std_msgs/Header")
    return current


def check_fields(sample: Any, steps: tuple, type_name: str) -> None:
    """LookupError naming the first named field of ``steps`` that ``sample`` lacks."""
    value = sample
    for position, step in enumerate(steps):
        if isinstance(step, int):
            return
        slots = getattr(value, "__slots__", None)
        if slots is not None and step not in slots:
            raise LookupError(f"{type_name} has no field {'.'.join(map(str, steps[:position + 1]))} "
                              f"(fields there: {', '.join(slots)})")
        value = getattr(value, step)


class TopicPredicateSensor(TopicMessageSensor):
    def __init__(self, config: dict[str, Any]) -> None:
        try:
            self.predicate = MessagePredicate([str(c) for c in config["conditions"]], config["array"])
        except ValueError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~conditions: {error}") from None
        super().__init__(config)

    def check(self, cls: type) -> None:
        try:
            element = element_class(cls, self.predicate.array) if self.predicate.array else cls
            if element is not None:
                for condition in self.predicate.conditions:
                    check_fields(element(), condition.steps, element._type)
        except LookupError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~array/~conditions: {error}") from None

    def value(self, msg: Any) -> bool:
        return self.predicate.evaluate(msg)


def topic_predicate_sensor_main() -> None:
    run_node(TOPIC_PREDICATE_SENSOR, TopicPredicateSensor)
