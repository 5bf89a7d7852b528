#!/usr/bin/env python3
"""Drive a Jackal with the arrow keys (written for ltl_stack's tests after thesis Example 1).

Up/down drive forwards/backwards, left/right turn on the spot, space stops, q quits.
"""
import sys
import termios
import tty

import rospy
from geometry_msgs.msg import Twist, Vector3

KEY_UP, KEY_DOWN, KEY_RIGHT, KEY_LEFT = "\x1b[A", "\x1b[B", "\x1b[C", "\x1b[D"


def read_key():
    """One key press from the terminal (arrow keys arrive as three characters)."""
    fd = sys.stdin.fileno()
    old = termios.tcgetattr(fd)
    try:
        tty.setraw(fd)
        key = sys.stdin.read(1)
        if key == "\x1b":
            key += sys.stdin.read(2)
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, old)
    return key


def command_for(key):
    """The velocity command for a key, or None to quit."""
    if key == KEY_UP:
        return Twist(Vector3(0.5, 0, 0), Vector3(0, 0, 0))
    elif key == KEY_DOWN:
        return Twist(Vector3(-0.5, 0, 0), Vector3(0, 0, 0))
    elif key == KEY_LEFT:
        return Twist(Vector3(0, 0, 0), Vector3(0, 0, 0.5))
    elif key == KEY_RIGHT:
        return Twist(Vector3(0, 0, 0), Vector3(0, 0, -0.5))
    elif key == "q":
        return None
    return Twist(Vector3(0, 0, 0), Vector3(0, 0, 0))


def main():
    rospy.init_node("keyboard_control")
    pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
    keys = rospy.get_param("~keys", "")  # scripted key presses (for tests); empty reads the terminal
    listeners = rospy.get_param("~listeners", 1)  # scripted keys: how many subscribers must hear them
    rate = rospy.Rate(10)
    while keys and pub.get_num_connections() < listeners and not rospy.is_shutdown():
        rate.sleep()  # scripted keys: wait for the robot to listen, so that no key press is lost
    index = 0
    while not rospy.is_shutdown():
        if keys:
            if index >= len(keys):
                break
            key = {"u": KEY_UP, "d": KEY_DOWN, "l": KEY_LEFT, "r": KEY_RIGHT}.get(keys[index], keys[index])
            index += 1
        else:
            key = read_key()
        command = command_for(key)
        if command is None:
            break
        pub.publish(command)
        rate.sleep()


if __name__ == "__main__":
    main()
