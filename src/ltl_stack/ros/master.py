"""The ROS master a command-line tool talks to, and the graph names it is given, checked before
any node starts.

A malformed master URI (``--master-uri``, ``__master:=`` or ``$ROS_MASTER_URI``) and an illegal
topic or action name are user mistakes (exit 2, one line); a master that does not answer is
``Exit.NO_ROS`` (3). Used by ``controller_trace``, ``set_propositions``, ``proposition_monitor``,
``send_proposition_goal`` and ``analyze_graph --live``.
"""
from __future__ import annotations

import argparse
import http.client
import os
import socket
import time
import xmlrpc.client
from typing import Any
from urllib.parse import urlsplit
from xml.parsers.expat import ExpatError

import rosgraph
import rosgraph.masterapi
import rosgraph.names

from ltl_stack.errors import Exit, UserError

#: seconds one probe of the master may take (an unreachable host otherwise blocks for minutes)
PROBE_TIMEOUT = 2.0


def check_master_uri(uri: str, origin: str = "--master-uri") -> str:
    """``uri`` if it has the form ``http://HOST:PORT/``; else ``UserError`` (exit 2) naming ``origin``."""
    problem = ""
    try:
        parts = urlsplit(uri)
        port = parts.port
    except ValueError as e:  # a port that is not a number or out of range, a bad IPv6 literal
        problem, parts, port = str(e), None, None
    if not problem and parts is not None:
        if parts.scheme not in ("http", "https"):
            problem = "the scheme must be http"
        elif not parts.hostname:
            problem = "no host"
        elif port is None:
            problem = "no port"
    if problem:
        shown = uri if len(uri) <= 80 else uri[:77] + "..."
        raise UserError(f"{origin} {shown!r} is not a ROS master URI ({problem}; expected http://HOST:PORT/)")
    return uri


def master_uri(given: str | None = None) -> str:
    """The master to use: ``given`` (``--master-uri``), else ``__master:=`` or ``$ROS_MASTER_URI``
    (rospy's default when neither is set), checked by ``check_master_uri``. ``given`` is also put in
    the environment, so a rospy node started afterwards registers with the same master."""
    if given is not None:
        check_master_uri(given, "--master-uri")
        os.environ["ROS_MASTER_URI"] = given
        return given
    try:
        uri = rosgraph.get_master_uri()
    except ValueError as e:  # an empty __master:= remapping
        raise UserError(str(e)) from None
    origin = "ROS_MASTER_URI" if os.environ.get("ROS_MASTER_URI") == uri else "__master:="
    return check_master_uri(uri, origin)


#: Seconds any XML-RPC call our nodes make at run time may take (the master, or a node, across a
#: partition would otherwise hold the calling thread for as long as TCP retries).
CALL_TIMEOUT = 3.0


class TimedTransport(xmlrpc.client.Transport):
    """An XML-RPC transport whose connections time out after ``timeout`` seconds."""

    def __init__(self, timeout: float) -> None:
        super().__init__()
        self.timeout = timeout

    def make_connection(self, host: Any) -> http.client.HTTPConnection:
        connection = super().make_connection(host)
        connection.timeout = self.timeout  # used when it connects, and for every read
        return connection


def timed_proxy(uri: str, timeout: float = CALL_TIMEOUT) -> xmlrpc.client.ServerProxy:
    """An XML-RPC proxy of ``uri`` (the master's, a node's) whose calls fail with ``OSError`` after
    ``timeout`` seconds instead of blocking."""
    return xmlrpc.client.ServerProxy(uri, transport=TimedTransport(timeout))


#: Seconds a start-up read of parameters may take: far longer than any answer of a working master on
#: a loaded machine, bounded so that a master cut off at start-up is one line, not a hang.
STARTUP_TIMEOUT = 30.0


def master_call(method: str, *args: Any, caller: str | None = None, uri: str | None = None,
                timeout: float = CALL_TIMEOUT) -> Any:
    """One call of the master's XML-RPC API (``getSystemState``, ``getParam``, ...) as ``caller`` (this
    node by default) with ``timeout``: its value. A refusal (code != 1, e.g. an unset parameter) raises
    ``rosgraph.MasterException``; no answer within ``timeout`` raises ``OSError`` (``socket.timeout``)."""
    if caller is None:
        import rospy

        caller = rospy.get_name()
    code, message, value = getattr(timed_proxy(uri or rosgraph.get_master_uri(), timeout), method)(caller, *args)
    if code != 1:
        raise rosgraph.MasterException(f"{method}: {message}")
    return value


#: The parameters outside the node's private namespace it read (``read_param``), by resolved name:
#: ``MasterWatch`` sets them again on a restarted master that lacks them (a launch file's namespace
#: parameters are gone with the old master, and a node started later needs them too).
SHARED_READ: dict[str, Any] = {}


def read_param(name: str, default: Any = None, timeout: float = STARTUP_TIMEOUT) -> Any:
    """The parameter ``name`` (resolved as rospy does: ``~x`` private, ``x`` in the node's namespace),
    ``default`` when it is not set. A master that does not answer within ``timeout`` s is a
    ``UserError`` with ``Exit.NO_ROS`` (rospy's own ``get_param`` would wait for ever)."""
    import rospy

    resolved = rospy.resolve_name(name)
    try:
        value = master_call("getParam", resolved, timeout=timeout)
        if not resolved.startswith(rospy.get_name() + "/") and resolved != rospy.get_name() + "/":
            SHARED_READ[resolved] = value
        return value
    except rosgraph.MasterException:
        return default
    except (OSError, http.client.HTTPException, xmlrpc.client.Error) as err:
        raise UserError(f"cannot read {resolved} from the ROS master at {rosgraph.get_master_uri()} ({err})",
                        Exit.NO_ROS) from None


def private_params(timeout: float = STARTUP_TIMEOUT) -> dict[str, Any]:
    """Every ``~param`` of this node, in one call ({} when none is set); see ``read_param``."""
    value = read_param("~", {}, timeout)
    return value if isinstance(value, dict) else {}


def master_online(uri: str) -> bool:
    """True when a ROS master answers at ``uri`` within ``PROBE_TIMEOUT`` seconds.

    Asks ``hasParam``, which only a master serves: any rospy node's XML-RPC server also answers
    ``getPid`` (what ``Master.is_online`` asks) and ``getUri``, and rospy would then wait forever to
    register with it. Something that answers but is not a master is a ``UserError`` with ``Exit.NO_ROS``."""
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(PROBE_TIMEOUT)
    try:
        rosgraph.masterapi.Master("/ltl_stack_probe", master_uri=uri).hasParam("/run_id")
        return True
    except (xmlrpc.client.Fault, ExpatError, rosgraph.masterapi.Error, rosgraph.masterapi.Failure) as e:
        raise UserError(f"{uri} answers but is not a ROS master ({e}); is it a node's URI?", Exit.NO_ROS) from None
    except (OSError, http.client.HTTPException, xmlrpc.client.ProtocolError, rosgraph.masterapi.MasterException):
        return False
    finally:
        socket.setdefaulttimeout(previous)


def wait_for_master(uri: str, timeout: float) -> None:
    """Return once the master at ``uri`` answers; ``UserError`` with ``Exit.NO_ROS`` after ``timeout`` s."""
    end = time.monotonic() + timeout
    while not master_online(uri):
        if time.monotonic() >= end:
            raise UserError(f"no ROS master at {uri} (waited {timeout:g} s)", Exit.NO_ROS)
        time.sleep(0.1)


def init_node(name: str, **kwargs: Any) -> None:
    """``rospy.init_node``, which waits for the master as long as it takes. Stopped meanwhile (Ctrl-C,
    SIGTERM from roslaunch or a test), rospy raises ``ROSInitException`` with a traceback; here it is one
    ``UserError`` line naming the master, exit ``Exit.INTERRUPTED``. With ``_param:=`` arguments and no
    master rospy failed at once with ``ConnectionRefusedError``'s traceback; any failure to start is now
    one line, ``Exit.NO_ROS``."""
    import rospy

    try:
        rospy.init_node(name, **kwargs)
    except OSError as err:  # rospy sets the _param:= arguments on the master first: refused
        raise UserError(f"no ROS master at {rosgraph.get_master_uri()} ({err.strerror or err})", Exit.NO_ROS) from None
    except rospy.exceptions.ROSInitException as err:
        uri = rosgraph.get_master_uri()
        if rospy.core.is_shutdown():
            raise UserError(f"stopped while waiting for the ROS master at {uri}", Exit.INTERRUPTED) from None
        raise UserError(f"cannot start the node with the ROS master at {uri}: {err}", Exit.NO_ROS) from None


def ros_name(text: str) -> str:
    """Option type: a legal ROS graph name (topic, action); illegal ones are a usage error (exit 2)."""
    if not text or not rosgraph.names.is_legal_name(text):
        shown = text if len(text) <= 60 else text[:57] + "..."
        raise argparse.ArgumentTypeError(f"{shown!r} is not a legal ROS name (a letter, '/' or '~' first, "
                                         "then letters, digits, '_' and '/')")
    return text
