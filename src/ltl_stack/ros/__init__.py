"""ROS adapters: executor node, proposition nodes, graph snapshots, transports.

Importing this package applies ``rospy_fixes`` (genpy's numpy import skipped at start-up, rospy's
XML-RPC thread ended at shutdown, no publisher lost when it registers with a subscriber at once).
Every node of ours imports it before anything else of ROS.
"""
from __future__ import annotations

from ltl_stack.ros import rospy_fixes

rospy_fixes.skip_numpy_in_genpy()
rospy_fixes.when_imported("rosgraph.xmlrpc", lambda module: rospy_fixes.stop_serving_on_shutdown(module.XmlRpcNode))
rospy_fixes.when_imported("rospy.impl.registration",
                          lambda module: rospy_fixes.merge_publisher_updates(module.RegManager))
