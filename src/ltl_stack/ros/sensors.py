"""Input proposition nodes: ``topic_threshold_sensor`` and ``region_sensor``.

``topic_threshold_sensor`` compares a numeric field of any message with a threshold (with optional
hysteresis); with ``_field:=data _comparison:='==' _threshold:=1`` on a ``std_msgs/Bool`` topic it
forwards a Boolean, like the thesis' ``forward_info_sensor``. ``region_sensor`` is true while the
robot's position lies inside a named polygon of an LTLMoP ``.regions`` file (the ``_rc`` inputs).

The field access, comparison and pose extraction are ROS-free (``ltl_stack.runtime.propositions.sensing``).
"""
from __future__ import annotations

import math
from typing import Any

import rospy
from std_msgs.msg import String

from ltl_stack.ros.proposition_node import (
    INPUT_PARAMS,
    InputPropositionNode,
    NodeConfigError,
    NodeSpec,
    Param,
    TopicMessageSensor,
    message_class,
    run_node,
    wait_for_topic_class,
)
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError, normalize_name
from ltl_stack.runtime.propositions.sensing import (
    COMPARISONS,
    ThresholdComparator,
    check_field_path,
    extract_field,
    parse_field_path,
    pose_xy,
)

THRESHOLD_SENSOR = NodeSpec(
    name="topic_threshold_sensor",
    kind="input",
    description="True while a numeric field of the messages on ~topic compares true with ~threshold.",
    params=[
        *INPUT_PARAMS,
        Param("topic", "", "topic to watch", aliases=("sensor_topic",), kind=str, required=True, ros_name=True),
        Param("type", "", "its message type, e.g. sensor_msgs/Range (default: ask the master)",
              aliases=("topic_type",)),
        Param("field", "data", "field path in the message, e.g. range, pose.position.x, ranges[0]"),
        Param("comparison", ">", "one of > >= < <= == != (or gt ge lt le eq ne)", choices=tuple(COMPARISONS)),
        Param("threshold", 0.0, "value compared with"),
        Param("hysteresis", 0.0, "margin past the threshold needed to switch back", bound=Bound.NON_NEGATIVE),
    ],
)


class TopicThresholdSensor(TopicMessageSensor):
    def __init__(self, config: dict[str, Any]) -> None:
        self.field = config["field"]
        try:
            self.steps = parse_field_path(self.field)
            self.comparator = ThresholdComparator(config["comparison"], config["threshold"],
                                                  config["hysteresis"])
        except ValueError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~field: {error}") from None
        super().__init__(config)

    def check(self, cls: type) -> None:
        try:
            check_field_path(cls(), self.steps, cls._type)
        except LookupError as error:
            raise NodeConfigError(f"{rospy.get_name()}: parameter ~field {self.field!r}: {error}") from None

    def value(self, msg: Any) -> bool:
        reading = float(extract_field(msg, self.steps))
        if math.isnan(reading):  # not a reading: the proposition takes ~stale_value, not the last value
            raise ValueError("the field is NaN")
        return self.comparator.update(reading)

    def what(self) -> str:
        return f"field {self.config['field']!r} of {self.config['topic']}"


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
        Param("pose_topic", "odom", "robot position: Odometry, PoseStamped, Pose, Pose2D, ...", ros_name=True),
        Param("pose_type", "", "its message type (default: ask the master)"),
        Param("scale", 1.0, "metres per unit of the .regions file", bound=Bound.POSITIVE),
        Param("x_trans", 0.0, "world x of the file's origin"),
        Param("y_trans", 0.0, "world y of the file's origin"),
        Param("flip_y", False, "negate the file's y (image coordinates point down)"),
        Param("robot_location_topic", "", "instead of a pose: a std_msgs/String topic carrying the name "
              "of the robot's current region (as sim_robot's current_region)", ros_name=True),
    ],
)


class RegionSensor(InputPropositionNode):
    def __init__(self, config: dict[str, Any]) -> None:
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
            self.regions = regions
        except RegionsError as error:
            raise NodeConfigError(f"{rospy.get_name()}: {error}") from None
        for warning in regions.warnings:
            rospy.logwarn("%s: %s", rospy.get_name(), warning)
        self.cls = message_class(config["pose_type"]) if config["pose_type"] else None
        super().__init__(config)

    def spin(self) -> None:
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
        inside = self.region.contains(x, y)
        if inside and self.region.name in self.regions.names() and self.region.name not in self.regions.obstacles:
            # in a region nested in this one the robot is in the nested one (as every map reader says)
            inside = self.regions.region_at(x, y) == self.region.name
        self.set_value(inside)


def threshold_sensor_main() -> None:
    run_node(THRESHOLD_SENSOR, TopicThresholdSensor)


def region_sensor_main() -> None:
    run_node(REGION_SENSOR, RegionSensor)


__all__ = ["REGION_SENSOR", "THRESHOLD_SENSOR", "RegionSensor", "TopicThresholdSensor", "region_sensor_main",
           "threshold_sensor_main"]
