"""Every XML-RPC call of ours to the master has a timeout: a master that accepts the connection and
never answers (a host cut off mid-call, a starved master) gives a clear error, never a hang."""
from __future__ import annotations

import socket
import threading

import pytest
from helpers import wait_for

# Debian's ROS modules: the main run has them, the other Pythons' unit runs do not
rosgraph = pytest.importorskip("rosgraph")
pytest.importorskip("rospy")

from ltl_stack.errors import Exit, UserError  # noqa: E402
from ltl_stack.ros import graph_snapshot, live_channels, master  # noqa: E402


@pytest.fixture
def silent_master():
    """The URI of a TCP server that accepts connections and never says a word."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(16)
    accepted = []
    stop = threading.Event()

    def accept() -> None:
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                accepted.append(server.accept()[0])
            except OSError:
                pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.getsockname()[1]}/"
    stop.set()
    thread.join(30)
    for conn in accepted:
        conn.close()
    server.close()


def finishes(call):
    """Run ``call`` in a thread; wait (at most 60 s) for it to end; its exception (None: it returned)."""
    result = {}

    def run() -> None:
        try:
            call()
            result["error"] = None
        except BaseException as err:  # noqa: BLE001 - handed to the test
            result["error"] = err

    threading.Thread(target=run, daemon=True).start()
    wait_for(lambda: "error" in result, 60, "the call to end (no answer: its timeout)")
    return result["error"]


def test_a_master_call_without_an_answer_ends_with_an_oserror(silent_master):
    error = finishes(lambda: master.master_call("getSystemState", caller="/t", uri=silent_master, timeout=0.5))
    assert isinstance(error, OSError), error


def test_a_startup_parameter_read_without_an_answer_is_one_clear_error(silent_master, monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", silent_master)
    error = finishes(lambda: master.read_param("~rate", 10, timeout=0.5))
    assert isinstance(error, UserError) and error.code == Exit.NO_ROS, error
    assert "cannot read" in str(error) and "rate" in str(error) and silent_master in str(error)


def test_the_graph_tools_give_up_on_a_silent_master(silent_master):
    error = finishes(lambda: graph_snapshot.take_snapshot(silent_master, timeout=0.5))
    assert error is not None and getattr(error, "code", None) == Exit.NO_ROS, error
    error = finishes(lambda: live_channels.list_live_channels(silent_master, timeout=0.5))
    assert error is not None and getattr(error, "code", None) == Exit.NO_ROS, error


def test_a_refusal_is_a_master_exception(monkeypatch):
    class Refusing:
        def getParam(self, caller, name):  # noqa: N802 - the master API's name
            return [-1, f"Parameter [{name}] is not set", 0]

    monkeypatch.setattr(master, "timed_proxy", lambda uri, timeout=master.CALL_TIMEOUT: Refusing())
    with pytest.raises(rosgraph.MasterException, match="is not set"):
        master.master_call("getParam", "/x", caller="/t", uri="http://127.0.0.1:1/")
    assert master.read_param("/x", "fallback") == "fallback"
