#!/usr/bin/env python
"""Move the arm by joint values and named states, in the style of a moveit_commander tutorial."""
import sys

import moveit_commander
import rospy

moveit_commander.roscpp_initialize(sys.argv)
rospy.init_node('commander_demo')
group = moveit_commander.MoveGroupCommander('arm')
group.set_joint_value_target({'shoulder_pan_joint': 0.5, 'elbow_flex_joint': 1.0})
group.go(wait=True)
group.set_joint_value_target('wrist_flex_joint', 0.3)
group.go(wait=True)
group.set_named_target('tucked')
group.go(wait=True)
