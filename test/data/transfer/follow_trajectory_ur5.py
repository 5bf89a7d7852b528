#!/usr/bin/env python3
"""Move a UR5 arm through three configurations with a joint trajectory action
(written for ltl_stack's tests after thesis Example 3)."""
import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINT_NAMES = ['shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint',
               'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint']
Q1 = [2.2, 0, -1.57, 0, 0, 0]
Q2 = [1.5, 0, -1.57, 0, 0, 0]
Q3 = [1.5, -0.2, -1.57, 0, 0, 0]


def move(client):
    goal = FollowJointTrajectoryGoal()
    goal.trajectory = JointTrajectory()
    goal.trajectory.joint_names = JOINT_NAMES
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=Q1, velocities=[0] * 6, time_from_start=rospy.Duration(2.0)),
        JointTrajectoryPoint(positions=Q2, velocities=[0] * 6, time_from_start=rospy.Duration(3.0)),
        JointTrajectoryPoint(positions=Q3, velocities=[0] * 6, time_from_start=rospy.Duration(4.0))]
    client.send_goal(goal)
    client.wait_for_result()


def main():
    rospy.init_node("test_move", anonymous=True, disable_signals=True)
    client = actionlib.SimpleActionClient('/arm_controller/follow_joint_trajectory', FollowJointTrajectoryAction)
    rospy.loginfo("waiting for the trajectory server")
    client.wait_for_server()
    move(client)


if __name__ == "__main__":
    main()
