#!/usr/bin/env python3
"""Move a Fetch gripper between two obstacles and away again with MoveIt
(written for ltl_stack's tests after thesis Example 5)."""
import rospy
from geometry_msgs.msg import Point, Pose, PoseStamped, Quaternion
from moveit_msgs.msg import MoveItErrorCodes
from moveit_python import MoveGroupInterface, PlanningSceneInterface


def main():
    rospy.init_node("simple_disco")
    move_group = MoveGroupInterface("arm_with_torso", "base_link")
    scene = PlanningSceneInterface("base_link")
    scene.removeCollisionObject("my_front_ground")
    scene.addCube("my_front_ground", 2, 1.1, 0.0, -1.0)
    scene.addBox("obstacle_left", 0.3, 0.05, 0.6, 0.75, 0.25, 0.8)
    scene.addBox("obstacle_right", 0.3, 0.05, 0.6, 0.75, -0.25, 0.8)
    gripper_frame = 'wrist_roll_link'
    gripper_poses = [Pose(Point(0.60, 0.0, 0.90), Quaternion(0.0, 0.0, 0.0, 1.0)),
                     Pose(Point(0.45, 0.0, 1.10), Quaternion(0.0, 0.0, 0.0, 1.0))]
    gripper_pose_stamped = PoseStamped()
    gripper_pose_stamped.header.frame_id = 'base_link'
    while not rospy.is_shutdown():
        for pose in gripper_poses:
            gripper_pose_stamped.header.stamp = rospy.Time.now()
            gripper_pose_stamped.pose = pose
            move_group.moveToPose(gripper_pose_stamped, gripper_frame)
            result = move_group.get_move_action().get_result()
            if result and result.error_code.val == MoveItErrorCodes.SUCCESS:
                rospy.loginfo("reached the goal")
            else:
                rospy.logerr("the arm could not reach the goal")
    move_group.get_move_action().cancel_all_goals()


if __name__ == "__main__":
    main()
