"""Finding channels and command literals with ast (§2.5.1, §2.5.2)."""
import textwrap

import pytest

from ltl_stack.errors import InputError
from ltl_stack.transfer.channels import find_channels
from ltl_stack.transfer.commands import find_joint_trajectories, find_velocity_commands
from ltl_stack.transfer.source_ast import SourceFile


def channels(code):
    return [(c.kind, c.name.value, c.msg_type, c.line) for c in find_channels(textwrap.dedent(code))]


def test_publisher_and_subscriber_positional_and_keyword():
    got = channels("""\
        import rospy
        import sensor_msgs.msg
        from geometry_msgs.msg import Twist
        pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        sub = rospy.Subscriber(data_class=sensor_msgs.msg.LaserScan, name="scan", callback=None)
    """)
    assert got == [("publisher", "cmd_vel", "geometry_msgs/Twist", 4),
                   ("subscriber", "scan", "sensor_msgs/LaserScan", 5)], got


def test_import_aliases_and_variables_bound_to_literals():
    got = channels("""\
        from rospy import Publisher as Pub
        import geometry_msgs.msg as gm
        TOPIC = '/cmd_vel'
        def main():
            p = Pub(TOPIC, gm.Twist)
    """)
    assert got == [("publisher", "/cmd_vel", "geometry_msgs/Twist", 5)], got


def test_actions_and_moveit():
    got = channels("""\
        import actionlib
        from control_msgs.msg import FollowJointTrajectoryAction
        from moveit_python import MoveGroupInterface
        import moveit_commander
        client = actionlib.SimpleActionClient('follow_joint_trajectory', FollowJointTrajectoryAction)
        server = actionlib.SimpleActionServer('do', FollowJointTrajectoryAction, execute_cb=None)
        group = MoveGroupInterface("arm_with_torso", "base_link")
        other = moveit_commander.MoveGroupCommander("arm")
        gripper_frame = 'wrist_roll_link'
        group.moveToPose(pose, gripper_frame)
        other.set_end_effector_link("wrist_roll_link")
    """)
    assert got == [("action_client", "follow_joint_trajectory", "control_msgs/FollowJointTrajectoryAction", 5),
                   ("action_server", "do", "control_msgs/FollowJointTrajectoryAction", 6),
                   ("move_group", "arm_with_torso", None, 7),
                   ("move_group", "arm", None, 8),
                   ("pose_frame", "wrist_roll_link", None, 10),
                   ("pose_frame", "wrist_roll_link", None, 11)], got


def test_computed_names_are_reported_not_guessed():
    uses = find_channels("import rospy\nns = rospy.get_param('~ns')\np = rospy.Publisher(ns + '/cmd_vel', T)\n")
    assert [u.name.value for u in uses] == [None], uses
    assert "computed name" in uses[0].name.problem, uses[0].name.problem


def test_syntax_errors_name_file_and_line():
    with pytest.raises(InputError) as err:
        find_channels("x = (\n", "prog.py")
    assert str(err.value).startswith("prog.py:1: not valid Python: "), str(err.value)


def velocity(code):
    commands, unresolved = find_velocity_commands(SourceFile(textwrap.dedent(code)))
    return [(c.field, c.value, c.line, c.via) for c in commands], [(u.field, u.line) for u in unresolved]


def test_twist_constructors_positional_and_keyword():
    got, _ = velocity("""\
        a = Twist(Vector3(0.5, 0, 0), Vector3(0, 0, -0.5))
        b = Twist(angular=Vector3(z=1.5), linear=Vector3(x=-2))
    """)
    assert got == [("linear.x", 0.5, 1, None), ("linear.y", 0, 1, None), ("linear.z", 0, 1, None),
                   ("angular.x", 0, 1, None), ("angular.y", 0, 1, None), ("angular.z", -0.5, 1, None),
                   ("angular.z", 1.5, 2, None), ("linear.x", -2.0, 2, None)], got  # source order


def test_assignments_tuples_and_variables():
    got, unresolved = velocity("""\
        msg.linear.x, msg.linear.y = 1.0, 1.0
        if d >= .3:
            vel = .3
        else:
            vel = scan.ranges[0] * 2
        msg.linear.x = vel
        msg.angular = Vector3(0, 0, 0.25)
        msg.angular.z += 0.1
    """)
    assert got == [("linear.x", 1.0, 1, None), ("linear.y", 1.0, 1, None), ("linear.x", 0.3, 6, "vel"),
                   ("angular.x", 0, 7, None), ("angular.y", 0, 7, None), ("angular.z", 0.25, 7, None)], got
    assert unresolved == [("linear.x", 6), ("angular.z", 8)], unresolved


def test_joint_names_and_positions_through_variables():
    src = SourceFile(textwrap.dedent("""\
        JOINTS = ['a', 'b']
        Q1 = [0.1, -0.2]
        g.trajectory.joint_names = JOINTS
        g.trajectory.points = [JointTrajectoryPoint(positions=Q1, velocities=[0]*2),
                               JointTrajectoryPoint(positions=[0.3, 0.4], time_from_start=d)]
    """))
    use = find_joint_trajectories(src)
    assert [n.values for n in use.names] == [["a", "b"]], use.names
    assert [p.values for p in use.points] == [[0.1, -0.2], [0.3, 0.4]], use.points
    assert [kind for _, kind, _ in use.zero_lists] == ["velocities"], use.zero_lists
