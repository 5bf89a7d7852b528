"""Support for the proposition-node and simulation integration tests (no tests in here).

rospy can start one node per process, and only against one master, so these tests share one real
``rosmaster`` for the pytest process and talk to the nodes under test through one in-process rospy
node (the *probe*). Each test uses its own topic namespace and stops the processes it started.
"""
from __future__ import annotations

import atexit
import os
import tempfile
import threading
import time
from pathlib import Path

import pytest
from helpers import WAIT, RosMaster, wait_for

_MASTER: RosMaster | None = None


def shared_master() -> RosMaster:
    """The master of this pytest process, started on first use and stopped at exit."""
    global _MASTER
    if _MASTER is None:
        rospy = pytest.importorskip("rospy")
        _MASTER = RosMaster(Path(tempfile.mkdtemp(prefix="ltl_stack_nodes_")))
        atexit.register(_MASTER.shutdown)
        saved = {k: os.environ.get(k) for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME")}
        os.environ.update({k: _MASTER.env[k] for k in saved})
        try:
            rospy.init_node("pytest_probe", anonymous=True, disable_signals=True)
            # rospy reads ROS_MASTER_URI lazily, once: for the parameter server and on the first
            # inbound connection. Make it read it now, while it points at this master.
            from rospy.impl import tcpros_base
            rospy.get_param_names()
            tcpros_base._is_use_tcp_keepalive()
        finally:
            # The probe keeps talking to this master; other tests must not see it in the environment.
            # ROS_IP stays 127.0.0.1 (what every test master uses): rospy reads it lazily when it first
            # serves a topic, and the machine's host name may not resolve (a bare chroot or container).
            saved.pop("ROS_IP")
            for key, value in saved.items():
                if value is None:
                    os.environ.pop(key, None)
                else:
                    os.environ[key] = value
    return _MASTER


class Recorder:
    """Every message received on a topic, with the time it arrived."""

    def __init__(self, topic: str, msg_type: type) -> None:
        import rospy

        self.topic = topic
        self.messages: list = []
        self.times: list[float] = []
        self._lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, msg_type, self._on_msg, queue_size=100)

    def _on_msg(self, msg) -> None:
        with self._lock:
            self.messages.append(msg)
            self.times.append(time.monotonic())

    def snapshot(self) -> list:
        with self._lock:
            return list(self.messages)

    def last(self):
        with self._lock:
            return self.messages[-1] if self.messages else None

    def wait_connected(self, publishers: int = 1, timeout: float = WAIT) -> None:
        """Wait until this recorder is connected to ``publishers`` publishers: rospy connects a subscriber
        to a publisher that registered later in the background, and what is sent before is not seen."""
        wait_for(lambda: self.sub.get_num_connections() >= publishers, timeout,
                 f"{publishers} publisher(s) connected on {self.topic}")

    def wait(self, predicate, timeout: float = WAIT, what: str = "a message"):
        """Wait until ``predicate(messages)`` is truthy; return its value."""
        return wait_for(lambda: predicate(self.snapshot()), timeout, f"{what} on {self.topic}")

    def wait_last(self, predicate, timeout: float = WAIT, what: str = "a message"):
        """Wait until the latest message satisfies ``predicate``; return that message."""
        def check():
            msg = self.last()
            return msg if msg is not None and predicate(msg) else None
        return wait_for(check, timeout, f"{what} on {self.topic}")

    def close(self) -> None:
        self.sub.unregister()


class Session:
    """What one test gets: the shared master, a topic namespace, publishers and recorders."""

    def __init__(self, master: RosMaster, ns: str) -> None:
        self.master = master
        self.ns = ns
        self._pubs: dict = {}
        self._recorders: list[Recorder] = []
        self._clients: list = []
        self._beats: dict = {}  # output topics set_bool keeps republishing, as the executor's heartbeat
        self._beat_timer = None

    def topic(self, name: str) -> str:
        return f"{self.ns}/{name}"

    def run(self, script: str, *params: str, name: str | None = None):
        """``rosrun ltl_stack <script>`` with params like ``_rate:=5``, node name under the namespace."""
        node = name or script
        return self.master.run(["rosrun", "ltl_stack", script, f"__name:={self.ns.strip('/')}_{node}",
                                *params], name=node)

    def record(self, topic: str, msg_type: type) -> Recorder:
        rec = Recorder(topic, msg_type)
        self._recorders.append(rec)
        return rec

    def publish(self, topic: str, msg, latch: bool = True, subscribers: int = 1, timeout: float = WAIT):
        """Publish ``msg`` (latched) once ``subscribers`` nodes listen to ``topic``."""
        import rospy

        pub = self._pubs.get(topic)
        if pub is None:
            pub = rospy.Publisher(topic, type(msg), queue_size=10, latch=latch)
            self._pubs[topic] = pub
        wait_for(lambda: pub.get_num_connections() >= subscribers, timeout, f"{subscribers} subscriber(s) on {topic}")
        pub.publish(msg)

    def set_bool(self, topic: str, value: bool, subscribers: int = 1) -> None:
        """Set a proposition as the controller executor does: published at once, then republished
        every 0.25 s (its heartbeat, which output nodes' deadman listens for)."""
        import rospy
        from std_msgs.msg import Bool

        self.publish(topic, Bool(data=value), subscribers=subscribers)
        self._beats[topic] = Bool(data=value)
        if self._beat_timer is None:
            self._beat_timer = rospy.Timer(rospy.Duration(0.25), self._beat)

    def _beat(self, _event) -> None:
        for topic, msg in list(self._beats.items()):
            self._pubs[topic].publish(msg)

    def action_client(self, name: str, action_type: type, timeout: float = WAIT):
        """A real actionlib SimpleActionClient (ours: without actionlib's send_goal race, see
        ltl_stack.ros.action_client), connected to its server."""
        import rospy

        from ltl_stack.ros.action_client import SimpleActionClient

        client = SimpleActionClient(name, action_type)
        self._clients.append(client)
        assert client.wait_for_server(rospy.Duration(timeout)), f"no action server {name}"
        return client

    def close(self, processes_before: int) -> None:
        if self._beat_timer is not None:
            self._beat_timer.shutdown()
        for client in self._clients:
            ac = client.action_client
            for endpoint in (ac.pub_goal, ac.pub_cancel, ac.status_sub, ac.result_sub, ac.feedback_sub):
                endpoint.unregister()
        for proc in self.master.processes[processes_before:]:
            proc.stop()
        del self.master.processes[processes_before:]
        for rec in self._recorders:
            rec.close()
        for pub in self._pubs.values():
            pub.unregister()


def make_session(request) -> Session:
    master = shared_master()
    ns = "/t_" + "".join(c if c.isalnum() else "_" for c in request.node.name)[:60]
    session = Session(master, ns)
    before = len(master.processes)
    request.addfinalizer(lambda: session.close(before))
    return session
