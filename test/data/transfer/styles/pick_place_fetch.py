#!/usr/bin/env python
"""Tuck the arm and pick a block, in the style of a mobile manipulator's MoveIt demo."""
import rospy
from moveit_python import MoveGroupInterface, PickPlaceInterface, PlanningSceneInterface

ARM_JOINTS = ['shoulder_pan_joint', 'shoulder_lift_joint', 'upperarm_roll_joint', 'elbow_flex_joint',
              'forearm_roll_joint', 'wrist_flex_joint', 'wrist_roll_joint']


class Grasping:
    def __init__(self):
        self.scene = PlanningSceneInterface('base_link')
        self.pickplace = PickPlaceInterface('arm', 'gripper', verbose=True)
        self.move_group = MoveGroupInterface('arm', 'base_link')

    def tuck(self):
        tucked = [1.32, 1.40, -0.20, 1.72, 0.0, 1.66, 0.0]
        self.move_group.moveToJointPosition(ARM_JOINTS, tucked, 0.02)

    def pick(self, block, grasps):
        return self.pickplace.pick_with_retry(block.name, grasps, support_name=block.support)


if __name__ == '__main__':
    rospy.init_node('pick_demo')
    Grasping().tuck()
