#!/usr/bin/env python3
"""Greet people with a Pepper from a small window (written for ltl_stack's tests after thesis Example 4).

Buttons drive the base (forward, back, turn left, turn right, stop) with velocity commands on
``cmd_vel`` and wave the right arm with a joint trajectory sent to the pose controller's action.
"Greet" turns towards the visitor and waves.
"""
import threading
import tkinter as tk

import actionlib
import rospy
from geometry_msgs.msg import Twist, Vector3
from naoqi_bridge_msgs.msg import JointTrajectoryAction, JointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

ARM_JOINTS = ['RShoulderPitch', 'RShoulderRoll', 'RElbowYaw', 'RElbowRoll', 'RWristYaw']

# The waving motion: raise the arm, swing the forearm out and in twice, lower the arm.
RAISED = [-1.0, -0.3, 1.2, 0.5, 0.0]
WAVE_OUT = [-1.0, -0.6, 1.2, 1.0, 0.0]
WAVE_IN = [-1.0, -0.1, 1.2, 0.3, 0.0]
LOWERED = [1.5, -0.1, 1.2, 0.3, 0.0]

# Joint speeds through the swings (rad/s), so the hand does not stop at each end.
SWING_OUT = [0.0, -1.5, 0.0, 2.0, 0.0]
SWING_IN = [0.0, 1.5, 0.0, -2.0, 0.0]

DRIVE_SECONDS = 1.0


def wave_goal():
    """The joint trajectory of one greeting wave."""
    goal = JointTrajectoryGoal()
    goal.trajectory = JointTrajectory()
    goal.trajectory.joint_names = ARM_JOINTS
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=RAISED, time_from_start=rospy.Duration(1.5)),
        JointTrajectoryPoint(positions=WAVE_OUT, velocities=SWING_OUT, time_from_start=rospy.Duration(2.0)),
        JointTrajectoryPoint(positions=WAVE_IN, velocities=SWING_IN, time_from_start=rospy.Duration(2.5)),
        JointTrajectoryPoint(positions=WAVE_OUT, velocities=SWING_OUT, time_from_start=rospy.Duration(3.0)),
        JointTrajectoryPoint(positions=WAVE_IN, velocities=SWING_IN, time_from_start=rospy.Duration(3.5)),
        JointTrajectoryPoint(positions=LOWERED, time_from_start=rospy.Duration(5.0))]
    goal.relative = 0
    return goal


class GreetApp:
    """The window and the robot's two channels."""

    def __init__(self, root):
        self.root = root
        self.velocity = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        self.arm = actionlib.SimpleActionClient('/pepper_robot/pose/joint_trajectory', JointTrajectoryAction)
        self.status = tk.StringVar(value="waiting for the arm controller")
        self.busy = threading.Lock()
        self.build()
        threading.Thread(target=self.connect, daemon=True).start()

    def build(self):
        self.root.title("Greet")
        frame = tk.Frame(self.root, padx=10, pady=10)
        frame.pack()
        buttons = [
            ("Forward", 0, 1, self.forward),
            ("Turn left", 1, 0, self.turn_left),
            ("Stop", 1, 1, self.stop),
            ("Turn right", 1, 2, self.turn_right),
            ("Back", 2, 1, self.back),
        ]
        for text, row, column, action in buttons:
            tk.Button(frame, text=text, width=10, command=action).grid(row=row, column=column, padx=2, pady=2)
        tk.Button(frame, text="Wave", width=10, command=self.wave).grid(row=3, column=0, pady=8)
        tk.Button(frame, text="Greet", width=10, command=self.greet).grid(row=3, column=2, pady=8)
        tk.Label(frame, textvariable=self.status).grid(row=4, column=0, columnspan=3)
        self.root.protocol("WM_DELETE_WINDOW", self.quit)

    def connect(self):
        if self.arm.wait_for_server(rospy.Duration(10.0)):
            self.status.set("ready")
        else:
            self.status.set("no arm controller: waving is not available")

    # --- the base ---

    def drive(self, twist, seconds=DRIVE_SECONDS):
        """Send ``twist`` at 10 Hz for ``seconds``, then stop."""
        def run():
            rate = rospy.Rate(10)
            end = rospy.Time.now() + rospy.Duration(seconds)
            while not rospy.is_shutdown() and rospy.Time.now() < end:
                self.velocity.publish(twist)
                rate.sleep()
            self.velocity.publish(Twist())
        threading.Thread(target=run, daemon=True).start()

    def forward(self):
        self.status.set("forward")
        self.drive(Twist(Vector3(0.3, 0, 0), Vector3(0, 0, 0)))

    def back(self):
        self.status.set("back")
        self.drive(Twist(Vector3(-0.3, 0, 0), Vector3(0, 0, 0)))

    def turn_left(self):
        self.status.set("turning left")
        self.drive(Twist(Vector3(0, 0, 0), Vector3(0, 0, 0.5)))

    def turn_right(self):
        self.status.set("turning right")
        self.drive(Twist(Vector3(0, 0, 0), Vector3(0, 0, -0.5)))

    def stop(self):
        self.status.set("stopped")
        self.velocity.publish(Twist())

    # --- the arm ---

    def wave(self):
        if not self.busy.acquire(blocking=False):
            return
        self.status.set("waving")

        def done(state, result):
            self.status.set("ready")
            self.busy.release()

        self.arm.send_goal(wave_goal(), done_cb=done)

    def greet(self):
        """Turn towards the visitor (a quarter turn to the left), then wave."""
        self.turn_left()
        self.root.after(int(DRIVE_SECONDS * 1000) + 200, self.wave)

    def quit(self):
        self.velocity.publish(Twist())
        rospy.signal_shutdown("window closed")
        self.root.destroy()


def main():
    rospy.init_node("greet", disable_signals=True)
    root = tk.Tk()
    GreetApp(root)
    root.mainloop()


if __name__ == "__main__":
    main()
