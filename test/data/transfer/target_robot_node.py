#!/usr/bin/env python3
"""A stand-in for a target robot's drivers on a real master (tests of A.2): it subscribes to the
Twist topics a Turtlebot base listens on, publishes a LaserScan, and serves actionlib actions."""
import actionlib
import rospy
from actionlib.msg import TestAction, TestResult
from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan


def main():
    rospy.init_node("target_robot")
    twist_topics = rospy.get_param("~twist_topics", [])
    scan_topic = rospy.get_param("~scan_topic", "")
    actions = rospy.get_param("~actions", [])
    subscribers = [rospy.Subscriber(t, Twist, lambda msg: None) for t in twist_topics]
    scan_pub = rospy.Publisher(scan_topic, LaserScan, queue_size=1) if scan_topic else None
    servers = []
    for name in actions:
        server = actionlib.SimpleActionServer(name, TestAction, auto_start=False)
        server.register_goal_callback(lambda s=server: s.accept_new_goal() and s.set_succeeded(TestResult()))
        server.start()
        servers.append(server)
    rospy.loginfo("target robot ready: %d twist topics, %d actions", len(subscribers), len(servers))
    rate = rospy.Rate(5)
    while not rospy.is_shutdown():
        if scan_pub:
            scan_pub.publish(LaserScan(ranges=[5.0] * 640))
        rate.sleep()


if __name__ == "__main__":
    main()
