"""ROS adapters: executor node, proposition nodes, graph snapshots, transports.

Importing this package applies ``rospy_fixes`` (genpy's numpy import skipped at start-up, rospy's
XML-RPC thread ended at shutdown, no publisher lost when it registers with a subscriber at once, a
shutdown begun in another thread finished before the process exits, log lines that never ask the
master, an unregistration at shutdown that gives up on an unreachable master, no traceback from a publish
while the node shuts down) and turns on ``faulthandler``:
a node that crashes inside the interpreter or a C extension prints every thread's Python stack to
stderr (its log under roslaunch) instead of dying with a bare signal.
Every node of ours imports it before anything else of ROS.
"""
from __future__ import annotations

import atexit
import faulthandler
import sys

from ltl_stack import stdstreams  # noqa: F401 - a closed stdout or stderr is /dev/null from here on
from ltl_stack.ros import rospy_fixes

if not faulthandler.is_enabled():
    try:
        faulthandler.enable()
    except (AttributeError, ValueError, OSError, RuntimeError):
        pass  # stderr is not a file (a host that replaced or closed it): nothing to print to
rospy_fixes.skip_numpy_in_genpy()
atexit.register(rospy_fixes.finish_shutdown_at_exit)
rospy_fixes.when_imported("rosgraph.xmlrpc", lambda module: rospy_fixes.stop_serving_on_shutdown(module.XmlRpcNode))
rospy_fixes.when_imported("rospy", rospy_fixes.log_without_master)
rospy_fixes.when_imported("rospy.topics", lambda module: rospy_fixes.drop_publish_while_shutting_down(
    module._PublisherImpl, sys.modules["rospy.core"], sys.modules["rospy.exceptions"].ROSException))
rospy_fixes.when_imported("rospy.impl.registration",
                          lambda module: (rospy_fixes.merge_publisher_updates(module.RegManager),
                                          rospy_fixes.bound_unregistration(module.RegManager)))
