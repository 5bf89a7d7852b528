"""Only real peers negotiate (docs/negotiation.md, "Authentication"), on a real master: a raw TCPROS
client that puts P's node name in its ``callerid`` (no node, nothing at the master) against a robot with
and without a fleet secret, and a ``registerService`` call that takes over a robot's ``~negotiate``."""
from __future__ import annotations

import dataclasses
import os
import sys
import xmlrpc.client
from pathlib import Path

import pytest
from helpers import wait_for
from tcpros_forger import forge
from test_executor_node import Probe
from test_negotiation_ros import P_MAP, Q_MAP, reports, start

from ltl_stack.ros.negotiation import from_ros, to_ros
from ltl_stack.runtime.resilience.negotiation import Message
from ltl_stack.runtime.resilience.negotiation.auth import Authenticator

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "unit" / "runtime"))
from test_negotiation import p_spec, q_spec  # noqa: E402

pytestmark = pytest.mark.ros

SECRET = b"a fleet secret of more than sixteen bytes"
SERVICE = "/t/Q/controller_executor/negotiate"
P_NODE = "/t/P/controller_executor"
FORGED = Message("offer", "P", "P->Q", 0, "[SYS_TRANS]\nFALSE\n")


def secret_file(tmp_path: Path, mode: int = 0o600) -> Path:
    path = tmp_path / "fleet.key"
    path.write_bytes(SECRET)
    path.chmod(mode)
    return path


def with_secret(mapping: str, path: Path) -> str:
    return mapping.replace("negotiation:\n", f"negotiation:\n  secret_file: {path}\n", 1)


def send(ros_master, message: Message) -> Message:
    return from_ros(forge(ros_master.env["ROS_MASTER_URI"], SERVICE, to_ros(message), callerid=P_NODE))


def test_with_a_secret_forged_messages_are_refused_and_use_nothing_up(ros_master, tmp_path):
    key = secret_file(tmp_path)
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), with_secret(Q_MAP, key))
    q.wait_output('"ready"', timeout=60)
    assert "negotiation is unauthenticated" not in q.output()
    # unsigned, under P's node name (the caller id check alone would take it)
    unsigned = send(ros_master, FORGED)
    assert unsigned.kind == "abort" and unsigned.reason == "refused: unsigned message for P", unsigned
    # signed with another secret; then a real signature on a changed text
    wrong = Authenticator("P", {"Q": b"not the fleet secret, but long enough"}).sign(FORGED, "Q")
    assert send(ros_master, wrong).reason == "refused: wrongly signed message for P"
    fleet = Authenticator("P", {"Q": SECRET})
    tampered = dataclasses.replace(fleet.sign(Message("status", "P", "P->Q", 1), "Q"), realizable=True)
    assert send(ros_master, tampered).reason == "refused: wrongly signed message for P"
    # a message that was accepted once (signed; a status with no negotiation, answered with an abort)
    # cannot be sent again
    once = fleet.sign(Message("status", "P", "P->Q", 1), "Q")
    first = send(ros_master, once)
    assert first.kind == "abort" and "no negotiation with P in progress" in first.reason, first
    assert send(ros_master, once).reason == "refused: replayed message for P"
    log = q.output()
    assert all(f"~negotiate: {why}" in log for why in ("unsigned message for P", "wrongly signed message for P",
                                                       "replayed message for P")), log
    assert not reports(q), reports(q)
    # the real P, which holds the secret, negotiates as if nothing had happened (4.8.1)
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), with_secret(P_MAP, key), "--peer", "Q",
              "--inputs", '{"x_Q": false}', "--timeout", "20")
    wait_for(lambda: reports(p) and reports(q), 90, "the real negotiation")
    assert reports(p)[0]["case"] == reports(q)[0]["case"] == "BOTH_ADOPT", (p.output(), q.output())
    assert "Traceback" not in p.output() + q.output()


def test_a_peer_without_the_secret_gets_nothing_and_a_readable_secret_is_refused(ros_master, tmp_path):
    key = secret_file(tmp_path)
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), with_secret(Q_MAP, key))
    q.wait_output('"ready"', timeout=60)
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--inputs",
              '{"x_Q": false}', "--timeout", "20")
    wait_for(lambda: reports(p), 90, "P's report")
    assert reports(p)[0]["case"] == "FAILED" and "unsigned message for P" in reports(p)[0]["reason"], reports(p)
    assert '"adopted"' not in p.output() + q.output() and not reports(q)
    os.chmod(key, 0o640)
    bad = start(ros_master, tmp_path, "responder", "R", q_spec(), with_secret(Q_MAP, key).replace("robot: Q", "robot: R"))
    wait_for(lambda: not bad.running(), 60, "the robot with a readable secret to stop")
    assert "accessible to group or others (mode 0640)" in bad.output(), bad.output()


def test_without_a_secret_the_robot_says_once_that_negotiation_is_unauthenticated(ros_master, tmp_path):
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), Q_MAP)
    q.wait_output('"ready"', timeout=60)
    assert q.output().count("negotiation is unauthenticated") == 1, q.output()
    # the threat it names: a forged caller id passes the caller id check (docs/negotiation.md)
    reply = send(ros_master, Message("status", "P", "P->Q", 1))
    assert "no negotiation with P in progress" in reply.reason, reply


def test_a_hijacked_negotiate_service_is_reported_and_registered_again(ros_master, tmp_path):
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), Q_MAP)
    q.wait_output('"ready"', timeout=60)
    probe = Probe(ros_master, tmp_path, ["diag:/diagnostics"])
    try:
        master = xmlrpc.client.ServerProxy(ros_master.env["ROS_MASTER_URI"])
        own = master.lookupService("/test", SERVICE)[2]
        assert master.registerService("/attacker", SERVICE, "rosrpc://127.0.0.1:9", "http://127.0.0.1:9/")[0] == 1
        wait_for(lambda: [d for d in probe.of("diag", level=2) if d["name"].endswith("negotiate registration")],
                 60, "an ERROR status for the hijack")
        wait_for(lambda: master.lookupService("/test", SERVICE)[2] == own, 60, "Q's service registered again")
        error = [d for d in probe.of("diag", level=2) if d["name"].endswith("negotiate registration")][0]
        assert "rosrpc://127.0.0.1:9" in error["message"] and "registered it again" in error["message"], error
        assert "registered it again" in q.output()
    finally:
        probe.stop()
