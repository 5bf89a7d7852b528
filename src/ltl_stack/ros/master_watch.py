"""Survive a master restart: re-register this node's topics, services and parameters.

rospy registers a node's publishers, subscribers and services with the master once; when the master
dies and a new one comes up on the same URI, the new master knows nothing about the node: new nodes
never connect to its topics, its services cannot be found, its parameters are gone. ``MasterWatch``
polls the master's process id (``getPid``) once a period in one daemon thread; when a different
master answers, it registers everything the node has — through rospy's own topic and service
managers, so nothing is created twice — sets the node's private parameters again, sets ``/run_id``
and the shared parameters the node read (``ros.master.read_param``) where the new master lacks them,
and connects the node's subscribers to the publishers the new master knows. ``/run_id`` matters to
roslaunch: one joining a master without it makes up its own and sets it, so two started together
race and one fails ("run_id on parameter server does not match declared run_id"), and one started
with ``--wait`` waits for ever; every node of ours re-sets the same value, the old master's. Every call has a timeout
(``ros.master.CALL_TIMEOUT``): an unreachable master never holds the thread for longer.
"""
from __future__ import annotations

import threading
import xmlrpc.client
from collections.abc import Callable
from typing import Any

import rosgraph
import rospy
from rospy.impl.registration import get_service_manager, get_topic_manager

from ltl_stack.ros.master import SHARED_READ, timed_proxy

#: The launch's run id (roscore sets it; roslaunch checks it against its own).
RUN_ID = "/run_id"


class MasterWatch:
    """Polls the master's pid every ``period`` seconds and re-registers the node with a new master."""

    def __init__(self, period: float = 1.0, on_restart: Callable[[], None] | None = None) -> None:
        self.period = period
        self.on_restart = on_restart
        self.restarts = 0
        self.caller_id = rospy.get_name()
        self.master = timed_proxy(rosgraph.get_master_uri())
        self.params = self._private_params()
        self.run_id = self._param(RUN_ID)
        self.pid = self._master_pid()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="master_watch", daemon=True)
        self._thread.start()
        rospy.on_shutdown(self._stop.set)

    def _master_pid(self) -> int | None:
        try:
            return int(_ok(self.master.getPid(self.caller_id), "getPid"))
        except (OSError, rosgraph.MasterException, xmlrpc.client.Error, ValueError, TypeError):
            return None

    def _param(self, name: str) -> Any:
        """The parameter ``name`` on the master (None: unset, or no answer)."""
        try:
            return _ok(self.master.getParam(self.caller_id, name), name)
        except (OSError, rosgraph.MasterException, xmlrpc.client.Error, TypeError, ValueError):
            return None

    def _private_params(self) -> dict[str, Any]:
        value = self._param(rospy.resolve_name("~"))
        return value if isinstance(value, dict) else {}

    def _run(self) -> None:
        while not self._stop.wait(self.period) and not rospy.is_shutdown():
            pid = self._master_pid()
            if pid is None or pid == self.pid:
                continue  # the master is away (wait for one) or it is the same one
            if self.pid is not None:
                try:
                    self.reregister()
                except (OSError, rosgraph.MasterException, xmlrpc.client.Error) as err:
                    rospy.logwarn("%s: re-registering with the new master failed (%s); trying again",
                                  self.caller_id, err)
                    continue
                self.restarts += 1
                rospy.logwarn("%s: the ROS master restarted (pid %s -> %s); registered topics, services and "
                              "parameters again", self.caller_id, self.pid, pid)
                if self.on_restart is not None:
                    self.on_restart()
            self.pid = pid

    def reregister(self) -> None:
        """Register every publisher, subscriber, service and private parameter with the master."""
        uri = rospy.core.get_node_uri()
        master = self.master
        tm, sm = get_topic_manager(), get_service_manager()
        with tm.lock, sm.lock:
            publications = tm.get_publications()
            subscriptions = tm.get_subscriptions()
            services = sm.get_services()
        if self.params:
            _ok(master.setParam(self.caller_id, rospy.resolve_name("~"), self.params), "~")
        shared = {**SHARED_READ, **({RUN_ID: self.run_id} if self.run_id is not None else {})}
        for name, value in shared.items():
            if not _ok(master.hasParam(self.caller_id, name), name):
                _ok(master.setParam(self.caller_id, name, value), name)
        for name, msg_type in publications:
            _ok(master.registerPublisher(self.caller_id, name, msg_type, uri), name)
        node = timed_proxy(uri)
        for name, msg_type in subscriptions:
            publishers = _ok(master.registerSubscriber(self.caller_id, name, msg_type, uri), name)
            # Connect to the publishers the new master knows (it tells us about later ones itself).
            node.publisherUpdate("/master", name, publishers)
        for name, service_uri in services:
            _ok(master.registerService(self.caller_id, name, service_uri, uri), name)


def _ok(reply: list, name: str) -> Any:
    code, message, value = reply
    if code != 1:
        raise rosgraph.MasterException(f"{name}: {message}")
    return value


__all__ = ["MasterWatch"]
