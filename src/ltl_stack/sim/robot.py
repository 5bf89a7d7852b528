"""``sim_robot``: a planar robot that integrates ``cmd_vel`` and publishes its odometry and pose.

It stands in for a mobile base (differential drive, like a TurtleBot, or holonomic, like a youBot)
so that the proposition nodes, the navigation server and the controller run without a robot.
A command older than ``~cmd_timeout`` seconds is dropped (the robot stops), as real bases do.
With ``~regions_file`` it also publishes the name of the region it is in on ``current_region``
(latched, on change), like the thesis' ``/robot_current_region``.
Like a real base it broadcasts tf (``~frame_id`` -> ``~child_frame_id``), and with ``~map_frame`` set it
stands in for localization too: a static identity ``~map_frame`` -> ``~frame_id`` (amcl's transform on
a real robot), so ``region_localization`` reads ``map`` -> ``base_link`` as it would there. With
``~prefix_frames`` each robot of a multi-robot scenario has its own frames under its namespace
(``map`` -> ``spheros/sphero_wpw/odom`` -> ``spheros/sphero_wpw/base_link``), on one tf tree.
"""
from __future__ import annotations

import math
import threading
import time
from typing import Any

import rospy
from geometry_msgs.msg import PoseStamped, TransformStamped, Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import String

from ltl_stack.ros.proposition_node import NodeConfigError, NodeSpec, Param, run_node
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError
from ltl_stack.sim.kinematics import MODES, Pose2D, integrate, limit_command, moving_time

REGION_PARAMS = [
    Param("regions_file", "", "LTLMoP .regions file of the workspace (optional)"),
    Param("scale", 1.0, "metres per unit of the .regions file", bound=Bound.POSITIVE),
    Param("x_trans", 0.0, "world x of the file's origin"),
    Param("y_trans", 0.0, "world y of the file's origin"),
    Param("flip_y", False, "negate the file's y (image coordinates point down)"),
]

SIM_ROBOT = NodeSpec(
    name="sim_robot",
    kind="sim",
    description="Simulated planar robot: integrates cmd_vel (geometry_msgs/Twist), publishes odom "
                "(nav_msgs/Odometry) and pose (geometry_msgs/PoseStamped).",
    params=[
        Param("mode", "diff", f"drive: {' or '.join(MODES)}", choices=tuple(MODES)),
        Param("rate", 50.0, "integration and publishing rate (Hz)", bound=Bound.RATE),
        Param("time_scale", 1.0, "simulated seconds per wall-clock second", bound=Bound.POSITIVE),
        Param("x", 0.0, "initial x (m)"),
        Param("y", 0.0, "initial y (m)"),
        Param("theta", 0.0, "initial heading (rad)"),
        Param("max_linear", 1.0, "speed limit (m/s)", bound=Bound.POSITIVE),
        Param("max_angular", 2.0, "turn-rate limit (rad/s)", bound=Bound.POSITIVE),
        Param("cmd_timeout", 0.5, "stop when no command came for this long (wall s; 0: never)",
              bound=Bound.NON_NEGATIVE),
        Param("frame_id", "odom", "frame of the published pose", ros_name=True),
        Param("child_frame_id", "base_link", "the robot's frame", ros_name=True),
        Param("publish_tf", True, "broadcast ~frame_id -> ~child_frame_id on tf"),
        Param("map_frame", "map", "broadcast a static identity ~map_frame -> ~frame_id (empty: none)",
              ros_name=True),
        Param("prefix_frames", False, "prefix ~frame_id and ~child_frame_id with the node's namespace "
              "(youbots/youbot_1/odom), as tf_prefix did, so several robots share one tf; ~map_frame stays"),
        *REGION_PARAMS,
    ],
)


def load_regions(config: dict[str, Any]) -> RegionMap | None:
    """The RegionMap named by ``~regions_file`` (None when empty); NodeConfigError when bad."""
    if not config["regions_file"]:
        return None
    try:
        return RegionMap.load(config["regions_file"], scale=config["scale"], x_trans=config["x_trans"],
                              y_trans=config["y_trans"], flip_y=config["flip_y"])
    except RegionsError as error:
        raise NodeConfigError(str(error)) from None


def prefixed_frame(namespace: str, frame: str) -> str:
    """``frame`` under the robot's namespace (``/youbots/youbot_1/``, ``odom`` -> ``youbots/youbot_1/odom``):
    tf frame ids carry no leading slash (tf2)."""
    return "/".join(part for part in (namespace.strip("/"), frame.strip("/")) if part)


class SimRobot:
    def __init__(self, config: dict[str, Any]) -> None:
        if config["prefix_frames"]:
            config = dict(config, **{key: prefixed_frame(rospy.get_namespace(), config[key])
                                     for key in ("frame_id", "child_frame_id")})
        self.config = config
        self.regions = load_regions(config)
        self.pose = Pose2D(config["x"], config["y"], config["theta"])
        self.command = (0.0, 0.0, 0.0)
        self.command_time = 0.0
        self.region: str | None = None
        self._lock = threading.Lock()
        self.odom_pub = rospy.Publisher("odom", Odometry, queue_size=10)
        self.pose_pub = rospy.Publisher("pose", PoseStamped, queue_size=10)
        self.region_pub = rospy.Publisher("current_region", String, queue_size=1, latch=True)
        rospy.Subscriber("cmd_vel", Twist, self._on_cmd, queue_size=10)
        self.tf = None
        if config["publish_tf"]:
            import tf2_ros

            self.tf = tf2_ros.TransformBroadcaster()
            if config["map_frame"]:
                self.static_tf = tf2_ros.StaticTransformBroadcaster()
                identity = TransformStamped()
                identity.header.stamp = rospy.Time.now()
                identity.header.frame_id, identity.child_frame_id = config["map_frame"], config["frame_id"]
                identity.transform.rotation.w = 1.0
                self.static_tf.sendTransform(identity)

    def _on_cmd(self, msg: Any) -> None:
        c = self.config
        with self._lock:
            self.command = limit_command(msg.linear.x, msg.linear.y, msg.angular.z, c["mode"],
                                         c["max_linear"], c["max_angular"])
            self.command_time = time.monotonic()

    def step(self, dt_wall: float, now_wall: float) -> None:
        """Advance the pose by ``dt_wall`` wall seconds (times ``~time_scale``)."""
        with self._lock:
            vx, vy, wz = self.command
            timeout = self.config["cmd_timeout"]
            moving = moving_time(dt_wall, now_wall, self.command_time, timeout)
            if timeout > 0 and now_wall >= self.command_time + timeout:
                self.command = (0.0, 0.0, 0.0)
            self.pose = integrate(self.pose, vx, vy, wz, moving * self.config["time_scale"])

    def publish(self) -> None:
        with self._lock:
            pose, (vx, vy, wz) = self.pose, self.command
        stamp = rospy.Time.now()
        odom = Odometry()
        odom.header.stamp = stamp
        odom.header.frame_id = self.config["frame_id"]
        odom.child_frame_id = self.config["child_frame_id"]
        p = odom.pose.pose
        p.position.x, p.position.y = pose.x, pose.y
        p.orientation.z, p.orientation.w = math.sin(pose.theta / 2), math.cos(pose.theta / 2)
        odom.twist.twist.linear.x, odom.twist.twist.linear.y = vx, vy
        odom.twist.twist.angular.z = wz
        self.odom_pub.publish(odom)
        stamped = PoseStamped()
        stamped.header = odom.header
        stamped.pose = p
        self.pose_pub.publish(stamped)
        if self.tf is not None:
            t = TransformStamped()
            t.header, t.child_frame_id = odom.header, odom.child_frame_id
            t.transform.translation.x, t.transform.translation.y = p.position.x, p.position.y
            t.transform.rotation = p.orientation
            self.tf.sendTransform(t)
        if self.regions is not None:
            region = self.regions.region_at(pose.x, pose.y) or ""
            if region != self.region:
                self.region = region
                self.region_pub.publish(String(data=region))

    def spin(self) -> None:
        rate = rospy.Rate(self.config["rate"])
        last = time.monotonic()
        while not rospy.is_shutdown():
            now = time.monotonic()
            self.step(now - last, now)
            last = now
            self.publish()
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break


def sim_robot_main() -> None:
    run_node(SIM_ROBOT, SimRobot)
