"""Integrative negotiation over a real master (thesis §4.8, Alg. 4): two nodes exchange their
messages through the ``ltl_stack/Negotiate`` service of ``ros.negotiation``; outcomes 4.8.1, 4.8.2
(only one robot can incorporate) and 4.8.3 (neither can: both abort), a peer that is not there and a
peer that never answers (both safe, nothing adopted)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from helpers import wait_for

pytestmark = pytest.mark.ros

PARTY = Path(__file__).with_name("negotiation_party.py")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "unit" / "runtime"))
from test_negotiation import p_spec, q_spec  # noqa: E402

P_MAP = "negotiation:\n  robot: P\n  peers:\n    Q:\n      eap: {x_Q: x}\n      shares: {p: p_P}\n"
Q_MAP = "negotiation:\n  robot: Q\n  peers:\n    P:\n      eap: {p_P: p}\n      shares: {x: x_Q}\n"


def reports(proc) -> list[dict]:
    return [json.loads(line)["report"] for line in proc.output().splitlines() if line.startswith('{"report"')]


def start(ros_master, tmp_path, role, robot, spec_text, mapping_text, *extra):
    spec = tmp_path / f"{robot}.structuredslugs"
    spec.write_text(spec_text)
    mapping = tmp_path / f"{robot}.yaml"
    mapping.write_text(mapping_text)
    proc = ros_master.run([sys.executable, str(PARTY), role, str(spec), str(mapping), *extra, f"__ns:=/t/{robot}"],
                          name=f"{role}-{robot}")
    return proc


def negotiate(ros_master, tmp_path, p_text, q_text, *, outputs="{}", q_inputs="{}"):
    q = start(ros_master, tmp_path, "responder", "Q", q_text, Q_MAP, "--inputs", q_inputs)
    q.wait_output('"ready"', timeout=60)
    p = start(ros_master, tmp_path, "initiator", "P", p_text, P_MAP, "--peer", "Q", "--inputs",
              '{"x_Q": false}', "--outputs", outputs, "--timeout", "20")
    wait_for(lambda: reports(p) and reports(q), 60, "both reports")
    return p, q, reports(p)[0], reports(q)[0]


def test_both_adopt_over_ros(ros_master, tmp_path):
    p, q, rp, rq = negotiate(ros_master, tmp_path, p_spec(), q_spec())
    assert rp["case"] == rq["case"] == "BOTH_ADOPT", (p.output(), q.output())
    assert rp["session"] == rq["session"] == "P->Q"
    assert rq["received"][0] == "assumption of P: always next x" and rp["sent"][0].endswith("always next x")
    q.wait_output('"adopted": "Q"')
    assert "Traceback" not in p.output() + q.output()


def test_only_one_incorporates_4_8_2_over_ros(ros_master, tmp_path):
    p, q, rp, rq = negotiate(ros_master, tmp_path, p_spec(), q_spec(refuses=True))
    assert (rp["case"], rq["case"]) == ("ADOPTED_PEERS", "KEPT_OWN"), (p.output(), q.output())
    q.wait_output('"adopted": "Q"')


def test_neither_incorporates_4_8_3_over_ros(ros_master, tmp_path):
    p, q, rp, rq = negotiate(ros_master, tmp_path, p_spec(refuses=True), q_spec(refuses=True, assumes=True),
                                 q_inputs='{"p_P": true}')
    assert rp["case"] == rq["case"] == "BOTH_ABORT", (p.output(), q.output())
    assert "unrealizable" in rp["explanation"] and "unrealizable" in rq["explanation"]
    assert '"adopted"' not in p.output() + q.output()


def test_a_peer_that_is_not_there_fails_safely(ros_master, tmp_path):
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--timeout", "1")
    wait_for(lambda: reports(p), 60, "the report")
    report = reports(p)[0]
    assert report["case"] == "FAILED" and "/t/Q/controller_executor/negotiate" in report["reason"], report
    assert '"adopted"' not in p.output()


def test_a_peer_that_never_answers_fails_safely(ros_master, tmp_path):
    q = start(ros_master, tmp_path, "silent", "Q", q_spec(), Q_MAP)
    q.wait_output('"ready"', timeout=60)
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--timeout", "2")
    wait_for(lambda: reports(p), 60, "the report")
    report = reports(p)[0]
    assert report["case"] == "FAILED" and "no answer within 2 s" in report["reason"], report
    assert '"adopted"' not in p.output()
