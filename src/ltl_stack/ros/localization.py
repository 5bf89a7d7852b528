"""Proposition nodes for a real base: ``region_localization`` and ``move_base_region``.

``region_localization`` (input) reads the robot's pose from tf (``~map_frame`` -> ``~base_frame``, as
amcl and a base driver provide) or from a pose topic (``PoseStamped``, ``PoseWithCovarianceStamped`` as
amcl publishes, ``Odometry``) and publishes one region proposition per region of a ``.regions`` map:
exactly one true, with hysteresis at the borders (``ltl_stack.runtime.propositions.localization.RegionTracker``).

``move_base_region`` (output) is ``action_proposition`` on ``move_base_msgs/MoveBase``: the goal is the
region's pose (``~pose`` from the mapping, else a point well inside the region's polygon) in
``~frame_id``; completion on arrival, cancel on the falling edge, resend after an abort.
"""
from __future__ import annotations

from typing import Any

import rospy
from std_msgs.msg import String

from ltl_stack.ros.action_proposition import ACTION_PROPOSITION, ActionProposition
from ltl_stack.ros.master import read_param
from ltl_stack.ros.proposition_node import (
    INPUT_PARAMS,
    NodeConfigError,
    NodeSpec,
    Param,
    PropositionGroup,
    message_class,
    run_node,
    wait_for_topic_class,
)
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.propositions.localization import RegionTracker, region_goal
from ltl_stack.runtime.propositions.regions import RegionMap, RegionsError
from ltl_stack.runtime.propositions.sensing import pose_xy

MAP_PARAMS = [
    Param("regions_file", "", "LTLMoP .regions file of the workspace (default: the parameter regions_file "
          "of the node's namespace, which a scenario's launch file sets once)"),
    Param("scale", 1.0, "metres per unit of the .regions file", bound=Bound.POSITIVE),
    Param("x_trans", 0.0, "map x of the file's origin"),
    Param("y_trans", 0.0, "map y of the file's origin"),
    Param("flip_y", False, "negate the file's y (image coordinates point down)"),
]

REGION_LOCALIZATION = NodeSpec(
    name="region_localization",
    kind="input",
    description="Region propositions from localization: the robot's pose from tf (~map_frame -> "
                "~base_frame) or ~pose_topic, tested against the polygons of ~regions_file; exactly one "
                "region true, switching only ~hysteresis metres past a border.",
    params=[
        *[p for p in INPUT_PARAMS if p.name in ("rate", "init_value")],
        *MAP_PARAMS,
        Param("regions", [], "regions to track (default: all but the boundary and obstacles)", kind=list),
        Param("prefix", "inputs/", "proposition topic of region R: ~prefix + R + ~suffix", ros_name=True),
        Param("suffix", "_rc", "see ~prefix (the thesis' completion propositions R_rc)"),
        Param("source", "tf", "where the pose comes from: tf or topic", choices=("tf", "topic")),
        Param("map_frame", "map", "tf: the fixed frame the regions are drawn in", ros_name=True),
        Param("base_frame", "base_link", "tf: the robot's frame", ros_name=True),
        Param("pose_topic", "amcl_pose", "topic: PoseStamped, PoseWithCovarianceStamped, Odometry, ...",
              ros_name=True),
        Param("pose_type", "", "topic: its message type (default: ask the master)"),
        Param("hysteresis", 0.1, "metres past a border before the region changes", bound=Bound.NON_NEGATIVE),
        Param("region_topic", "localized_region", "the current region's name (std_msgs/String, latched; "
              "empty: none)", ros_name=True),
    ],
)


def load_map(config: dict[str, Any]) -> RegionMap:
    """The RegionMap of ``~regions_file``; NodeConfigError naming the file when it is bad."""
    path = config["regions_file"] or str(read_param("regions_file", ""))
    if not path:
        raise NodeConfigError(f"{rospy.get_name()}: set ~regions_file (or regions_file in the node's namespace)")
    try:
        return RegionMap.load(path, scale=config["scale"], x_trans=config["x_trans"],
                              y_trans=config["y_trans"], flip_y=config["flip_y"])
    except RegionsError as error:
        raise NodeConfigError(f"{rospy.get_name()}: {error}") from None


class RegionLocalization:
    def __init__(self, config: dict[str, Any]) -> None:
        self.config = config
        try:
            self.tracker = RegionTracker(load_map(config), [str(n) for n in config["regions"]],
                                         config["hysteresis"])
        except (RegionsError, ValueError) as error:
            raise NodeConfigError(f"{rospy.get_name()}: {error}") from None
        regions = self.tracker.shapes
        for warning in self.tracker.warnings:
            rospy.logwarn("%s: %s", rospy.get_name(), warning)
        # one group: one timer republishes every region's proposition, and a region change is one
        # ~valuation message (the executor's one update), not two Bools a slow link delivers apart
        self.group = PropositionGroup(rate=config["rate"])
        self.outputs = {name: self.group.add(config["prefix"] + name + config["suffix"], config["init_value"])
                        for name in regions}
        self.region_pub = rospy.Publisher(config["region_topic"], String, queue_size=1, latch=True) \
            if config["region_topic"] else None
        self.cls = message_class(config["pose_type"]) if config["pose_type"] else None
        self.reported: str | None = None
        self._warned = False

    def on_position(self, x: float, y: float) -> None:
        region = self.tracker.update(x, y)
        if region is None or region == self.reported:
            return
        rospy.loginfo("%s: in region %s", rospy.get_name(), region)
        self.reported = region
        self.group.set_many({self.outputs[n].topic: v for n, v in self.tracker.valuation().items()})
        if self.region_pub is not None:
            self.region_pub.publish(String(data=region))

    def spin(self) -> None:
        if self.config["source"] == "tf":
            self._spin_tf()
        else:
            cls = self.cls or wait_for_topic_class(rospy.resolve_name(self.config["pose_topic"]))
            if cls is None:
                return
            rospy.Subscriber(self.config["pose_topic"], cls, self._on_pose, queue_size=10)
            rospy.spin()
        self.group.close()

    def _on_pose(self, msg: Any) -> None:
        try:
            position = pose_xy(msg)
        except LookupError as error:
            if not self._warned:
                rospy.logerr("%s: %s: %s", rospy.get_name(), self.config["pose_topic"], error)
                self._warned = True
            return
        self.on_position(*position)

    def _spin_tf(self) -> None:
        import tf2_ros

        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        rate = rospy.Rate(max(self.config["rate"], 1.0))
        target, source = self.config["map_frame"], self.config["base_frame"]
        while not rospy.is_shutdown():
            try:
                t = buffer.lookup_transform(target, source, rospy.Time(0)).transform.translation
                self.on_position(t.x, t.y)
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
                pass  # not yet known: the propositions keep their last values
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break


MOVE_BASE_REGION = NodeSpec(
    name="move_base_region",
    kind="output",
    description="Region activation through move_base (move_base_msgs/MoveBase): on the rising edge send "
                "the region's pose as the goal, completion on arrival, cancel on the falling edge, resend "
                "after an abort (as action_proposition).",
    params=[
        *[p for p in ACTION_PROPOSITION.params if p.name not in ("action", "action_type", "goal", "result_field")],
        Param("action", "move_base", "move_base's action name", required=True, ros_name=True),
        Param("region", "", "the region this proposition drives to", kind=str, required=True),
        Param("pose", [], "its goal pose [x, y] or [x, y, yaw] in ~frame_id (default: the centre of the "
              "region's polygon)", kind=list),
        Param("frame_id", "map", "frame of the goal pose", ros_name=True),
        *MAP_PARAMS,
    ],
)


class MoveBaseRegion(ActionProposition):
    def __init__(self, config: dict[str, Any]) -> None:
        try:
            pose = region_goal(load_map(config), config["region"], config["pose"])
        except RegionsError as error:
            raise NodeConfigError(f"{rospy.get_name()}: {error}") from None
        qx, qy, qz, qw = pose.quaternion()
        goal = {"target_pose": {"header": {"frame_id": config["frame_id"]},
                                "pose": {"position": {"x": pose.x, "y": pose.y, "z": 0.0},
                                         "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}}}
        rospy.loginfo("%s: goal for %s: (%.2f, %.2f, yaw %.2f) in %s", rospy.get_name(), config["region"],
                      pose.x, pose.y, pose.yaw, config["frame_id"])
        super().__init__(dict(config, action_type="move_base_msgs/MoveBase", goal=goal, result_field=""))


def region_localization_main() -> None:
    run_node(REGION_LOCALIZATION, RegionLocalization)


def move_base_region_main() -> None:
    run_node(MOVE_BASE_REGION, MoveBaseRegion)
