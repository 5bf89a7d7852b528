"""Input proposition nodes: ``topic_threshold_sensor`` and ``region_sensor``.

``topic_threshold_sensor`` compares a numeric field of any message with a threshold (with optional
hysteresis); with ``_field:=data _comparison:='==' _threshold:=1`` on a ``std_msgs/Bool`` topic it
forwards a Boolean, like the thesis' ``forward_info_sensor``. ``region_sensor`` is true while the
robot's position lies inside a named polygon of an LTLMoP ``.regions`` file (the ``_rc`` inputs).

The field access, comparison and pose extraction are pure functions, tested without ROS.
"""
from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable
from typing import Any

from ltl_stack.ros.proposition_node import (
    INPUT_PARAMS,
    InputPropositionNode,
    NodeConfigError,
    NodeSpec,
    Param,
    message_class,
    run_node,
    wait_for_topic_class,
)
from ltl_stack.ros.regions import RegionMap, RegionsError, normalize_name

COMPARISONS: dict[str, Callable[[float, float], bool]] = {
    ">": operator.gt, ">=": operator.ge, "<": operator.lt, "<=": operator.le,
    "==": operator.eq, "!=": operator.ne,
    "gt": operator.gt, "ge": operator.ge, "lt": operator.lt, "le": operator.le,
    "eq": operator.eq, "ne": operator.ne,
}

_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)?((?:\[-?\d+\])*)$")


def parse_field_path(path: str) -> list[str | int]:
    """Split ``pose.position.x`` or ``ranges[3]`` or ``data`` into attribute names and indices."""
    steps: list[str | int] = []
    if not path.strip():
        raise ValueError("the field path is empty")
    for part in path.strip().split("."):
        match = _STEP.match(part)
        if not match or (not match.group(1) and not match.group(2)):
            raise ValueError(f"bad field path {path!r} at {part!r}")
        if match.group(1):
            steps.append(match.group(1))
        steps.extend(int(i) for i in re.findall(r"-?\d+", match.group(2)))
    return steps


def extract_field(msg: Any, steps: list[str | int]) -> Any:
    """Follow attribute names and indices into ``msg``; raise LookupError naming the missing step."""
    value = msg
    for step in steps:
        try:
            value = value[step] if isinstance(step, int) else getattr(value, step)
        except (AttributeError, IndexError, TypeError):
            raise LookupError(f"message has no field {step!r}") from None
    return value


class ThresholdComparator:
    """``value <op> threshold`` with hysteresis: once true, it turns false only past the threshold
    by ``hysteresis`` (and the other way round), so a noisy reading does not make it flicker."""

    def __init__(self, comparison: str, threshold: float, hysteresis: float = 0.0) -> None:
        if comparison not in COMPARISONS:
            raise ValueError(f"unknown comparison {comparison!r} (one of {' '.join(COMPARISONS)})")
        self.op = COMPARISONS[comparison]
        self.comparison = comparison
        self.threshold = float(threshold)
        self.hysteresis = abs(float(hysteresis))
        self.state: bool | None = None

    def update(self, value: float) -> bool:
        value = float(value)
        if math.isnan(value):
            return bool(self.state)
        if self.hysteresis == 0.0 or self.state is None or self.comparison in ("==", "!=", "eq", "ne"):
            self.state = self.op(value, self.threshold)
            return self.state
        # Moving the threshold away from the current state makes leaving it harder.
        larger = self.op(1.0, 0.0)  # true for > and >=
        shift = self.hysteresis if self.state != larger else -self.hysteresis
        self.state = self.op(value, self.threshold + shift)
        return self.state


THRESHOLD_SENSOR = NodeSpec(
    name="topic_threshold_sensor",
    kind="input",
    description="True while a numeric field of the messages on ~topic compares true with ~threshold.",
    params=[
        *INPUT_PARAMS,
        Param("topic", "", "topic to watch", aliases=("sensor_topic",), kind=str, required=True),
        Param("type", "", "its message type, e.g. sensor_msgs/Range (default: ask the master)",
              aliases=("topic_type",)),
        Param("field", "data", "field path in the message, e.g. range, pose.position.x, ranges[0]"),
        Param("comparison", ">", "one of > >= < <= == != (or gt ge lt le eq ne)"),
        Param("threshold", 0.0, "value compared with"),
        Param("hysteresis", 0.0, "margin past the threshold needed to switch back"),
    ],
)


class TopicThresholdSensor(InputPropositionNode):
    def __init__(self, config: dict[str, Any]) -> None:
        import rospy

        try:
            self.steps = parse_field_path(config["field"])
            self.comparator = ThresholdComparator(config["comparison"], config["threshold"],
                                                  config["hysteresis"])
        except ValueError as error:
            raise NodeConfigError(f"{rospy.get_name()}: {error}") from None
        self.cls = message_class(config["type"]) if config["type"] else None
        self._warned = False
        super().__init__(config)

    def spin(self) -> None:
        import rospy

        cls = self.cls or wait_for_topic_class(rospy.resolve_name(self.config["topic"]))
        if cls is None:
            return
        rospy.Subscriber(self.config["topic"], cls, self._on_msg, queue_size=10)
        super().spin()

    def _on_msg(self, msg: Any) -> None:
        import rospy

        try:
            value = extract_field(msg, self.steps)
            result = self.comparator.update(float(value))
        except (LookupError, TypeError, ValueError) as error:
            if not self._warned:
                rospy.logerr("%s: field %r of %s: %s", rospy.get_name(), self.config["field"],
                             self.config["topic"], error)
                self._warned = True
            return
        self.set_value(result)


def pose_xy(msg: Any) -> tuple[float, float]:
    """(x, y) of an Odometry, PoseStamped, PoseWithCovarianceStamped, Pose, Pose2D or Point."""
    for path in ("pose.pose.position", "pose.position", "position", ""):
        obj = msg
        try:
            for step in path.split(".") if path else []:
                obj = getattr(obj, step)
            return (float(obj.x), float(obj.y))
        except AttributeError:
            continue
    raise LookupError(f"cannot read a position from a {type(msg).__name__}")


REGION_SENSOR = NodeSpec(
    name="region_sensor",
    kind="input",
    description="True while the robot's position (from ~pose_topic) lies inside ~region of "
                "~regions_file (an LTLMoP .regions file), or, with ~robot_location_topic, while the "
                "region name published there is ~region.",
    params=[
        *INPUT_PARAMS,
        Param("regions_file", "", "LTLMoP .regions file (needed unless ~robot_location_topic is set)"),
        Param("region", "", "region name (rightLane also matches right_lane)",
              aliases=("region_in_consideration",), kind=str, required=True),
        Param("pose_topic", "odom", "robot position: Odometry, PoseStamped, Pose, Pose2D, ..."),
        Param("pose_type", "", "its message type (default: ask the master)"),
        Param("scale", 1.0, "metres per unit of the .regions file"),
        Param("x_trans", 0.0, "world x of the file's origin"),
        Param("y_trans", 0.0, "world y of the file's origin"),
        Param("flip_y", False, "negate the file's y (image coordinates point down)"),
        Param("robot_location_topic", "", "instead of a pose: a std_msgs/String topic carrying the name "
              "of the robot's current region (as sim_robot's current_region)"),
    ],
)


class RegionSensor(InputPropositionNode):
    def __init__(self, config: dict[str, Any]) -> None:
        import rospy

        self.region = None
        if config["robot_location_topic"]:
            super().__init__(config)
            return
        if not config["regions_file"]:
            raise NodeConfigError(f"{rospy.get_name()}: set ~regions_file (or ~robot_location_topic)")
        try:
            regions = RegionMap.load(config["regions_file"], scale=config["scale"],
                                     x_trans=config["x_trans"], y_trans=config["y_trans"],
                                     flip_y=config["flip_y"])
            self.region = regions.find(config["region"])
        except RegionsError as error:
            raise NodeConfigError(f"{rospy.get_name()}: {error}") from None
        self.cls = message_class(config["pose_type"]) if config["pose_type"] else None
        super().__init__(config)

    def spin(self) -> None:
        import rospy
        from std_msgs.msg import String

        if self.region is None:
            rospy.Subscriber(self.config["robot_location_topic"], String, self._on_region_name, queue_size=10)
            super().spin()
            return
        cls = self.cls or wait_for_topic_class(rospy.resolve_name(self.config["pose_topic"]))
        if cls is None:
            return
        rospy.Subscriber(self.config["pose_topic"], cls, self._on_pose, queue_size=10)
        super().spin()

    def _on_region_name(self, msg: Any) -> None:
        self.set_value(normalize_name(msg.data) == normalize_name(self.config["region"]))

    def _on_pose(self, msg: Any) -> None:
        x, y = pose_xy(msg)
        self.set_value(self.region.contains(x, y))


def threshold_sensor_main() -> None:
    run_node(THRESHOLD_SENSOR, TopicThresholdSensor)


def region_sensor_main() -> None:
    run_node(REGION_SENSOR, RegionSensor)
