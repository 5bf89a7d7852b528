"""``sim_manipulation_server``: pick and drop actions that take time and report.

For each name in ``~actions`` (default ``pick drop``) it serves an ``ltl_stack/Proposition`` action
of that name: an activating goal runs for ``~duration`` simulated seconds with progress feedback and
then succeeds with ``completed=True``; a cancel preempts it; names in ``~fail`` abort half-way (to try
what happens when an action does not complete). The robot's hand is published latched on
``holding`` (std_msgs/Bool): a completed ``pick`` sets it, a completed ``drop`` clears it.
"""
from __future__ import annotations

import threading
import time
from typing import Any

import actionlib
import rospy
from std_msgs.msg import Bool

from ltl_stack.msg import PropositionAction, PropositionFeedback, PropositionResult
from ltl_stack.ros.proposition_node import NodeConfigError, NodeSpec, Param, run_node
from ltl_stack.runtime.config.node_params import Bound

MANIPULATION_SERVER = NodeSpec(
    name="sim_manipulation_server",
    kind="sim",
    description="Simulated manipulation: ltl_stack/Proposition action servers (pick, drop) that take "
                "~duration and report progress; publishes holding (std_msgs/Bool).",
    params=[
        Param("actions", ["pick", "drop"], "action names to serve", kind=list, ros_name=True),
        Param("duration", 1.0, "simulated seconds each action takes", bound=Bound.NON_NEGATIVE),
        Param("time_scale", 1.0, "simulated seconds per wall-clock second", bound=Bound.POSITIVE),
        Param("fail", [], "action names that abort instead of completing", kind=list, ros_name=True),
        Param("feedback_rate", 10.0, "progress feedback rate (Hz)", bound=Bound.RATE),
    ],
)

#: What a completed action does to the hand (actions not listed leave it alone).
HOLDING_AFTER = {"pick": True, "drop": False}


class ManipulationServer:
    def __init__(self, config: dict[str, Any]) -> None:
        unknown = set(config["fail"]) - set(config["actions"])
        if unknown:
            raise NodeConfigError(f"{rospy.get_name()}: ~fail names actions not in ~actions: "
                                  f"{', '.join(sorted(unknown))}")
        self.config = config
        self.holding = False
        self._lock = threading.Lock()
        self.holding_pub = rospy.Publisher("holding", Bool, queue_size=1, latch=True)
        self.holding_pub.publish(Bool(data=False))
        self.servers = {}
        for name in config["actions"]:
            server = actionlib.SimpleActionServer(
                str(name), PropositionAction, execute_cb=lambda goal, n=str(name): self.execute(n, goal),
                auto_start=False)
            server.start()
            self.servers[str(name)] = server
        rospy.loginfo("%s: actions %s ready", rospy.get_name(), ", ".join(map(str, config["actions"])))

    def execute(self, name: str, goal: Any) -> None:
        server = self.servers[name]
        if not goal.activate:
            server.set_succeeded(PropositionResult(completed=False), "not activated")
            return
        wall_duration = self.config["duration"] / self.config["time_scale"]
        fails = name in self.config["fail"]
        start = time.monotonic()
        rate = rospy.Rate(self.config["feedback_rate"])
        while not rospy.is_shutdown():
            if server.is_preempt_requested():
                server.set_preempted(PropositionResult(completed=False), f"{name} cancelled")
                return
            progress = (time.monotonic() - start) / wall_duration if wall_duration > 0 else 1.0
            if fails and progress >= 0.5:
                server.set_aborted(PropositionResult(completed=False), f"{name} failed (~fail)")
                return
            if progress >= 1.0:
                break
            server.publish_feedback(PropositionFeedback(progress=progress))
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                return
        if rospy.is_shutdown():
            return
        server.publish_feedback(PropositionFeedback(progress=1.0))
        if name in HOLDING_AFTER:
            with self._lock:
                self.holding = HOLDING_AFTER[name]
                self.holding_pub.publish(Bool(data=self.holding))
        server.set_succeeded(PropositionResult(completed=True), f"{name} completed")

    def spin(self) -> None:
        rospy.spin()


def manipulation_server_main() -> None:
    run_node(MANIPULATION_SERVER, ManipulationServer)
