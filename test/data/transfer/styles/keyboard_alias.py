#!/usr/bin/env python
"""Keyboard driving in the style of a teleop node that names its message type through an alias."""
import sys

import rospy
from geometry_msgs.msg import Twist, TwistStamped

VelocityMsg = Twist

KEYS = {'w': (1, 0), 's': (-1, 0), 'a': (0, 1), 'd': (0, -1)}


class Driver:
    def __init__(self):
        self.pub = rospy.Publisher('cmd_vel', VelocityMsg, queue_size=1)

    def send(self, forward, turn):
        msg = VelocityMsg()
        msg.linear.x = forward
        msg.angular.z = turn
        self.pub.publish(msg)


if __name__ == '__main__':
    rospy.init_node('alias_keyboard')
    if rospy.get_param('~stamped', False):
        VelocityMsg = TwistStamped
    driver = Driver()
    for key in sys.stdin.read():
        if key in KEYS:
            driver.send(*KEYS[key])
