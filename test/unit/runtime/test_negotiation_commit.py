"""The commit protocol of negotiation (docs/negotiation.md, "Agreement survives lost messages"), in
process: k <= 4 robots in a cycle (each needs the next one's output) negotiate over a network that loses,
duplicates and replays messages; then the link heals and each robot asks again (``settle``). No report
claims an adoption the peer did not make, every adoption is on both sides or neither once healed, and no
adopted guarantee is ever dropped from what a robot runs."""
from __future__ import annotations

import threading
from types import SimpleNamespace

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.runtime.resilience.characterize import Characterizer, Observation
from ltl_stack.runtime.resilience.negotiation import (
    Classes,
    Negotiation,
    Negotiator,
    Outcome,
    Peer,
    answer,
    drive,
)
from ltl_stack.spec import parse_structured

CONFIRMED = (Outcome.BOTH_ADOPT, Outcome.ADOPTED_PEERS, Outcome.KEPT_OWN)


class Party:
    """What ``Negotiator.hook`` and ``serve`` need of a robot (``sessions.NegotiationHost``) and of its
    controller (a lock, a position)."""

    def __init__(self, spec) -> None:
        self.characterizer = Characterizer(spec)
        self.lock = threading.RLock()
        self.state = SimpleNamespace(inputs=dict.fromkeys(spec.inputs, True), outputs=dict.fromkeys(spec.outputs, False))
        self.aborted, self.spec_path, self.held = False, None, 0

    def negotiation_base(self):
        return self.characterizer.original

    def rebase(self, spec):
        self.characterizer = Characterizer(spec)

    def negotiation_held(self):
        self.held += 1

    def install_negotiated(self, spec, text, strategy, inputs, outputs, write=True):
        self.rebase(spec)
        return self.state


def cycle(k: int):
    """Robot i needs robot i+1's output o<i+1> (input n<i>, assumed always true)."""
    names = [f"R{i}" for i in range(k)]
    robots = {}
    for i, me in enumerate(names):
        nxt, prev = names[(i + 1) % k], names[(i - 1) % k]
        text = (f"[INPUT]\nn{i}\n[OUTPUT]\no{i}\n[SYS_INIT]\n!o{i}\n[ENV_TRANS]\nn{i}'\n[SYS_LIVENESS]\nn{i}\n")
        peers = {nxt: Peer(nxt, {f"n{i}": f"o{(i + 1) % k}"}, {})}
        if prev != nxt:
            peers[prev] = Peer(prev, {}, {f"o{i}": f"n{(i - 1) % k}"})
        else:
            peers[nxt] = Peer(nxt, {f"n{i}": f"o{(i + 1) % k}"}, {f"o{i}": f"n{(i - 1) % k}"})
        party = Party(parse_structured(text, f"{me}.structuredslugs"))
        negotiator = Negotiator(Classes(me, peers))
        negotiator.answer_wait, negotiator.retry = 2.0, (0.0, 0.01)
        robots[me] = (party, negotiator)
    return robots


class Network:
    """Delivers each message with the next fault of a script: ok, a lost request, a lost reply, a
    duplicated request, or an earlier message replayed first (reordering); ``healed``: no more faults."""

    def __init__(self, robots, faults: list[str]) -> None:
        self.robots = robots
        self.faults = list(faults)
        self.sent: list[tuple[str, object]] = []
        self.healed = False

    def transport(self, sender: str):
        def to(peer):
            party, negotiator = self.robots[peer.name]

            def deliver(message):
                return negotiator.serve(message, party, party)

            def call(message):
                fault = "ok" if self.healed or not self.faults else self.faults.pop(0)
                if fault == "replay" and self.sent:
                    old_peer, old = self.sent[len(self.sent) // 2]
                    other_party, other = self.robots[old_peer]
                    other.serve(old, other_party, other_party)
                self.sent.append((peer.name, message))
                if fault == "lose_request":
                    raise TimeoutError("request lost")
                reply = deliver(message)
                if fault == "duplicate":
                    deliver(message)
                if fault == "lose_reply":
                    raise TimeoutError("reply lost")
                return reply
            return call
        return to


def guarantees(n: Negotiation) -> set[str]:
    return {" ".join(c.text.split()) for c in (n.ownership.guarantees if n.ownership else [])}


def running(party) -> set[str]:
    return {" ".join(c.text.split()) for c in party.characterizer.original.sys_safety}


def check_reports(robots) -> None:
    """No party reports a confirmed adoption its peer did not make."""
    sides: dict[str, dict[str, Negotiation]] = {}
    for name, (_, negotiator) in robots.items():
        for n in negotiator.history:
            sides.setdefault(n.session, {})[name] = n
    for session, by_robot in sides.items():
        for name, n in by_robot.items():
            if n.outcome in CONFIRMED:
                other = [m for r, m in by_robot.items() if r != name]
                assert other and other[0].adopted is not None, (session, name, n.outcome, n.log)


@settings(max_examples=40, deadline=None)
@given(k=st.integers(2, 4), order=st.randoms(use_true_random=False),
       faults=st.lists(st.sampled_from(["ok", "ok", "lose_request", "lose_reply", "duplicate", "replay"]),
                       max_size=24))
def test_lost_duplicated_and_replayed_messages_never_break_agreement(k, order, faults):
    robots = cycle(k)
    network = Network(robots, faults)
    for name, (_, negotiator) in robots.items():
        negotiator.transport = network.transport(name)
    starters = list(robots)
    order.shuffle(starters)
    for name in starters:
        party, negotiator = robots[name]
        i = int(name[1:])
        seen = Observation(1, 0.0, {f"n{i}": True}, {f"o{i}": False}, {f"n{i}": False})
        negotiator.hook(party, seen)
        check_reports(robots)
    network.healed = True
    for _, negotiator in robots.values():  # the responder's timeout (the ROS endpoint's timer)
        for peer in list(negotiator.active):
            negotiator.expire(peer, "the initiator went silent")
    for _ in range(5):
        if not sum(negotiator.settle(party, party) for party, negotiator in robots.values()):
            break
    check_reports(robots)
    for name, (party, negotiator) in robots.items():
        assert not any(n.unresolved for n in negotiator.history), [n.report() for n in negotiator.history]
        assert negotiator.current is None, name
        for n in negotiator.history:
            if n.adopted is not None:  # every promise this robot made is in what it runs
                assert guarantees(n) <= running(party), (name, n.session, guarantees(n), running(party))
    for session in {n.session for _, neg in robots.values() for n in neg.history}:
        sides = [n for _, neg in robots.values() for n in neg.history if n.session == session]
        if len(sides) == 2:  # healed: both adopted or neither
            assert (sides[0].adopted is None) == (sides[1].adopted is None), [s.report() for s in sides]


P = Classes("P", {"Q": Peer("Q", {"x_Q": "x"}, {})})
Q = Classes("Q", {"P": Peer("P", {}, {"x": "x_Q"})})


def pair():
    p = parse_structured("[INPUT]\nx_Q\n[OUTPUT]\np\n[ENV_TRANS]\nx_Q'\n[SYS_LIVENESS]\nx_Q\n", "P")
    q = parse_structured("[INPUT]\nt\n[OUTPUT]\nx\n", "Q")
    a = Negotiation(p, P, "Q", incoming={"x_Q": False}, outputs={"p": False})
    b = Negotiation(q, Q, "P", incoming={"t": False}, outputs={"x": False}, initiator=False)
    return a, b


def test_a_lost_confirmation_is_reported_as_unconfirmed_until_the_link_heals():
    """The initiator decided and adopted; the responder's confirmation is lost: the initiator's report
    says the peer has not confirmed (not 4.8.1); the decision, sent again, gets the confirmation."""
    a, b = pair()
    lost = [True]

    def call(message):
        reply = answer(b, message)
        if message.kind == "commit" and lost.pop() if lost else False:
            raise TimeoutError("reply lost")
        return reply

    drive(a, call)
    assert a.adopted is not None and a.outcome is Outcome.UNCONFIRMED and a.unresolved
    assert b.adopted is not None and b.outcome is Outcome.BOTH_ADOPT  # it had the decision
    from ltl_stack.runtime.resilience.negotiation.party import confirm

    assert confirm(a, lambda message: answer(b, message)) and a.outcome is Outcome.BOTH_ADOPT


def test_a_lost_decision_leaves_the_responder_prepared_and_asking():
    a, b = pair()

    def call(message):
        if message.kind == "commit":
            raise TimeoutError("request lost")
        return answer(b, message)

    drive(a, call)
    assert a.outcome is Outcome.UNCONFIRMED and b.phase.value == "prepared" and b.adopted is None
    assert b.report()["outcome"] is None and b.unresolved  # no claim of adoption either way
