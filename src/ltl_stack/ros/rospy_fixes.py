"""Work-arounds for rospy/genpy behaviour that costs our nodes time or messages (Noetic, unfixed).

Applied by ``import ltl_stack.ros``, which every node of ours does before anything else of ROS:

- **Start-up time**: ``genpy.message``, which every message class and ``rospy`` import, tries
  ``import numpy`` only to list numpy's scalar types among the values a float field accepts when it
  words a serialization error; with the venv's numpy that costs ~80 ms CPU in every node, and none
  of our nodes puts numpy values into messages. numpy is marked absent while genpy is first imported
  (a ``None`` entry in ``sys.modules`` makes an import fail, documented behaviour, and genpy catches
  the ImportError) and the mark is taken out right after: a later ``import numpy`` works as usual,
  and ``struct`` still packs numpy floats into float fields.
- **Shutdown** (ros/ros_comm#2238): rospy's shutdown closes the socket of the node's XML-RPC server
  but never asks ``serve_forever`` to return, so that thread polls the closed socket in a busy loop
  until the process ends. rospy then waits up to 0.5 s more for its registration thread (woken only
  before the shutdown flag is raised) and sleeps 0.1 s: each node burnt ~0.5 s of a core on every
  stop, and a scenario stops dozens at once. ``XmlRpcNode.shutdown`` now also ends ``serve_forever``
  (``socketserver``'s public ``shutdown``, from a daemon thread because it blocks until the loop has
  seen it; the socket is shut down first, which wakes the loop's select at once) and wakes the
  registration thread again.
- **A lost publisher** (publisher and subscriber registering at the same moment): rospy's
  registration thread keeps a queue of publisher lists per topic and, for a topic, acts only on the
  list queued last. The list that ``registerSubscriber`` returned is queued after the master's reply
  arrives, so a ``publisherUpdate`` naming a publisher that registered meanwhile can be queued first
  and then dropped: the subscriber never connects, and a latched value never arrives. Queued lists
  of a topic are now merged, so every publisher named in any of them is connected to (rospy only
  connects from these lists, never disconnects; a publisher that has gone just fails to connect).
- **A crash at exit** (exit -11 once in ~2,000 runs of ``proposition_monitor --count 1``): when a
  thread other than the main one starts rospy's shutdown (a subscriber callback, the master asking
  the node to stop), ``rospy.spin`` returns as soon as the shutdown flag is raised, and the process
  begins to exit while that thread still runs the shutdown hooks, joins rospy's threads and sleeps
  0.1 s. A thread that wakes while CPython tears the interpreter down can crash it (python/cpython
  gh-110052, gh-127893). An exit job, registered when ``ltl_stack.ros`` is
  imported, makes the main thread wait, at most 10 s, until no other thread is inside
  ``rospy.core.signal_shutdown`` and those loops have returned.
- **Logging asks the master** (ros/ros_comm#2337): every ``rospy.log*`` call that reaches /rosout
  reads ``/rosout_disable_topics_generation`` with ``rospy.get_param_cached``, which caches only
  parameters that are set: while it is unset (always, unless someone sets it) each log line is an
  XML-RPC call to the master, and with the master unreachable it blocks for as long as TCP tries —
  under the executor's controller lock, in a sensor's callback. The flag is now asked once, in a
  daemon thread of its own, and its answer kept; until it comes (and if it never does) log lines
  list their topics, rospy's default. A master restart changes nothing: nothing is asked again.
- **Stopping without a master**: on shutdown rospy unregisters the node's topics and services from the
  master in one XML-RPC call without a timeout (``RegManager.cleanup``); with the master cut off it
  held the process for as long as TCP tries (minutes): a node that gave up reading its parameters
  (one error line) did not exit. The call now runs in a daemon thread of its own, waited for at most
  ``UNREGISTER_TIMEOUT`` s; a master that does not answer by then has lost the node anyway.
- **A publish while shutting down raises**: rospy closes every topic in a *pre*-shutdown hook (its
  registration cleanup), before it raises the shutdown flag, and a publish to a closed topic raises
  ``ROSException`` unless that flag is up. A timer or a thread of ours that publishes in that window
  (a proposition republished, a heartbeat) died with a traceback in the node's output. Such a
  publish is now dropped silently, as rospy drops it a moment later: only a topic closed while no
  shutdown is under way still raises.
"""
from __future__ import annotations

import importlib.abc
import importlib.util
import socket
import sys
import threading
import time
from collections.abc import Callable


def skip_numpy_in_genpy() -> None:
    """Import ``genpy.message`` with numpy hidden (see the module docstring)."""
    hide = "numpy" not in sys.modules and "genpy.message" not in sys.modules
    if hide:
        sys.modules["numpy"] = None  # type: ignore[assignment]
    try:
        import genpy.message  # noqa: F401 - imported here, before rospy, for the reason above
    except ImportError:
        pass  # no ROS here: nothing to speed up (the ROS-free parts of ltl_stack.sim import this package)
    finally:
        if hide and sys.modules.get("numpy", False) is None:
            del sys.modules["numpy"]


def _replace(cls: type, name: str, make: Callable[[Callable], Callable]) -> None:
    """Replace method ``name`` of ``cls`` by ``make(original)``, once (a second call leaves it)."""
    original = getattr(cls, name)
    if getattr(original, "ltl_stack_fix", False):
        return
    replacement = make(original)
    replacement.ltl_stack_fix = True
    replacement.__doc__ = original.__doc__
    setattr(cls, name, replacement)


#: the threads ``stop_serving_on_shutdown`` started, each until its server loop has returned
_stoppers: list[threading.Thread] = []


def stop_serving_on_shutdown(node_class: type) -> None:
    """Make rosgraph's ``XmlRpcNode.shutdown`` end its server thread and wake rospy's registration thread."""

    def make(close: Callable) -> Callable:
        def shutdown(self, reason):
            server, handler = self.server, self.handler
            self.is_shutdown = True  # as ``close`` does first: else rosgraph's loop would serve again
            if server is not None:
                stopper = threading.Thread(target=server.shutdown, name="xmlrpc_stop", daemon=True)
                _stoppers.append(stopper)
                stopper.start()
                try:  # wakes the loop's select now: once closed, its socket's number may be reused
                    server.socket.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
            close(self, reason)
            registration = getattr(handler, "reg_man", None)
            if registration is not None and registration.cond is not None:
                with registration.cond:
                    registration.cond.notify_all()
        return shutdown

    _replace(node_class, "shutdown", make)


#: Seconds a stopping node waits for the master to take its unregistration.
UNREGISTER_TIMEOUT = 3.0


def bound_unregistration(manager_class: type, timeout: float = UNREGISTER_TIMEOUT) -> None:
    """Make rospy's ``RegManager.cleanup`` return after ``timeout`` s even if the master never answers."""

    def make(cleanup: Callable) -> Callable:
        def bounded_cleanup(self, reason):
            worker = threading.Thread(target=cleanup, args=(self, reason), name="unregister", daemon=True)
            worker.start()
            worker.join(timeout)
        return bounded_cleanup

    _replace(manager_class, "cleanup", make)


def drop_publish_while_shutting_down(impl_class: type, core: object, closed_error: type) -> None:
    """Make rospy's ``_PublisherImpl.publish`` drop a message to a topic closed by the shutdown under way
    (``core`` is ``rospy.core``: its ``is_shutdown_requested`` is up from the first shutdown hook on;
    ``closed_error`` is ``rospy.exceptions.ROSException``, what a publish to a closed topic raises)."""

    def make(publish: Callable) -> Callable:
        def drop_if_shutting_down(self, message, connection_override=None):
            try:
                return publish(self, message, connection_override)
            except closed_error:
                if self.closed and (core.is_shutdown_requested() or core.is_shutdown()):
                    return False
                raise
        return drop_if_shutting_down

    _replace(impl_class, "publish", make)


def merge_publisher_updates(manager_class: type) -> None:
    """Make rospy's ``RegManager.publisher_update`` keep the publishers of lists still queued for the topic."""

    def make(queue: Callable) -> Callable:
        def publisher_update(self, resolved_name, uris):
            with self.cond:  # a Condition on an RLock: ``queue`` takes it again
                pending = [uri for topic, listed in self.updates if topic == resolved_name for uri in listed]
                queue(self, resolved_name, list(dict.fromkeys([*uris, *pending])))
        return publisher_update

    _replace(manager_class, "publisher_update", make)


def _inside(frame, code) -> bool:
    while frame is not None:
        if frame.f_code is code:
            return True
        frame = frame.f_back
    return False


def finish_shutdown_at_exit(timeout: float = 10.0) -> None:
    """Exit job: end rospy's shutdown before Python tears the interpreter down (see the docstring).

    Starts it here if nobody did (rospy's own exit job would, in whichever order the two run), then
    waits, at most ``timeout`` s in all, while another thread is still in ``signal_shutdown`` and
    until the XML-RPC server loops asked to stop have returned.
    """
    core = sys.modules.get("rospy.core")
    if core is None:
        return
    if not (core.is_shutdown_requested() or core.is_shutdown()):
        core.signal_shutdown("atexit")  # it logs first: never once the program's log files are gone
    deadline = time.monotonic() + timeout
    code, me = core.signal_shutdown.__code__, threading.get_ident()
    while time.monotonic() < deadline and any(
            ident != me and _inside(frame, code) for ident, frame in sys._current_frames().items()):
        time.sleep(0.01)
    for stopper in list(_stoppers):
        stopper.join(max(0.0, deadline - time.monotonic()))


#: the parameter rospy's /rosout handler reads on every log line
ROSOUT_FLAG = "/rosout_disable_topics_generation"


def log_without_master(rospy_module: object) -> None:
    """Make ``rospy.get_param_cached(ROSOUT_FLAG)`` never block (see the module docstring); other
    parameters are read as before."""
    original = getattr(rospy_module, "get_param_cached", None)
    if original is None or getattr(original, "ltl_stack_fixed", False):
        return  # no rospy here (marked absent), or already fixed
    known = {"value": False, "asked": False}
    lock = threading.Lock()

    def ask() -> None:
        try:
            known["value"] = bool(original(ROSOUT_FLAG, False))
        except Exception:  # noqa: BLE001 - no master, no node yet: keep rospy's default
            pass

    def get_param_cached(param_name, *default):
        if param_name != ROSOUT_FLAG:
            return original(param_name, *default)
        with lock:
            first, known["asked"] = not known["asked"], True
        if first:
            threading.Thread(target=ask, name="rosout_flag", daemon=True).start()
        return known["value"]

    get_param_cached.ltl_stack_fixed = True  # type: ignore[attr-defined]
    rospy_module.get_param_cached = get_param_cached


class AfterImport(importlib.abc.MetaPathFinder):
    """Calls ``then(module)`` right after module ``name`` is first imported, by whoever imports it.

    So a fix for rospy's internals costs nothing in a process that never imports rospy (a
    command-line tool that only talks to the master), and still precedes ``rospy.init_node``.
    """

    def __init__(self, name: str, then: Callable[[object], None]):
        self.name, self.then = name, then

    def find_spec(self, fullname, path, target=None):
        if fullname != self.name:
            return None
        # a new list, not ``remove``: another thread may be going through the old one
        sys.meta_path = [finder for finder in sys.meta_path if finder is not self]
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        load, then = spec.loader.exec_module, self.then

        def exec_module(module):
            load(module)
            then(module)

        spec.loader.exec_module = exec_module
        return spec


def when_imported(name: str, then: Callable[[object], None]) -> None:
    """``then(module)`` now if ``name`` is already imported, else right after it is."""
    if name in sys.modules:
        then(sys.modules[name])
    else:
        sys.meta_path = [AfterImport(name, then), *sys.meta_path]
