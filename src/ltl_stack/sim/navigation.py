"""``sim_navigation_server``: a move_base-like action server for the simulated robot.

It serves ``ltl_stack/Navigate`` on ``~action`` (default ``navigate``): the goal names a region of
``~regions_file`` (the robot drives to a point well inside it, crossing the middle of the border when
it starts in an adjacent region — see ``RegionMap.route``) or a world point. It reads the robot's
``odom``, publishes ``cmd_vel`` with a proportional go-to-point controller, sends the remaining distance
as feedback, stops the robot and succeeds within ``~goal_tolerance``, and stops and reports
preempted when the goal is cancelled. A goal naming an unknown region is aborted with the reason.

With ``~action_type:=move_base_msgs/MoveBase`` it serves move_base's interface instead (``move_base``
on a real robot): the goal is a pose in the map frame (the simulated robot's odom frame is the map),
reached through the middle of the border when it lies in an adjacent region, as above.
"""
from __future__ import annotations

import math
import threading
import time
from typing import Any

import actionlib
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from ltl_stack.msg import NavigateAction, NavigateFeedback, NavigateResult
from ltl_stack.ros.proposition_node import NodeSpec, Param, run_node
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.propositions.regions import RegionsError
from ltl_stack.sim.kinematics import MODES, Pose2D, go_to_point
from ltl_stack.sim.robot import REGION_PARAMS, load_regions

NAVIGATE, MOVE_BASE = "ltl_stack/Navigate", "move_base_msgs/MoveBase"
#: Frames a move_base goal may name: the simulated robot's map is its odom frame.
MAP_FRAMES = ("", "map", "odom", "/map", "/odom")

NAVIGATION_SERVER = NodeSpec(
    name="sim_navigation_server",
    kind="sim",
    description="Simulated navigation action server (ltl_stack/Navigate): drives the robot on "
                "cmd_vel to a region or point using odom; cancellable.",
    params=[
        Param("action", "navigate", "action name", required=True, ros_name=True),
        Param("action_type", NAVIGATE, "the interface served", choices=(NAVIGATE, MOVE_BASE)),
        Param("mode", "diff", f"drive of the robot: {' or '.join(MODES)}", choices=tuple(MODES)),
        Param("rate", 20.0, "control rate (Hz)", bound=Bound.RATE),
        Param("max_linear", 0.5, "speed limit (m/s)", bound=Bound.POSITIVE),
        Param("max_angular", 1.5, "turn-rate limit (rad/s)", bound=Bound.POSITIVE),
        Param("goal_tolerance", 0.05, "success radius around the target (m)", bound=Bound.POSITIVE),
        Param("abort_first", 0, "abort the first N goals, as a planner that finds no path (for tests)",
              bound=Bound.NON_NEGATIVE),
        Param("odom_timeout", 5.0, "abort a goal when no odometry came for this long (s)", bound=Bound.POSITIVE),
        *REGION_PARAMS,
    ],
)


def odom_pose(msg: Any) -> Pose2D:
    """Planar pose of a nav_msgs/Odometry (heading from the quaternion's yaw)."""
    p = msg.pose.pose.position
    q = msg.pose.pose.orientation
    yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    return Pose2D(p.x, p.y, yaw)


class NavigationServer:
    def __init__(self, config: dict[str, Any]) -> None:
        self.config = config
        self.regions = load_regions(config)
        self._lock = threading.Lock()
        self.pose: Pose2D | None = None
        self.pose_time = 0.0
        self.cmd_pub = rospy.Publisher("cmd_vel", Twist, queue_size=10)
        rospy.Subscriber("odom", Odometry, self._on_odom, queue_size=10)
        self.to_abort = config["abort_first"]
        self.move_base = config["action_type"] == MOVE_BASE
        if self.move_base:
            from move_base_msgs.msg import MoveBaseAction, MoveBaseFeedback, MoveBaseResult

            action, self.feedback_cls, self.result_cls = MoveBaseAction, MoveBaseFeedback, MoveBaseResult
        else:
            action, self.feedback_cls, self.result_cls = NavigateAction, NavigateFeedback, NavigateResult
        self.server = actionlib.SimpleActionServer(config["action"], action,
                                                   execute_cb=self.execute, auto_start=False)
        self.server.start()
        rospy.loginfo("%s: action %s ready", rospy.get_name(), rospy.resolve_name(config["action"]))

    def _on_odom(self, msg: Any) -> None:
        with self._lock:
            self.pose = odom_pose(msg)
            self.pose_time = time.monotonic()

    def current_pose(self) -> Pose2D | None:
        with self._lock:
            if self.pose is None or time.monotonic() - self.pose_time > self.config["odom_timeout"]:
                return None
            return self.pose

    def region_of(self, pose: Pose2D) -> str:
        return (self.regions.region_at(pose.x, pose.y) or "") if self.regions is not None else ""

    def waypoints_of(self, goal: Any, start: Pose2D | None) -> list[tuple[float, float]]:
        """World points to drive through for a goal; RegionsError for an unknown region or no regions file."""
        if self.move_base:
            frame = goal.target_pose.header.frame_id
            if frame not in MAP_FRAMES:
                raise RegionsError(f"goal in frame {frame!r}: the simulated robot knows only map and odom")
            point = goal.target_pose.pose.position
            region = self.regions.region_at(point.x, point.y) if self.regions is not None else None
            if region is None or start is None:
                return [(point.x, point.y)]
            return [*self.regions.route((start.x, start.y), region)[:-1], (point.x, point.y)]
        if not goal.region:
            return [(goal.x, goal.y)]
        if self.regions is None:
            raise RegionsError(f"goal names region {goal.region!r} but the server has no ~regions_file")
        if start is None:
            return [self.regions.find(goal.region).interior_point()]
        return self.regions.route((start.x, start.y), goal.region)

    def result(self, reached: bool, region: str = "") -> Any:
        return self.result_cls() if self.move_base else NavigateResult(reached=reached, region=region)

    def feedback(self, left: float, pose: Pose2D) -> Any:
        if not self.move_base:
            return NavigateFeedback(distance=left, x=pose.x, y=pose.y)
        feedback = self.feedback_cls()
        feedback.base_position.header.frame_id = "map"
        feedback.base_position.header.stamp = rospy.Time.now()
        position, orientation = feedback.base_position.pose.position, feedback.base_position.pose.orientation
        position.x, position.y = pose.x, pose.y
        orientation.z, orientation.w = math.sin(pose.theta / 2), math.cos(pose.theta / 2)
        return feedback

    def stop(self) -> None:
        self.cmd_pub.publish(Twist())

    def execute(self, goal: Any) -> None:
        c = self.config
        if self.to_abort > 0:
            self.to_abort -= 1
            self.server.set_aborted(self.result(False), "no path found (~abort_first)")
            return
        wait_until = time.monotonic() + c["odom_timeout"]
        while self.current_pose() is None and time.monotonic() < wait_until and not rospy.is_shutdown():
            rospy.sleep(0.02)
        try:
            waypoints = self.waypoints_of(goal, self.current_pose())
        except RegionsError as error:
            self.server.set_aborted(self.result(False), str(error))
            return
        target = waypoints.pop(0)
        rate = rospy.Rate(c["rate"])
        while not rospy.is_shutdown():
            pose = self.current_pose()
            if self.server.is_preempt_requested():
                self.stop()
                region = self.region_of(pose) if pose else ""
                self.server.set_preempted(self.result(False, region), "cancelled")
                return
            if pose is None:
                if time.monotonic() > wait_until:
                    self.stop()
                    self.server.set_aborted(self.result(False), "no odometry on "
                                            + rospy.resolve_name("odom"))
                    return
            else:
                wait_until = time.monotonic() + c["odom_timeout"]
                dist = math.hypot(target[0] - pose.x, target[1] - pose.y)
                if waypoints and dist <= c["goal_tolerance"]:
                    target = waypoints.pop(0)
                    dist = math.hypot(target[0] - pose.x, target[1] - pose.y)
                left = dist + sum(math.dist(a, b) for a, b in zip([target, *waypoints], waypoints))
                self.server.publish_feedback(self.feedback(left, pose))
                if not waypoints and dist <= c["goal_tolerance"]:
                    self.stop()
                    self.server.set_succeeded(self.result(True, self.region_of(pose)),
                                              "reached")
                    return
                vx, vy, wz = go_to_point(pose, target, c["mode"], c["max_linear"], c["max_angular"])
                cmd = Twist()
                cmd.linear.x, cmd.linear.y, cmd.angular.z = vx, vy, wz
                self.cmd_pub.publish(cmd)
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
        if self.server.is_active():
            self.stop()
            self.server.set_aborted(self.result(False), "shutting down")

    def spin(self) -> None:
        rospy.spin()


def navigation_server_main() -> None:
    run_node(NAVIGATION_SERVER, NavigationServer)
