"""Output proposition nodes that command a robot directly: ``set_velocity``, ``set_color`` and the
generic ``publish_on_edge`` (any message on the rising/falling edge; a dummy actuator without a topic).

Their parameters keep the names of the thesis' mappings (``publish_topic``, ``vx`` .. ``az``,
``r``/``g``/``b``), so a mapping written for the original stack names them unchanged.
"""
from __future__ import annotations

from typing import Any

import rospy
from geometry_msgs.msg import Twist, Vector3
from std_msgs.msg import ColorRGBA

from ltl_stack.ros.proposition_node import (
    OUTPUT_PARAMS,
    NodeSpec,
    OutputPropositionNode,
    Param,
    fill_message,
    message_class,
    run_node,
)

SET_VELOCITY = NodeSpec(
    name="set_velocity",
    kind="output",
    description="While the proposition is true, publish a constant Twist at ~rate; "
                "publish one zero Twist on the falling edge and on shutdown.",
    params=[
        *OUTPUT_PARAMS,
        Param("topic", "cmd_vel", "velocity command topic (geometry_msgs/Twist)", aliases=("publish_topic",),
              required=True, ros_name=True),
        Param("vx", 0.0, "linear x velocity (m/s)"),
        Param("vy", 0.0, "linear y velocity (m/s)"),
        Param("vz", 0.0, "linear z velocity (m/s)"),
        Param("ax", 0.0, "angular x velocity (rad/s)"),
        Param("ay", 0.0, "angular y velocity (rad/s)"),
        Param("az", 0.0, "angular z velocity (rad/s)"),
    ],
)


def twist_values(config: dict[str, Any]) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The (linear, angular) velocity triples that ``config`` asks for."""
    return ((config["vx"], config["vy"], config["vz"]), (config["ax"], config["ay"], config["az"]))


class SetVelocity(OutputPropositionNode):
    """Publish a constant Twist while true; one zero Twist when the proposition falls."""

    def __init__(self, config: dict[str, Any]) -> None:
        linear, angular = twist_values(config)
        self.command = Twist(linear=Vector3(*linear), angular=Vector3(*angular))
        self.zero = Twist()
        self.pub = rospy.Publisher(config["topic"], Twist, queue_size=10)
        super().__init__(config)

    def on_rising(self) -> None:
        self.pub.publish(self.command)

    def while_true(self) -> None:
        self.pub.publish(self.command)

    def on_falling(self) -> None:
        self.pub.publish(self.zero)

    def publishers(self) -> list[rospy.Publisher]:
        return [self.pub]


SET_COLOR = NodeSpec(
    name="set_color",
    kind="output",
    description="On the rising edge publish a colour (std_msgs/ColorRGBA, latched), e.g. a Sphero's LED; "
                "optionally publish black on the falling edge.",
    params=[
        *OUTPUT_PARAMS,
        Param("topic", "set_color", "colour topic (std_msgs/ColorRGBA)", aliases=("publish_topic",),
              required=True, ros_name=True),
        Param("r", 0.0, "red, published as given (the Sphero driver reads 0..1)"),
        Param("g", 0.0, "green"),
        Param("b", 0.0, "blue"),
        Param("a", 1.0, "alpha"),
        Param("off_on_false", False, "publish black (0, 0, 0) on the falling edge"),
        Param("repeat", False, "republish the colour every 1/~rate s while true"),
    ],
)


class SetColor(OutputPropositionNode):
    """Set a colour when the proposition rises; optionally switch it off when it falls."""

    def __init__(self, config: dict[str, Any]) -> None:
        self.color = ColorRGBA(r=config["r"], g=config["g"], b=config["b"], a=config["a"])
        self.black = ColorRGBA(r=0.0, g=0.0, b=0.0, a=config["a"])
        self.pub = rospy.Publisher(config["topic"], ColorRGBA, queue_size=10, latch=True)
        super().__init__(config)

    def on_rising(self) -> None:
        self.pub.publish(self.color)

    def while_true(self) -> None:
        if self.config["repeat"]:
            self.pub.publish(self.color)

    def on_falling(self) -> None:
        if self.config["off_on_false"]:
            self.pub.publish(self.black)

    def publishers(self) -> list[rospy.Publisher]:
        return [self.pub]


PUBLISH_ON_EDGE = NodeSpec(
    name="publish_on_edge",
    kind="output",
    description="Publish a message of any type on the rising edge (~on_true) and, if given, on the "
                "falling edge (~on_false); with no ~topic it only logs the edges (a dummy actuator).",
    params=[
        *OUTPUT_PARAMS,
        Param("topic", "", "topic to publish on (empty: only log the edges)", aliases=("publish_topic",),
              ros_name=True),
        Param("type", "std_msgs/Bool", "its message type"),
        Param("on_true", {"data": True}, "message fields published on the rising edge"),
        Param("on_false", {}, "message fields published on the falling edge (empty: nothing)"),
        Param("latch", True, "latch the topic"),
        Param("repeat", False, "republish ~on_true every 1/~rate s while true"),
    ],
)


class PublishOnEdge(OutputPropositionNode):
    """Publish one configured message when the proposition rises and another when it falls."""

    def __init__(self, config: dict[str, Any]) -> None:
        self.pub = self.on_true = self.on_false = None
        if config["topic"]:
            cls = message_class(config["type"])
            self.on_true = fill_message(cls, config["on_true"], "~on_true")
            self.on_false = fill_message(cls, config["on_false"], "~on_false") if config["on_false"] else None
            self.pub = rospy.Publisher(config["topic"], cls, queue_size=10, latch=config["latch"])
        super().__init__(config)

    def on_rising(self) -> None:
        if self.pub is not None:
            self.pub.publish(self.on_true)

    def while_true(self) -> None:
        if self.pub is not None and self.config["repeat"]:
            self.pub.publish(self.on_true)

    def on_falling(self) -> None:
        if self.pub is not None and self.on_false is not None:
            self.pub.publish(self.on_false)

    def publishers(self) -> list[rospy.Publisher]:
        return [self.pub] if self.pub is not None else []


def publish_on_edge_main() -> None:
    run_node(PUBLISH_ON_EDGE, PublishOnEdge)


def set_velocity_main() -> None:
    run_node(SET_VELOCITY, SetVelocity)


def set_color_main() -> None:
    run_node(SET_COLOR, SetColor)
