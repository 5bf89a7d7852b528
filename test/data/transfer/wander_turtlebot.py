#!/usr/bin/env python3
"""Wander around and avoid obstacles with a Turtlebot (written for ltl_stack's tests after thesis Example 2).

Drive forward while the laser sees free space ahead, otherwise turn on the spot.
"""
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan

SCAN = None


def scan_callback(msg):
    global SCAN
    SCAN = msg


def main():
    rospy.init_node('wander')
    rospy.Subscriber('scan', LaserScan, scan_callback)
    vel_pub = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=1)
    rate = rospy.Rate(10)
    twist = Twist()
    while not rospy.is_shutdown():
        if SCAN is None:
            rate.sleep()
            continue
        middle = len(SCAN.ranges) // 2
        if SCAN.ranges[middle]/10 >= .3:
            vel=.3
            turn = 0
        else:
            vel = 0
            turn = -0.5
        twist.linear.x = vel
        twist.angular.z = turn
        vel_pub.publish(twist)
        rate.sleep()


if __name__ == "__main__":
    main()
