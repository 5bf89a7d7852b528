#!/usr/bin/env python
"""Stop before an obstacle, in the style of a node that polls the laser with wait_for_message."""
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan

SAFE_DISTANCE = 0.3


def nearest():
    scan = rospy.wait_for_message('scan', LaserScan)
    return min(r for r in scan.ranges if r > 0.0)


def main():
    rospy.init_node('obstacle_stop')
    pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
    while not rospy.is_shutdown():
        twist = Twist()
        if nearest() > SAFE_DISTANCE:
            twist.linear.x = 0.1
        pub.publish(twist)


if __name__ == '__main__':
    main()
