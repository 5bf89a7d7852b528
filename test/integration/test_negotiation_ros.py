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


ROGUE = Path(__file__).with_name("negotiation_rogue.py")


def rogue(ros_master, *messages: dict, ns: str = "/elsewhere", name: str = "rogue"):
    proc = ros_master.run([sys.executable, str(ROGUE), "/t/Q/controller_executor/negotiate",
                           *[json.dumps(m) for m in messages], f"__ns:={ns}", f"__name:={name}"], name=f"rogue{ns.replace('/', '_')}")
    proc.wait_output('"done"', timeout=90)
    return [json.loads(line)["reply"] for line in proc.output().splitlines() if line.startswith('{"reply"')]


def test_a_rogue_node_cannot_abort_stall_or_use_up_a_negotiation(ros_master, tmp_path):
    """A node that is not P's negotiating node, posing as P (a FALSE offer, then two
    unrealizable statuses), is refused; P's own node name with a 1 MB offer, an offer declaring
    [INPUT], or garbled text: refused in one line each, nothing started. Then the real P negotiates
    with Q as if nothing had happened (4.8.1)."""
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), Q_MAP)
    q.wait_output('"ready"', timeout=60)
    offer = {"kind": "offer", "sender": "P", "session": "P->Q", "text": "[SYS_TRANS]\nFALSE\n"}
    status = {"kind": "status", "sender": "P", "session": "P->Q", "round": 1, "realizable": False}
    forged = rogue(ros_master, offer, status, {**status, "round": 2})
    assert [r["kind"] for r in forged] == ["abort"] * 3, forged
    assert all("not from /t/P/controller_executor" in r["reason"] for r in forged), forged
    posing = rogue(ros_master, {**offer, "text": "", "head": "[SYS_TRANS]\n", "repeat": "TRUE | x'\n",
                                "times": 100000},
                   {**offer, "text": "[INPUT]\nz\n[SYS_TRANS]\nz'\n"}, {**offer, "text": "[SYS_TRANS]\nx' &&& (\n"},
                   ns="/t/P", name="controller_executor")
    assert [r["kind"] for r in posing] == ["abort"] * 3, posing
    assert "bytes (at most 65536)" in posing[0]["reason"] and "declares [INPUT]" in posing[1]["reason"], posing
    assert "garbled" in posing[2]["reason"] and all("\n" not in r["reason"] for r in posing), posing
    assert not reports(q) or all(r["case"] == "FAILED" for r in reports(q)), reports(q)
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--inputs",
              '{"x_Q": false}', "--timeout", "20")
    wait_for(lambda: reports(p) and [r for r in reports(q) if r["case"] != "FAILED"], 90, "the real negotiation")
    assert reports(p)[0]["case"] == "BOTH_ADOPT", (p.output(), q.output())
    q.wait_output('"adopted": "Q"')
    log = q.output()
    assert "Traceback" not in log and log.count("refused so far") <= 10, log


def test_two_robots_that_start_at_once_reach_the_in_turn_outcome(ros_master, tmp_path):
    """P and Q both start negotiating with each other at the same moment; P (the name
    that sorts first) initiates, Q answers it; P->Q ends 4.8.1 on both, Q's own attempt FAILED."""
    q = start(ros_master, tmp_path, "initiator", "Q", q_spec(assumes=True), Q_MAP, "--peer", "P", "--inputs",
              '{"p_P": false}', "--start", '{"p_P": true}', "--timeout", "20")
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--inputs",
              '{"x_Q": false}', "--start", '{"x_Q": true}', "--timeout", "20")
    try:
        wait_for(lambda: [r for r in reports(p) if r["session"] == "P->Q"]
                 and [r for r in reports(q) if r["session"] == "P->Q"], 120, "the P->Q negotiation on both sides")
    except AssertionError as err:
        raise AssertionError(f"{err}\n{p.output()[-3000:]}\n{q.output()[-3000:]}") from None
    mine = [r for r in reports(p) if r["session"] == "P->Q"][0]
    theirs = [r for r in reports(q) if r["session"] == "P->Q"][0]
    assert mine["case"] == theirs["case"] == "BOTH_ADOPT", (p.output(), q.output())
    q.wait_output('"adopted": "Q"')
    p.wait_output('"adopted": "P"')
    own = wait_for(lambda: [r for r in reports(q) if r["session"] == "Q->P"], 120, "Q's own attempt")[0]
    assert own["case"] == "FAILED", own
    assert "Traceback" not in p.output() + q.output()


@pytest.mark.parametrize("broken", ["P", "Q"])
def test_an_unwritable_adopted_spec_on_either_side_fails_both(ros_master, tmp_path, broken):
    """Two-phase adoption over ROS. The adopted-spec file of one robot cannot be
    written (its folder is gone): both reports say FAILED, neither robot adopts, nothing is written;
    the responder keeps running its own controller."""
    paths = {r: tmp_path / f"out_{r}" / f"{r}.adopted.structuredslugs" for r in "PQ"}
    for r in "PQ":
        if r != broken:
            paths[r].parent.mkdir()
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), Q_MAP, "--adopted", str(paths["Q"]))
    q.wait_output('"ready"', timeout=60)
    p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--inputs",
              '{"x_Q": false}', "--timeout", "20", "--adopted", str(paths["P"]))
    wait_for(lambda: reports(p) and reports(q), 90, "both reports")
    rp, rq = reports(p)[0], reports(q)[0]
    assert rp["case"] == rq["case"] == "FAILED", (rp, rq)
    assert "cannot write its adopted specification" in rp["reason"] + rq["reason"], (rp, rq)
    assert '"adopted"' not in p.output() + q.output()
    assert not any(f for r in "PQ" if paths[r].parent.exists() for f in paths[r].parent.iterdir())
    assert q.running() and "Traceback" not in p.output() + q.output()


def start_dropping(ros_master, tmp_path, drops: str):
    """Q answers; P initiates with its transport dropping ``drops`` once (``LTL_STACK_TEST_DROP``)."""
    q = start(ros_master, tmp_path, "responder", "Q", q_spec(), Q_MAP)
    q.wait_output('"ready"', timeout=60)
    ros_master.env["LTL_STACK_TEST_DROP"] = drops
    try:
        p = start(ros_master, tmp_path, "initiator", "P", p_spec(), P_MAP, "--peer", "Q", "--inputs",
                  '{"x_Q": false}', "--timeout", "4")
    finally:
        del ros_master.env["LTL_STACK_TEST_DROP"]
    return p, q


def test_a_lost_confirmation_is_reported_truthfully_and_converges(ros_master, tmp_path):
    """Commit protocol: P decided and adopted, Q adopted on the decision, Q's confirmation is lost. P
    says so (not 4.8.1) and sends its decision again: then both reports say 4.8.1."""
    p, q = start_dropping(ros_master, tmp_path, "reply:commit")
    wait_for(lambda: reports(p) and reports(q), 60, "both reports")
    assert reports(p)[0]["case"] == "UNCONFIRMED", reports(p)
    assert reports(q)[0]["case"] == "BOTH_ADOPT", reports(q)
    q.wait_output('"adopted": "Q"')
    wait_for(lambda: reports(p)[-1]["case"] == "BOTH_ADOPT", 60, "P's decision confirmed")
    assert "Traceback" not in p.output() + q.output()


def test_a_lost_status_2_leaves_both_on_their_old_controllers(ros_master, tmp_path):
    """Q is prepared (both statuses 2 realizable); its status 2 never reaches P: P decides not to adopt
    and tells Q; neither adopts, both report FAILED."""
    p, q = start_dropping(ros_master, tmp_path, "reply:status:2")
    wait_for(lambda: reports(p) and reports(q), 60, "both reports")
    assert reports(p)[0]["case"] == reports(q)[0]["case"] == "FAILED", (reports(p), reports(q))
    assert '"adopted"' not in p.output() + q.output()


def test_a_lost_decision_is_asked_for_again(ros_master, tmp_path):
    """P's decision (commit) never reaches Q: Q stays prepared (its report has no outcome, it adopted
    nothing) and asks P for the session's outcome; then Q adopts and P's decision is confirmed."""
    p, q = start_dropping(ros_master, tmp_path, "request:commit")
    wait_for(lambda: reports(p), 60, "P's report")
    assert reports(p)[0]["case"] == "UNCONFIRMED", reports(p)
    wait_for(lambda: reports(q) and reports(p)[-1]["case"] == "BOTH_ADOPT", 60, "Q adopting on the decision")
    assert reports(q)[-1]["case"] == "BOTH_ADOPT"
    q.wait_output('"adopted": "Q"')


OWN_P_MAP = ("negotiation:\n  robot: P\n  peers:\n    Q:\n      eap: {road_c_Q: road_c, dig_c_Q: dig_c, s_Q: s}\n"
             "      shares: {}\n")
OWN_Q_MAP = "negotiation:\n  robot: Q\n  peers:\n    P:\n      shares: {road_c: road_c_Q, dig_c: dig_c_Q, s: s_Q}\n"


@pytest.mark.parametrize("assumption, cases, received", [
    # over Q's completion sensors, whose rewrite onto activations would not keep it: kept as sent, 4.8.1
    ("!(road_c_Q' & dig_c_Q')", ("BOTH_ADOPT", "BOTH_ADOPT"), "kept as sent"),
    # over a sensor Q does not control: Q cannot guarantee it, 4.8.2 (never an adoption of it)
    ("!s_Q'", ("ADOPTED_PEERS", "KEPT_OWN"), "kept as sent"),
])
def test_ownership_of_received_clauses_over_ros(ros_master, tmp_path, assumption, cases, received):
    from test_negotiation_ownership import LAG, Q_TEXT, p_text

    q = start(ros_master, tmp_path, "responder", "Q", Q_TEXT.format(env=LAG), OWN_Q_MAP)
    q.wait_output('"ready"', timeout=60)
    p = start(ros_master, tmp_path, "initiator", "P", p_text(assumption), OWN_P_MAP, "--peer", "Q", "--timeout", "20")
    wait_for(lambda: reports(p) and reports(q), 60, "both reports")
    rp, rq = reports(p)[-1], reports(q)[-1]
    assert (rp["case"], rq["case"]) == cases, (rp, rq)
    assert any(received in line for line in rq["received"]), rq["received"]
