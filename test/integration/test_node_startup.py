"""How a node of ours starts and stops: genpy's optional numpy import is skipped at start-up (~80 ms
CPU per node) while numpy stays usable, and rospy's XML-RPC server thread ends at shutdown instead of
polling its closed socket until the process exits (ros/ros_comm#2238), and a subscriber connects to
every publisher named in the lists queued for it, also when a stale list is queued last, and a
shutdown that another thread began has ended before the process exits."""
from __future__ import annotations

import subprocess
import sys

CODE = """
import sys
import ltl_stack.ros.executor
print('numpy' in sys.modules)
import io
import numpy
from std_msgs.msg import Float64
buf = io.BytesIO()
Float64(numpy.float64(1.5)).serialize(buf)
msg = Float64()
msg.deserialize(buf.getvalue())
print(msg.data, numpy.__name__)
"""


def test_executor_start_up_does_not_import_numpy_which_stays_usable():
    proc = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["False", "1.5", "numpy"], proc.stdout


#: imported first by each probe below, and how it waits for a condition (at most ``timeout`` s)
PRELUDE = """
import sys, threading, time, traceback
import ltl_stack.ros
import rospy

def wait(condition, timeout):
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.05)
    return condition()
"""


def run_probe(code: str, env: dict, before: str = "") -> subprocess.CompletedProcess:
    """Run ``before + PRELUDE + code`` against the master of ``env``, which must exit 0."""
    proc = subprocess.run([sys.executable, "-c", before + PRELUDE + code], capture_output=True, text=True,
                          timeout=300, check=False, env=env)
    assert proc.returncode == 0, proc.stderr
    return proc


SHUTDOWN = """
def serving():
    return any("serve_forever" in "".join(traceback.format_stack(frame))
               for frame in sys._current_frames().values())

rospy.init_node("shutdown_probe", anonymous=True)
print(wait(serving, 120))
rospy.signal_shutdown("test")
print(wait(lambda: not serving(), 60))
"""


def test_the_xml_rpc_server_thread_ends_when_the_node_shuts_down(ros_master):
    proc = run_probe(SHUTDOWN, ros_master.env)
    assert proc.stdout.split() == ["True", "True"], (proc.stdout, proc.stderr)


STALE_LIST = """
from rospy.impl.registration import RegManager, get_registration_listeners
from std_msgs.msg import Bool

def manager():
    return next((m for m in get_registration_listeners().listeners if isinstance(m, RegManager)), None)

rospy.init_node("stale_list_probe", anonymous=True, disable_signals=True)
assert wait(lambda: manager() is not None and manager().is_registered(), 120), "never registered"
registration = manager()
publisher = rospy.Publisher("/stale/source", Bool, queue_size=1, latch=True)
publisher.publish(Bool(True))
received = threading.Event()
with registration.cond:  # nothing is taken off the queue until both lists are on it
    subscriber = rospy.Subscriber("/stale/source", Bool, lambda message: received.set())
    # registerSubscriber's reply, naming the publisher, is queued now; a stale list comes after it
    registration.publisher_update(subscriber.resolved_name, [])
print(received.wait(60))
rospy.signal_shutdown("done")
"""


def test_a_stale_publisher_list_queued_last_does_not_lose_the_publisher(ros_master):
    """The race behind a latched value that never arrived (a region sensor and sim_robot registering
    in the same millisecond): rospy acts only on the publisher list queued last for a topic."""
    proc = run_probe(STALE_LIST, ros_master.env)
    assert proc.stdout.split() == ["True"], (proc.stdout, proc.stderr)


#: an exit job registered before rospy's and ours, so it runs after both: is a thread still in
#: rospy's shutdown or in the XML-RPC server's loop?
AT_EXIT = """
import atexit, socketserver, sys

def still_shutting_down():
    codes = {sys.modules["rospy.core"].signal_shutdown.__code__, socketserver.BaseServer.serve_forever.__code__}
    def inside(frame):
        return frame is not None and (frame.f_code in codes or inside(frame.f_back))
    print(any(inside(frame) for frame in sys._current_frames().values()))

atexit.register(still_shutting_down)
"""

SHUTDOWN_FROM_A_THREAD = """
rospy.init_node("exit_probe", anonymous=True)
threading.Thread(target=rospy.signal_shutdown, args=("from a callback",), daemon=True).start()
print(wait(rospy.is_shutdown, 60))  # as rospy.spin, the main thread returns once the flag is up
"""


def test_a_shutdown_begun_in_another_thread_ends_before_the_process_exits(ros_master):
    """``proposition_monitor --count`` stops from its subscriber callback: the process exited while
    that thread was still in rospy's shutdown, and a thread waking during CPython's teardown can crash
    it (exit -11 once in ~2,000 runs)."""
    proc = run_probe(SHUTDOWN_FROM_A_THREAD, ros_master.env, before=AT_EXIT)
    assert proc.stdout.split() == ["True", "False"], (proc.stdout, proc.stderr)


def test_a_node_that_crashes_says_where_each_thread_was():
    code = "import os, signal, ltl_stack.ros, rospy\nos.kill(os.getpid(), signal.SIGSEGV)\n"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=False)
    assert proc.returncode == -11, proc.stderr
    assert "Fatal Python error: Segmentation fault" in proc.stderr and 'File "<string>", line 2' in proc.stderr, \
        proc.stderr
