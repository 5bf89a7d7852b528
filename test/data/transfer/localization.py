#!/usr/bin/env python3
"""Localize a mobile robot from wheel odometry, an IMU and laser scans
(written for ltl_stack's tests after thesis Example 6; the robot it was written for is not known).

The pose is predicted from the wheel odometry, its heading is blended with the IMU's, and each new
laser scan corrects the heading by the rotation that best aligns it with the previous scan (circular
cross-correlation of the range profiles). The estimate is broadcast as the transform map -> base,
drawn as an axis in rviz. rviz's "2D Pose Estimate" resets it; while the robot is driven by hand the
velocity commands stand in for odometry that has not arrived yet.
"""
import math
import threading

import numpy as np
import rospy
import tf
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, LaserScan

IMU_WEIGHT = 0.3          # share of the IMU heading in each update
SCAN_WEIGHT = 0.5         # share of the scan-matching rotation in each correction
MAX_SCAN_ROTATION = 0.3   # rad; larger apparent rotations between scans are taken as outliers
ODOM_TIMEOUT = 0.5        # s without odometry before the velocity commands are integrated


def yaw_of(q):
    """Heading of a quaternion message."""
    return tf.transformations.euler_from_quaternion((q.x, q.y, q.z, q.w))[2]


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


def scan_rotation(previous, current, increment):
    """The rotation (rad) that best aligns two range profiles, by circular cross-correlation."""
    a = np.nan_to_num(np.asarray(previous, dtype=float), posinf=0.0)
    b = np.nan_to_num(np.asarray(current, dtype=float), posinf=0.0)
    if len(a) != len(b) or len(a) < 8:
        return 0.0
    a, b = a - a.mean(), b - b.mean()
    spectrum = np.fft.irfft(np.fft.rfft(a) * np.conj(np.fft.rfft(b)), n=len(a))
    shift = int(np.argmax(spectrum))
    if shift > len(a) // 2:
        shift -= len(a)
    return shift * increment


class Localizer:
    """Pose estimate (x, y, yaw) in the map frame."""

    def __init__(self):
        self.lock = threading.Lock()
        self.x = self.y = self.yaw = 0.0
        self.last_odom = None
        self.last_odom_time = None
        self.last_scan = None
        self.command = Twist()
        self.last_command_time = None
        self.broadcaster = tf.TransformBroadcaster()
        rospy.Subscriber('laser/scan', LaserScan, self.on_scan, queue_size=1)
        rospy.Subscriber('wheel_odom', Odometry, self.on_odom, queue_size=10)
        rospy.Subscriber('imu', Imu, self.on_imu, queue_size=10)
        rospy.Subscriber('teleop/cmd_vel', Twist, self.on_command, queue_size=1)
        rospy.Subscriber('set_pose', PoseWithCovarianceStamped, self.on_set_pose, queue_size=1)

    def on_odom(self, msg):
        pose = msg.pose.pose
        current = (pose.position.x, pose.position.y, yaw_of(pose.orientation))
        with self.lock:
            if self.last_odom is not None:
                dx, dy = current[0] - self.last_odom[0], current[1] - self.last_odom[1]
                dyaw = wrap(current[2] - self.last_odom[2])
                # the odometry step, expressed in the robot frame, applied to the estimate
                forward = math.cos(self.last_odom[2]) * dx + math.sin(self.last_odom[2]) * dy
                sideways = -math.sin(self.last_odom[2]) * dx + math.cos(self.last_odom[2]) * dy
                self.x += math.cos(self.yaw) * forward - math.sin(self.yaw) * sideways
                self.y += math.sin(self.yaw) * forward + math.cos(self.yaw) * sideways
                self.yaw = wrap(self.yaw + dyaw)
            self.last_odom = current
            self.last_odom_time = msg.header.stamp if msg.header.stamp else rospy.Time.now()

    def on_imu(self, msg):
        if msg.orientation_covariance[0] < 0:  # the IMU gives no orientation
            return
        with self.lock:
            self.yaw = wrap(self.yaw + IMU_WEIGHT * wrap(yaw_of(msg.orientation) - self.yaw))

    def on_scan(self, msg):
        with self.lock:
            if self.last_scan is not None:
                rotation = scan_rotation(self.last_scan, msg.ranges, msg.angle_increment)
                if abs(rotation) < MAX_SCAN_ROTATION:
                    self.yaw = wrap(self.yaw + SCAN_WEIGHT * rotation)
            self.last_scan = list(msg.ranges)

    def on_command(self, msg):
        with self.lock:
            self.command = msg
            self.last_command_time = rospy.Time.now()

    def on_set_pose(self, msg):
        pose = msg.pose.pose
        with self.lock:
            self.x, self.y, self.yaw = pose.position.x, pose.position.y, yaw_of(pose.orientation)
        rospy.loginfo("pose set to (%.2f, %.2f, %.2f)", self.x, self.y, self.yaw)

    def predict_from_commands(self, dt):
        """Without recent odometry, integrate the commanded velocity (the robot is driven by hand)."""
        now = rospy.Time.now()
        if self.last_odom_time is not None and (now - self.last_odom_time).to_sec() < ODOM_TIMEOUT:
            return
        if self.last_command_time is None or (now - self.last_command_time).to_sec() > ODOM_TIMEOUT:
            return
        v, w = self.command.linear.x, self.command.angular.z
        self.x += v * math.cos(self.yaw) * dt
        self.y += v * math.sin(self.yaw) * dt
        self.yaw = wrap(self.yaw + w * dt)

    def publish(self):
        with self.lock:
            x, y, yaw = self.x, self.y, self.yaw
        self.broadcaster.sendTransform((x, y, 0.0), tf.transformations.quaternion_from_euler(0.0, 0.0, yaw),
                                       rospy.Time.now(), "estimated_base", "map")

    def run(self, rate_hz=20.0):
        rate = rospy.Rate(rate_hz)
        while not rospy.is_shutdown():
            with self.lock:
                self.predict_from_commands(1.0 / rate_hz)
            self.publish()
            rate.sleep()


def main():
    rospy.init_node("scan_localization")
    Localizer().run()


if __name__ == "__main__":
    main()
