"""Integrative negotiation without ROS (thesis §4.8, Alg. 4): two in-process parties, every outcome
(4.8.1, 4.8.2, 4.8.3, line 20) and every fault (timeout, vanished peer, garbled text, out of order,
once per pair), and the invariant that nobody adopts without a realizable spec and the peer's status."""
from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.runtime.config.mapping import MappingError, parse_mapping
from ltl_stack.runtime.resilience.negotiation import (
    OFFER,
    STATUS,
    Classes,
    Message,
    Negotiation,
    NegotiationError,
    Negotiator,
    Outcome,
    Peer,
    answer,
    assumptions_about,
    classes_from_data,
    classes_from_mapping,
    drive,
    negotiation_classes,
    report_lines,
)
from ltl_stack.spec import parse_structured
from ltl_stack.synthesis import synthesize

# P observes Q's output x as its input x_Q; Q observes P's output p as its input p_P.
P_CLASSES = Classes("P", {"Q": Peer("Q", eap={"x_Q": "x"}, shares={"p": "p_P"})})
Q_CLASSES = Classes("Q", {"P": Peer("P", eap={"p_P": "p"}, shares={"x": "x_Q"})})


def p_spec(*, refuses: bool = False, stuck: bool = False) -> str:
    """P assumes Q does x; its goal is p. ``refuses``: P never does p (cannot incorporate Q's
    assumption that it does). ``stuck``: a latch q that, once set, never clears, and a goal !q."""
    return f"""
[INPUT]
x_Q
[OUTPUT]
p
q
[ENV_INIT]
x_Q
[SYS_INIT]
!p & !q
[ENV_TRANS]
x_Q'
[SYS_TRANS]
{"!p'" if refuses else "TRUE"}
{"q -> q'" if stuck else "TRUE"}
[SYS_LIVENESS]
{"!q" if stuck else "TRUE"}
"""


def q_spec(*, refuses: bool = False, assumes: bool = False) -> str:
    """Q may do x; ``refuses``: it never does (cannot incorporate P's assumption); ``assumes``: Q
    assumes P does p."""
    return f"""
[INPUT]
p_P
[OUTPUT]
x
[ENV_INIT]
{"p_P" if assumes else "TRUE"}
[SYS_INIT]
!x
[ENV_TRANS]
{"p_P'" if assumes else "TRUE"}
[SYS_TRANS]
{"!x'" if refuses else "TRUE"}
"""


def pair(p_text: str, q_text: str, *, p_outputs: dict | None = None):
    p = parse_structured(p_text, "P.structuredslugs")
    q = parse_structured(q_text, "Q.structuredslugs")
    init_q = {"p_P": "p_P'" in q_text}
    a = Negotiation(p, P_CLASSES, "Q", incoming={"x_Q": False}, outputs=p_outputs or {"p": False, "q": False},
                    initiator=True)
    b = Negotiation(q, Q_CLASSES, "P", incoming=init_q, outputs={"x": False}, initiator=False)
    return a, b


def direct(b: Negotiation):
    return lambda message: answer(b, message)


def test_assumptions_about_a_peer_are_the_env_safety_clauses_with_its_eap():
    spec = parse_structured(p_spec(), "P")
    assert [c.text.strip() for c in assumptions_about(spec, P_CLASSES, "Q")] == ["x_Q'"]
    assert assumptions_about(parse_structured(q_spec(), "Q"), Q_CLASSES, "P") == []


def test_both_adopt_4_8_1_and_the_received_assumption_is_guaranteed():
    a, b = pair(p_spec(), q_spec())
    drive(a, direct(b))
    assert a.outcome is b.outcome is Outcome.BOTH_ADOPT
    assert a.adopted.incorporated and b.adopted.incorporated
    # Q now guarantees x (P's assumption, renamed into Q's names) and assumes P's goal (none here)
    assert any(c.text.strip() == "x'" for c in b.adopted.spec.sys_safety)
    assert b.received == ["assumption of P: always next x", "goal of P: infinitely often true"]
    assert len(a.sent) == 2 and b.sent == a.received == []
    # init from the current position (Alg. 4 lines 6-7)
    assert [c.text.strip() for c in b.adopted.spec.env_init] == ["!p_P"]
    assert a.syntheses == 1 and b.syntheses == 1  # §4.9: at most two each


def test_report_lines_say_who_what_and_how_it_ended():
    a, b = pair(p_spec(), q_spec())
    drive(a, direct(b))
    lines = report_lines(b.report(), "Q")
    assert lines[0] == "Q answered negotiation P->Q: " + Outcome.BOTH_ADOPT.value
    assert "  received from P: assumption of P: always next x" in lines


def test_only_one_incorporates_4_8_2():
    a, b = pair(p_spec(), q_spec(refuses=True))
    drive(a, direct(b))
    assert b.outcome is Outcome.KEPT_OWN and not b.adopted.incorporated  # line 14-15: own spec, new init
    assert a.outcome is Outcome.ADOPTED_PEERS and a.adopted.incorporated
    assert not any(c.text.strip() == "x'" for c in b.adopted.spec.sys_safety)
    assert b.syntheses == 2


def test_neither_incorporates_4_8_3_both_abort_with_an_explanation():
    a, b = pair(p_spec(refuses=True), q_spec(refuses=True, assumes=True))
    drive(a, direct(b))
    assert a.outcome is b.outcome is Outcome.BOTH_ABORT
    assert a.adopted is None and b.adopted is None
    assert "unrealizable" in a.explanation and "unrealizable" in b.explanation


def test_line_20_one_incorporates_but_the_other_cannot_run_its_own_spec_either():
    a, b = pair(p_spec(stuck=True), q_spec(), p_outputs={"p": False, "q": True})
    drive(a, direct(b))
    assert a.outcome is b.outcome is Outcome.ABORT_LINE_20
    assert a.adopted is None and b.adopted is None and a.syntheses == 2


@pytest.mark.parametrize("delivered", [0, 1, 2])
def test_a_peer_that_stops_answering_leaves_both_without_adoption(delivered):
    a, b = pair(p_spec(), q_spec())
    calls = []

    def call(message):
        if len(calls) >= delivered:
            raise TimeoutError("no answer within 5 s")
        calls.append(message)
        return answer(b, message)

    drive(a, call)
    assert a.outcome is Outcome.FAILED and a.adopted is None and "did not answer" in a.reason
    if not b.done:  # the responder's own timeout (the ROS adapter's expire)
        b.fail("the initiator went silent")
    assert b.adopted is None


def test_a_lost_status_2_reply_leaves_both_on_their_old_controllers():
    """The responder has both realizable statuses 2 (it is prepared); its reply never arrives: the
    initiator decides not to adopt and says so (commit protocol): nobody adopts."""
    a, b = pair(p_spec(), q_spec())
    n = [0]

    def call(message):
        n[0] += 1
        reply = answer(b, message)
        if n[0] == 3:
            raise ConnectionError("peer vanished")
        return reply

    drive(a, call)
    assert a.adopted is None and a.outcome is Outcome.FAILED
    assert b.adopted is None and b.outcome is Outcome.FAILED and "aborted" in b.reason


@pytest.mark.parametrize("garbled", ["[SYS_TRANS]\nx' &&& (", "[SYS_TRANS]\nnot_a_proposition'",
                                     "[ENV_TRANS]\nx'", "\x00binary"])
def test_garbled_spec_text_is_a_fault_on_both_sides(garbled):
    a, b = pair(p_spec(), q_spec())

    def call(message):
        if message.kind == OFFER:
            message = dataclasses.replace(message, text=garbled)
        return answer(b, message)

    drive(a, call)
    assert b.outcome is Outcome.FAILED and b.reason.startswith(("garbled", "offer from P", "offer refused"))
    assert a.outcome is Outcome.FAILED and "Q aborted" in a.reason
    assert a.adopted is None and b.adopted is None


def test_out_of_order_and_foreign_messages_are_faults():
    a, b = pair(p_spec(), q_spec())
    b.receive(Message(STATUS, "P", "P->Q", 1, realizable=True))
    assert b.outcome is Outcome.FAILED and "status 1 received in phase" in b.reason
    a, b = pair(p_spec(), q_spec())
    b.receive(Message(OFFER, "Z", "Z->Q"))
    assert b.outcome is Outcome.FAILED and "'Z'" in b.reason


def test_negotiator_negotiates_once_per_pair_and_reports():
    p = parse_structured(p_spec(), "P")
    q = parse_structured(q_spec(), "Q")
    q_side = Negotiator(Q_CLASSES)

    def transport(peer):
        return lambda message: q_side.respond(message, q, {"p_P": False}, {"x": False})[0]

    p_side = Negotiator(P_CLASSES, transport=transport)
    assert p_side.choose(p, {"x_Q": True, "p": False, "q": False}, {"x_Q": False}) == "Q"
    first = p_side.initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False})
    assert first.outcome is Outcome.BOTH_ADOPT
    assert p_side.choose(p, {"x_Q": True, "p": False, "q": False}, {"x_Q": False}) is None  # once per pair
    again = Negotiator(P_CLASSES, transport=transport).initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False})
    assert again.outcome is Outcome.FAILED and "once per pair" in again.reason
    report = p_side.reports()[0]
    assert report["peer"] == "Q" and report["case"] == "BOTH_ADOPT" and report["sent"]


def test_proposition_classes_from_the_mapping():
    mapping = parse_mapping("negotiation:\n  robot: D\n  global_sensors: [g]\n  peers:\n    A:\n"
                            "      eap: {door_A: door}\n      shares: {road_c: road_c_D}\n", "D.yaml")
    classes = classes_from_mapping(mapping)
    assert classes.robot == "D" and classes.eap("A") == {"door_A"} and classes.global_sensors == ("g",)
    assert classes.peers["A"].table == {"road_c": "road_c_D", "door_A": "door"}
    spec = parse_structured("[INPUT]\ndoor_A\ng\n[OUTPUT]\nroad_c\n", "D")
    assert classes.check(spec) == []
    with pytest.raises(MappingError, match="D.yaml:1: unknown top-level key 'negotiations'"):
        parse_mapping("negotiations: {}\n", "D.yaml")
    with pytest.raises(NegotiationError, match="D.yaml:2: negotiation: peers.A: unknown key"):
        classes_from_data({"robot": "D", "peers": {"A": {"eab": {}}}}, "D.yaml", 2)
    bad = Classes("D", {"A": Peer("A", {"nope": "x", "g": "y"}, {"road_c": "y"})}, ("g",), "D.yaml", 3)
    problems = bad.check(spec)
    assert any("'nope' is not an input" in p for p in problems)
    assert any("also a global sensor" in p for p in problems)
    assert any("both translate to 'y'" in p for p in problems)


def test_a_declaration_that_does_not_fit_the_spec_names_the_mapping_line():
    mapping = parse_mapping("inputs: {}\nnegotiation:\n  robot: P\n  peers:\n    Q: {eap: {nope: x}}\n", "P.yaml")
    with pytest.raises(NegotiationError, match=r"^P.yaml:2: negotiation.peers.Q.eap: 'nope' is not an input"):
        negotiation_classes(mapping, parse_structured(p_spec(), "P"))
    assert negotiation_classes(None, parse_structured(p_spec(), "P")) is None


# --- the invariant, under every fault ------------------------------------------------------------------
SPECS = {
    "p": [p_spec(), p_spec(refuses=True), p_spec(stuck=True)],
    "q": [q_spec(), q_spec(refuses=True), q_spec(assumes=True), q_spec(refuses=True, assumes=True)],
}


@settings(max_examples=60, deadline=None)
@given(pi=st.integers(0, 2), qi=st.integers(0, 3), stuck_now=st.booleans(),
       fault=st.one_of(st.none(), st.tuples(st.sampled_from(["before", "after", "garble", "flip"]),
                                            st.integers(0, 3))))
def test_nobody_adopts_without_a_realizable_spec_and_the_peers_status(pi, qi, stuck_now, fault):
    a, b = pair(SPECS["p"][pi], SPECS["q"][qi], p_outputs={"p": False, "q": stuck_now})
    n = [0]

    def call(message):
        i = n[0]
        n[0] += 1
        if fault and fault[1] == i and fault[0] == "before":
            raise TimeoutError("timeout")
        if fault and fault[1] == i and fault[0] == "garble":
            message = dataclasses.replace(message, text=message.text + "\n)(", realizable=not message.realizable)
        reply = answer(b, message)
        if fault and fault[1] == i and fault[0] == "after":
            raise ConnectionError("gone")
        if fault and fault[1] == i and fault[0] == "flip":
            reply = dataclasses.replace(reply, round=reply.round + 1)
        return reply

    drive(a, call)
    if not b.done:
        b.fail("initiator silent")
    for party in (a, b):
        assert party.done
        if party.adopted is not None:
            assert party.outcome.adopts
            assert party._status.get(2) is True and party._peer_status.get(2) is True
            assert synthesize(party.adopted.spec).realizable
        else:
            assert not party.outcome.adopts
    if fault is None:
        assert (a.adopted is None) == (b.adopted is None)
        assert a.outcome.adopts == b.outcome.adopts


# --- negotiation that can neither deadlock nor be abused ---------------------------------------
def q_side_answering(q_text: str = q_spec()):
    q = parse_structured(q_text, "Q")
    side = Negotiator(Q_CLASSES)
    return side, lambda message: side.respond(message, q, {"p_P": False}, {"x": False})


@pytest.mark.parametrize("text, needle", [
    ("[INPUT]\nz\n[SYS_TRANS]\nz'\n", "declares [INPUT]"),
    ("[SYS_TRANS]\n" + "TRUE\n" * 201, "201 clauses (at most 200)"),
    ("[SYS_TRANS]\n# " + "x" * 70000 + "\nTRUE\n", "bytes (at most 65536)"),
    ("[SYS_TRANS]\nx' &&& (\n", "garbled"),
])
def test_a_refused_offer_is_one_line_and_does_not_use_up_the_pair(text, needle):
    side, respond = q_side_answering()
    reply, _ = respond(Message(OFFER, "P", "P->Q", 0, text))
    assert reply.kind == "abort" and needle in reply.reason and "\n" not in reply.reason, reply
    # the real P can still negotiate: the refused message used up nothing
    p = parse_structured(p_spec(), "P")
    real = Negotiator(P_CLASSES, transport=lambda peer: lambda message: respond(message)[0])
    assert real.initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False}).outcome is Outcome.BOTH_ADOPT


def test_only_the_node_serving_a_declared_peer_may_speak_for_it():
    from ltl_stack.runtime.resilience.negotiation import caller_refusal

    nodes = {"P": "/t/P/controller_executor"}
    assert caller_refusal("/t/P/controller_executor", "P", nodes) is None
    assert "not from /t/P/controller_executor" in caller_refusal("/rogue", "P", nodes)
    assert "not a declared peer" in caller_refusal("/t/Z/controller_executor", "Z", nodes)


def test_simultaneous_negotiation_resolves_as_negotiating_in_turn():
    """Both robots start at the same instant (each offer in flight before either arrives): P, whose
    name sorts first, initiates; Q answers P's negotiation and its own offer is refused. The outcome
    of P->Q is the one of negotiating in turn; nobody is left half-way."""
    import threading

    p = parse_structured(p_spec(), "P")
    q = parse_structured(q_spec(assumes=True), "Q")

    def in_turn():
        q_side = Negotiator(Q_CLASSES)
        p_side = Negotiator(P_CLASSES, transport=lambda peer: lambda m: q_side.respond(m, q, {"p_P": False},
                                                                                     {"x": False})[0])
        mine = p_side.initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False})
        return mine.outcome, q_side.history[-1].outcome

    expected = in_turn()
    p_side, q_side = Negotiator(P_CLASSES), Negotiator(Q_CLASSES)
    both = threading.Barrier(2, timeout=60)

    def through(other, spec, inputs, outputs):
        def transport(peer):
            def call(message):
                if message.kind == OFFER:
                    both.wait()  # both offers are in flight
                with other.lock:
                    return other.respond(message, spec, inputs, outputs)[0]
            return call
        return transport

    p_side.transport = through(q_side, q, {"p_P": False}, {"x": False})
    q_side.transport = through(p_side, p, {"x_Q": False}, {"p": False, "q": False})
    results = {}
    threads = [threading.Thread(target=lambda: results.setdefault("P", p_side.initiate(p, "Q", {"x_Q": False},
                                                                                        {"p": False, "q": False}))),
               threading.Thread(target=lambda: results.setdefault("Q", q_side.initiate(q, "P", {"p_P": False},
                                                                                        {"x": False})))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    answered = [n for n in q_side.history if not n.initiator]
    assert results["P"].outcome is expected[0] and answered and answered[-1].outcome is expected[1]
    # refused while its own offer was in flight (or, scheduled late, once P's negotiation was done)
    assert results["Q"].outcome is Outcome.FAILED and ("P initiates" in results["Q"].reason
                                                       or "already negotiated" in results["Q"].reason)
    assert not p_side.yielded and frozenset("PQ") in q_side.partners  # Q answered P: the pair negotiated
    assert answered[-1].adopted is not None and results["P"].adopted is not None  # both adopt, as in turn


class Held:
    """A stand-in for the strategy the hook negotiates for (``sessions.NegotiationHost``)."""

    def __init__(self, spec):
        import threading

        self.base, self.lock, self.spec_path, self.held = spec, threading.RLock(), None, 0

    def negotiation_base(self):
        return self.base

    def rebase(self, spec):
        self.base = spec

    def negotiation_held(self):
        self.held += 1


def test_hook_by_cause_s1_unless_the_robots_negotiated_and_disagree():
    """Alg. 3 by cause: no peer involved, a silent peer, an already negotiated pair:
    None (S.1: explanation and the user); 4.8.3: NegotiationAbort."""
    from ltl_stack.runtime.resilience.characterize import NegotiationAbort, Observation

    p = parse_structured(p_spec(refuses=True), "P")
    seen = Observation(1, 0.0, {"x_Q": True}, {"p": False, "q": False}, {"x_Q": False})
    no_peer = Observation(1, 0.0, {"x_Q": True}, {"p": False, "q": False}, {"x_Q": True})
    assert Negotiator(P_CLASSES).hook(Held(p), no_peer) is None  # the violated clauses name no peer

    def silent(peer):
        def call(message):
            raise TimeoutError("no answer within 2 s")
        return call

    assert Negotiator(P_CLASSES, transport=silent).hook(Held(p), seen) is None
    _, respond = q_side_answering(q_spec(refuses=True, assumes=True))
    side = Negotiator(P_CLASSES, transport=lambda peer: lambda message: respond(message)[0])
    with pytest.raises(NegotiationAbort, match="4.8.3"):
        side.hook(Held(p), seen)
    assert side.hook(Held(p), seen) is None  # the pair already negotiated


@pytest.mark.parametrize("broken", ["P", "Q"])
def test_adoption_is_two_phase_a_write_failure_on_either_side_fails_both(tmp_path, broken):
    """Each party writes its adopted spec aside before its realizable status 2; one
    that cannot (its folder is gone) says so, and both end FAILED with nothing adopted and nothing
    written; with both folders there, both files are written and both adopt."""
    p = parse_structured(p_spec(), "P")
    q = parse_structured(q_spec(), "Q")
    paths = {r: tmp_path / r / f"{r}.adopted.structuredslugs" for r in "PQ"}
    for r in "PQ":
        if r != broken:
            paths[r].parent.mkdir()
    q_side = Negotiator(Q_CLASSES, path=paths["Q"])
    p_side = Negotiator(P_CLASSES, path=paths["P"], transport=lambda peer: lambda m: q_side.respond(
        m, q, {"p_P": False}, {"x": False})[0])
    mine = p_side.initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False})
    theirs = q_side.history[-1]
    assert mine.outcome is theirs.outcome is Outcome.FAILED, (mine.reason, theirs.reason)
    assert "cannot write its adopted specification" in mine.reason + theirs.reason
    assert mine.adopted is None and theirs.adopted is None
    assert not p_side.commit(mine) and not q_side.commit(theirs)
    assert [f for r in "PQ" if paths[r].parent.exists() for f in paths[r].parent.iterdir()] == []
    # both folders there: both written, both adopt
    paths[broken].parent.mkdir()
    q_side = Negotiator(Q_CLASSES, path=paths["Q"])
    p_side = Negotiator(P_CLASSES, path=paths["P"], transport=lambda peer: lambda m: q_side.respond(
        m, q, {"p_P": False}, {"x": False})[0])
    mine = p_side.initiate(p, "Q", {"x_Q": False}, {"p": False, "q": False})
    theirs = q_side.history[-1]
    assert mine.outcome is theirs.outcome is Outcome.BOTH_ADOPT
    assert p_side.commit(mine) and q_side.commit(theirs)
    assert paths["P"].read_text() == mine.adopted.text and paths["Q"].read_text() == theirs.adopted.text
    assert sorted(f.name for r in "PQ" for f in paths[r].parent.iterdir()) == sorted(p.name for p in paths.values())


def test_serve_handles_a_message_off_the_controllers_lock_and_refuses_once_aborted():
    """While the responder parses and synthesizes an offer, another thread can
    take the controller's lock (the robot keeps stepping); an aborted responder answers with an
    abort and adopts nothing."""
    import threading

    from ltl_stack.runtime.executor.controller import Controller
    from ltl_stack.runtime.resilience.characterize import ResilientStrategy

    q = parse_structured(q_spec(), "Q")
    strategy = ResilientStrategy(q, recovery=False)
    controller = Controller(strategy, settle_steps=0)
    controller.report_many({"p_P": False})
    side = Negotiator(Q_CLASSES)
    taken: list = []
    respond = side.respond

    def respond_while_stepping(*args, **kwargs):
        other = threading.Thread(target=lambda: taken.append(controller.lock.acquire(timeout=30)
                                                             and controller.lock.release() is None))
        other.start()
        other.join()
        return respond(*args, **kwargs)

    side.respond = respond_while_stepping
    p = parse_structured(p_spec(), "P")
    offer = Negotiation(p, P_CLASSES, "Q", incoming={"x_Q": False}, outputs={"p": False, "q": False}).offer()
    reply = side.serve(offer, strategy, controller)
    assert taken == [True] and reply.kind == "offer", (taken, reply)
    strategy.abort("test")
    again = Negotiator(Q_CLASSES).serve(offer, strategy, controller)
    assert again.kind == "abort" and "has aborted" in again.reason
