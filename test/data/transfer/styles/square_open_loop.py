#!/usr/bin/env python
"""Drive a square by time alone (no odometry), in the style of the TurtleBot tutorials."""
import actionlib
import rospy
from geometry_msgs.msg import Twist
from move_base_msgs.msg import MoveBaseAction

SIDE_TICKS = 10
TURN_TICKS = 16


def main():
    rospy.init_node('square')
    pub = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=10)
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
    client.wait_for_server(rospy.Duration(5))
    rate = rospy.Rate(5)
    forward, turn = Twist(), Twist()
    forward.linear.x = 0.2
    turn.angular.z = 0.5
    for _ in range(4):
        for _ in range(SIDE_TICKS):
            pub.publish(forward)
            rate.sleep()
        for _ in range(TURN_TICKS):
            pub.publish(turn)
            rate.sleep()
        pub.publish(Twist())
        rospy.sleep(0.5)


if __name__ == '__main__':
    main()
