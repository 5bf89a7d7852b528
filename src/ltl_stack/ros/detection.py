"""``topic_predicate_sensor``: an input proposition true while a message meets conditions.

For detections: "tag 7 closer than 1.5 m" on an AprilTag-style array is
``_type:=ltl_stack/TagDetectionArray _array:=detections _conditions:="['id == 7', 'pose.position within 1.5']"``.
The conditions and their evaluation are ROS-free (``ltl_stack.runtime.propositions.predicate``); here the fields are
checked against the message definition at start-up (or once the master reports the topic's type):\na field the type lacks, ``within`` on a Pose or ``contains`` on a number is one [FATAL] line naming the\nfield and its type, exit 2.
"""
from __future__ import annotations

from collections.abc import Sequence
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
from ltl_stack.runtime.propositions import predicate
from ltl_stack.runtime.propositions.predicate import OPS, MessagePredicate
from ltl_stack.runtime.propositions.sensing import field_path_text as _path

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


def message_fields(type_name: str) -> dict[str, str] | None:
    """The field types of message type ``type_name`` by field name (None for a primitive or array)."""
    if type_name.endswith("]") or "/" not in type_name and type_name != "Header":
        return None
    cls = roslib.message.get_message_class("std_msgs/Header" if type_name == "Header" else type_name)
    if cls is None:
        raise LookupError(f"unknown message type {type_name}")
    return {name: cls._slot_types[i] for i, name in enumerate(cls.__slots__)}


def field_type(type_name: str, steps: Sequence[str | int]) -> str:
    """The ROS type of the field ``steps`` of message type ``type_name`` (``int32``, ``float64[]``,
    ``geometry_msgs/Point``); LookupError naming the first step the definition lacks."""
    current = type_name
    for position, step in enumerate(steps):
        here = _path(list(steps[:position + 1]))
        if isinstance(step, int):
            if not predicate.is_array(current):
                raise LookupError(f"{type_name} field {_path(list(steps[:position]))} is a {current}, not an array")
            current = predicate.element_type(current)
            continue
        fields = message_fields(current)
        if fields is None or step not in fields:
            known = ", ".join(fields or ()) or "none"
            raise LookupError(f"{type_name} has no field {here} (fields there: {known})")
        current = fields[step]
    return current


class TopicPredicateSensor(TopicMessageSensor):
    def __init__(self, config: dict[str, Any]) -> None:
        try:
            self.predicate = MessagePredicate([str(c) for c in config["conditions"]], config["array"])
        except ValueError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~conditions: {error}") from None
        super().__init__(config)

    def check(self, cls: type) -> None:
        """Every condition against the message definition: its field exists and has a type its
        operator can read (one error naming the field and its type)."""
        try:
            element = cls._type
            if self.predicate.array:
                array = field_type(cls._type, self.predicate.array)
                if not predicate.is_array(array):
                    raise LookupError(f"{cls._type} field {_path(list(self.predicate.array))} is a {array}, not an array")
                element = predicate.element_type(array)
            for condition in self.predicate.conditions:
                found = field_type(element, condition.steps)
                error = condition.type_error(found, message_fields(found))
                if error:
                    raise LookupError(f"{element}: {error}")
        except LookupError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~array/~conditions: {error}") from None

    def value(self, msg: Any) -> bool:
        return self.predicate.evaluate(msg)


def topic_predicate_sensor_main() -> None:
    run_node(TOPIC_PREDICATE_SENSOR, TopicPredicateSensor)
