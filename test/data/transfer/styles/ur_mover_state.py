#!/usr/bin/env python
"""Move a six-joint arm home, then hold where it is, in the style of a UR test mover."""
import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

NAMES = ['shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint',
         'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint']
HOME = [0.0, -1.57, 1.57, -1.57, -1.57, 0.0]


def go_home(client):
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = NAMES
    goal.trajectory.points = [JointTrajectoryPoint(positions=HOME, velocities=[0] * 6,
                                                   time_from_start=rospy.Duration(3.0))]
    client.send_goal_and_wait(goal)


def hold(client):
    state = rospy.wait_for_message('joint_states', JointState)
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(state.name)
    goal.trajectory.points = [JointTrajectoryPoint(positions=list(state.position), velocities=[0] * 6,
                                                   time_from_start=rospy.Duration(1.0))]
    client.send_goal_and_wait(goal)


if __name__ == '__main__':
    rospy.init_node('ur_mover')
    arm = actionlib.SimpleActionClient('follow_joint_trajectory', FollowJointTrajectoryAction)
    arm.wait_for_server()
    go_home(arm)
    hold(arm)
