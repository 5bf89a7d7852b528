"""The simulation against a real master: robot kinematics, navigation and manipulation servers."""
from __future__ import annotations

import math

import pytest
from helpers import require_shared, wait_for
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits


@pytest.fixture
def ros(request):
    return make_session(request)


def remaps(ros) -> list[str]:
    return [f"{name}:={ros.topic(name)}" for name in ("cmd_vel", "odom", "pose", "current_region")]


def twist(vx=0.0, vy=0.0, wz=0.0):
    from geometry_msgs.msg import Twist

    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = vx, vy, wz
    return msg


def xy(odom) -> tuple[float, float]:
    return odom.pose.pose.position.x, odom.pose.pose.position.y


def yaw(odom) -> float:
    q = odom.pose.pose.orientation
    return 2.0 * math.atan2(q.z, q.w)


def test_diff_drive_robot_ignores_sideways_commands_and_drives_a_circle(ros):
    from nav_msgs.msg import Odometry

    odom = ros.record(ros.topic("odom"), Odometry)
    ros.run("sim_robot", "_mode:=diff", "_cmd_timeout:=0", *remaps(ros))
    ros.publish(ros.topic("cmd_vel"), twist(vx=0.5, vy=0.5))
    odom.wait_last(lambda o: xy(o)[0] > 0.2, what="the robot to move forward")
    assert all(abs(xy(o)[1]) < 1e-9 for o in odom.snapshot()), "a diff-drive robot moved sideways"

    ros.publish(ros.topic("cmd_vel"), twist(vx=0.5, wz=1.0))
    odom.wait_last(lambda o: yaw(o) > 1.0, what="the robot to turn 1 rad")
    # Constant (v, w) moves along a circle of radius r = v / w = 0.5: the centre
    # (x - r sin(yaw), y + r cos(yaw)) is the same for every pose on it.
    turning = [o for o in odom.snapshot() if o.twist.twist.angular.z == 1.0][2:]
    assert len(turning) > 5, len(turning)
    centres = [(xy(o)[0] - 0.5 * math.sin(yaw(o)), xy(o)[1] + 0.5 * math.cos(yaw(o))) for o in turning]
    for cx, cy in centres:
        assert math.hypot(cx - centres[0][0], cy - centres[0][1]) < 1e-3, (cx, cy, centres[0])


def test_holonomic_robot_moves_sideways_and_stops_when_commands_stop(ros):
    from nav_msgs.msg import Odometry

    odom = ros.record(ros.topic("odom"), Odometry)
    ros.run("sim_robot", "_mode:=holonomic", "_cmd_timeout:=0.3", "_x:=1.0", *remaps(ros))
    ros.publish(ros.topic("cmd_vel"), twist(vx=0.2, vy=0.4))  # one command, never repeated
    moving = odom.wait_last(lambda o: xy(o)[1] > 0.02, what="sideways motion")
    x, y = xy(moving)
    assert abs((x - 1.0) * 2 - y) < 1e-6, (x, y)  # the direction of (0.2, 0.4)
    stopped = odom.wait_last(lambda o: o.twist.twist.linear.y == 0.0, what="the command to time out")
    final = xy(stopped)
    assert 0.0 < final[1] < 0.4 * 0.3 + 0.05, final  # about cmd_timeout seconds of motion
    assert abs(yaw(stopped)) < 1e-9


def test_navigation_server_reaches_a_region_of_a_real_regions_file(ros):
    from std_msgs.msg import String

    from ltl_stack.msg import NavigateAction, NavigateGoal
    from ltl_stack.runtime.propositions.regions import RegionMap

    path = require_shared("specs", "move_group_and_move_base", "lab_loop.regions")
    start = RegionMap.load(path, scale=0.005).find("top_lane").interior_point()
    region = ros.record(ros.topic("current_region"), String)
    ros.run("sim_robot", f"_x:={start[0]}", f"_y:={start[1]}", "_time_scale:=4", f"_regions_file:={path}",
            "_scale:=0.005", *remaps(ros))
    ros.run("sim_navigation_server", f"_action:={ros.topic('navigate')}", "_max_linear:=0.5",
            f"_regions_file:={path}", "_scale:=0.005", *remaps(ros))
    region.wait_last(lambda s: s.data == "top_lane", what="the robot in top_lane")
    client = ros.action_client(ros.topic("navigate"), NavigateAction)
    feedback = []
    client.send_goal(NavigateGoal(region="leftGround"), feedback_cb=feedback.append)
    assert client.wait_for_result(__import__("rospy").Duration(60)), "no result"
    result = client.get_result()
    assert client.get_state() == 3, client.get_goal_status_text()  # SUCCEEDED
    assert (result.reached, result.region) == (True, "left_ground"), result
    assert len(feedback) > 3 and feedback[0].distance > feedback[-1].distance, feedback[-1:]
    region.wait_last(lambda s: s.data == "left_ground", what="current_region left_ground")


def test_navigation_goal_is_cancellable_and_the_robot_stops(ros):
    import rospy
    from nav_msgs.msg import Odometry

    from ltl_stack.msg import NavigateAction, NavigateGoal

    odom = ros.record(ros.topic("odom"), Odometry)
    ros.run("sim_robot", "_mode:=holonomic", "_cmd_timeout:=0", *remaps(ros))
    ros.run("sim_navigation_server", f"_action:={ros.topic('navigate')}", "_mode:=holonomic", *remaps(ros))
    client = ros.action_client(ros.topic("navigate"), NavigateAction)
    client.send_goal(NavigateGoal(x=50.0, y=0.0))
    odom.wait_last(lambda o: xy(o)[0] > 0.1, what="the robot to move")
    client.cancel_goal()
    assert client.wait_for_result(rospy.Duration(60))
    assert client.get_state() == 2, client.get_goal_status_text()  # PREEMPTED
    odom.wait_last(lambda o: o.twist.twist.linear.x == 0.0, what="the robot to stop")

    client.send_goal(NavigateGoal(region="kitchen"))
    assert client.wait_for_result(rospy.Duration(60))
    assert client.get_state() == 4, client.get_state()  # ABORTED
    assert "no ~regions_file" in client.get_goal_status_text(), client.get_goal_status_text()


def test_manipulation_server_pick_sets_holding_and_drop_can_be_cancelled_or_fail(ros):
    import rospy
    from std_msgs.msg import Bool

    from ltl_stack.msg import PropositionAction, PropositionGoal

    holding = ros.record(ros.topic("holding"), Bool)
    ros.run("sim_manipulation_server", "_duration:=0.4", f"__ns:={ros.ns}", "_actions:=[pick, drop, wave]",
            "_fail:=[wave]")
    pick = ros.action_client(ros.topic("pick"), PropositionAction)
    drop = ros.action_client(ros.topic("drop"), PropositionAction)
    wave = ros.action_client(ros.topic("wave"), PropositionAction)
    holding.wait_last(lambda b: b.data is False, what="not holding at start")

    progress = []
    pick.send_goal(PropositionGoal(activate=True), feedback_cb=lambda f: progress.append(f.progress))
    assert pick.wait_for_result(rospy.Duration(60))
    assert (pick.get_state(), pick.get_result().completed) == (3, True), pick.get_goal_status_text()
    # Feedback and result travel on different topics; the last feedback may come after the result.
    assert len(progress) >= 2 and progress == sorted(progress) and 0 <= progress[0] <= progress[-1] <= 1, progress
    holding.wait_last(lambda b: b.data is True, what="holding after pick")

    drop.send_goal(PropositionGoal(activate=True))
    wait_for(lambda: drop.get_state() == 1, 90, "drop to be active")
    drop.cancel_goal()
    assert drop.wait_for_result(rospy.Duration(60))
    assert (drop.get_state(), drop.get_result().completed) == (2, False), drop.get_goal_status_text()
    assert holding.last().data is True  # a cancelled drop leaves the object in the hand

    wave.send_goal(PropositionGoal(activate=True))
    assert wave.wait_for_result(rospy.Duration(60))
    assert wave.get_state() == 4 and "wave failed" in wave.get_goal_status_text(), wave.get_goal_status_text()


TWO_ROOMS = """Regions: # Stored as JSON string
[
  {"name": "left", "type": "rect", "position": [0, 0], "size": [100, 100]},
  {"name": "right", "type": "rect", "position": [100, 0], "size": [100, 100]}
]
"""


def test_set_velocity_drives_the_sim_robot_into_a_region_that_region_sensor_sees(ros, tmp_path):
    from std_msgs.msg import Bool

    regions = tmp_path / "two_rooms.regions"
    regions.write_text(TWO_ROOMS)
    in_right = ros.record(ros.topic("inputs/right_rc"), Bool)
    ros.run("sim_robot", "_x:=0.8", "_y:=0.5", "_time_scale:=2", *remaps(ros))
    ros.run("region_sensor", f"_regions_file:={regions}", "_region:=right", "_scale:=0.01",
            f"_pose_topic:={ros.topic('odom')}", f"proposition:={ros.topic('inputs/right_rc')}")
    ros.run("set_velocity", f"_topic:={ros.topic('cmd_vel')}", "_vx:=0.5",
            f"proposition:={ros.topic('outputs/forward')}")
    in_right.wait_last(lambda b: b.data is False, what="not in the right room at the start")
    ros.set_bool(ros.topic("outputs/forward"), True)
    in_right.wait_last(lambda b: b.data is True, what="the robot driven into the right room")
