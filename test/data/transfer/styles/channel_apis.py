#!/usr/bin/env python
"""One program that opens a channel through every ROS 1 Python API the transfer follows."""
import actionlib
import message_filters
import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_srvs.srv import Empty, Trigger


def make_publisher(topic, kind=Twist):
    return rospy.Publisher(topic, kind, queue_size=1)


class Node:
    def __init__(self):
        self.odom_topic = rospy.get_param('~odom_topic', 'odom')
        self.drive = make_publisher('cmd_vel')
        rospy.wait_for_service('reset_odometry')
        self.reset = rospy.ServiceProxy('reset_odometry', Empty)
        self.server = rospy.Service('~ready', Trigger, self.ready)
        scan = message_filters.Subscriber('scan', LaserScan)
        odom = message_filters.Subscriber(self.odom_topic, Odometry)
        self.sync = message_filters.ApproximateTimeSynchronizer([scan, odom], 10, 0.1)
        self.actions = actionlib.SimpleActionServer('go_to', MoveBaseAction, self.go, False)
        self.buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.cmd_name = rospy.get_param('~cmd_topic')
        self.extra = rospy.Publisher(self.cmd_name, Twist, queue_size=1)

    def where(self):
        return self.buffer.lookup_transform('odom', 'base_footprint', rospy.Time(0))

    def ready(self, request):
        return True, 'ready'

    def go(self, goal):
        self.actions.set_succeeded()
