"""ROS adapters: executor node, proposition nodes, graph snapshots, transports.

Start-up (issue 16): ``genpy.message``, which every message class and ``rospy`` import, tries
``import numpy`` only to list numpy's scalar types among the values a float field accepts when it
words a serialization error; with the venv's numpy that import costs ~80 ms CPU in every node, and
none of our nodes puts numpy values into messages. So numpy is marked absent while genpy is first
imported here (a ``None`` entry in ``sys.modules`` makes an import fail, documented behaviour, and
genpy catches the ImportError) and the mark is taken out right after: a later ``import numpy``
works as usual, and ``struct`` still packs numpy floats into float fields.

Shutdown (ros/ros_comm#2238, never fixed in Noetic): rospy's shutdown closes the socket of the
node's XML-RPC server but never asks ``serve_forever`` to return, so that thread polls the closed
socket in a busy loop until the process ends. rospy then waits up to 0.5 s more for its registration
thread (woken only before the shutdown flag is raised) and sleeps 0.1 s: each node burnt ~0.5 s of a
core on every stop, and a scenario stops dozens of nodes at once. ``_stop_serving_on_shutdown`` makes
``XmlRpcNode.shutdown`` also end ``serve_forever`` (``socketserver``'s public ``shutdown``, from a
daemon thread because it blocks until the loop has seen it) and wake the registration thread again.
"""
from __future__ import annotations

import sys
import threading

_HIDE_NUMPY = "numpy" not in sys.modules and "genpy.message" not in sys.modules
if _HIDE_NUMPY:
    sys.modules["numpy"] = None  # type: ignore[assignment]
try:
    import genpy.message  # noqa: F401 - imported here, before rospy, for the reason above
except ImportError:
    pass  # no ROS here: nothing to speed up (the ROS-free parts of ltl_stack.sim import this package)
finally:
    if _HIDE_NUMPY and sys.modules.get("numpy", False) is None:
        del sys.modules["numpy"]
try:
    from rosgraph.xmlrpc import XmlRpcNode
except ImportError:
    XmlRpcNode = None


def _stop_serving_on_shutdown() -> None:
    """Make rospy's XML-RPC server thread end at shutdown instead of spinning (see above)."""
    if XmlRpcNode is None or getattr(XmlRpcNode.shutdown, "ends_serving", False):
        return
    close = XmlRpcNode.shutdown

    def shutdown(self, reason):
        server, handler = self.server, self.handler
        close(self, reason)
        registration = getattr(handler, "reg_man", None)
        if registration is not None and registration.cond is not None:
            with registration.cond:
                registration.cond.notify_all()
        if server is not None:
            threading.Thread(target=server.shutdown, name="xmlrpc_stop", daemon=True).start()

    shutdown.ends_serving = True
    shutdown.__doc__ = close.__doc__
    XmlRpcNode.shutdown = shutdown


_stop_serving_on_shutdown()
