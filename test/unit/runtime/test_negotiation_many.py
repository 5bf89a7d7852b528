"""Negotiation among more than two robots, in process, with real threads (docs/negotiation.md, "Many
robots"): a robot is in one negotiation at a time, so each phi^nego is built on the spec the robot runs
after every earlier adoption; two initiators at one responder at once, and a three-robot cycle, end with
every promise in the running spec, the adopted-spec file and the reports."""
from __future__ import annotations

import threading

from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.resilience.characterize import Observation, ResilientStrategy
from ltl_stack.runtime.resilience.negotiation import BUSY, Classes, Negotiator, Outcome, Peer
from ltl_stack.spec import load_spec, parse_structured


def robot_spec(name: str, inputs: list[str], outputs: list[str], assumes: list[str]) -> str:
    return (f"[INPUT]\n{chr(10).join(inputs)}\n[OUTPUT]\n{chr(10).join(outputs)}\n[ENV_INIT]\nTRUE\n[SYS_INIT]\n"
            + " & ".join(f"!{o}" for o in outputs) + "\n[ENV_TRANS]\n" + ("\n".join(assumes) or "TRUE") + "\n")


class Robot:
    """A robot with a ResilientStrategy and a Controller, its Negotiator (both roles) and a gate that
    holds its first offer until every robot's first offer is in flight."""

    def __init__(self, name: str, text: str, classes: Classes, tmp_path, gate: threading.Barrier) -> None:
        self.name = name
        self.spec = parse_structured(text, f"{name}.structuredslugs")
        self.strategy = ResilientStrategy(self.spec, recovery=False)
        self.controller = Controller(self.strategy, settle_steps=0)
        self.controller.report_many(dict.fromkeys(self.spec.inputs, True))
        self.path = tmp_path / f"{name}.adopted.structuredslugs"
        self.negotiator = Negotiator(classes, path=self.path)
        self.negotiator.retry = (0.01, 0.1)
        self.gate = gate
        self.offered = False
        self.result: object = None

    def connect(self, robots: dict[str, Robot]) -> None:
        def transport(peer):
            other = robots[peer.name]

            def call(message):
                if message.kind == "offer" and not self.offered:
                    self.offered = True
                    self.gate.wait()  # every robot's first offer is in flight at once
                return other.negotiator.serve(message, other.strategy, other.controller)
            return call
        self.negotiator.transport = transport

    def start(self, broken: str) -> threading.Thread:
        """Negotiate (the hook) after the assumption ``broken`` (an eAP input going false) broke."""
        inputs = dict.fromkeys(self.spec.inputs, True)
        outputs = dict.fromkeys(self.spec.outputs, False)
        seen = Observation(1, 0.0, inputs, outputs, {**inputs, broken: False})
        thread = threading.Thread(target=lambda: setattr(self, "result", self.negotiator.hook(self.strategy, seen)))
        thread.start()
        return thread

    def guarantees(self) -> set[str]:
        """The received assumptions in the spec this robot runs (its promises)."""
        return {" ".join(c.text.split()) for c in self.strategy.characterizer.original.sys_safety
                if c.text.strip().endswith("'") and "&" not in c.text}


def test_two_initiators_at_one_responder_keep_both_promises(tmp_path):
    """R1 needs S's gate g1 and R2 needs S's gate g2, at the same step: S answers one, the other waits
    (busy) and negotiates on S's spec with the first promise; S runs and has written both."""
    gate = threading.Barrier(2, timeout=60)
    s_classes = Classes("S", {"R1": Peer("R1", {}, {"g1": "g1_S"}), "R2": Peer("R2", {}, {"g2": "g2_S"})})
    robots = {
        "S": Robot("S", robot_spec("S", ["t"], ["g1", "g2"], []), s_classes, tmp_path, gate),
        "R1": Robot("R1", robot_spec("R1", ["g1_S"], ["a"], ["g1_S'"]),
                    Classes("R1", {"S": Peer("S", {"g1_S": "g1"}, {})}), tmp_path, gate),
        "R2": Robot("R2", robot_spec("R2", ["g2_S"], ["b"], ["g2_S'"]),
                    Classes("R2", {"S": Peer("S", {"g2_S": "g2"}, {})}), tmp_path, gate),
    }
    for robot in robots.values():
        robot.connect(robots)
    threads = [robots["R1"].start("g1_S"), robots["R2"].start("g2_S")]
    for thread in threads:
        thread.join(120)
    s = robots["S"]
    answered = [n for n in s.negotiator.history if not n.initiator]
    assert [n.outcome for n in answered] == [Outcome.BOTH_ADOPT] * 2, [(n.session, n.reason) for n in answered]
    for name in ("R1", "R2"):
        mine = robots[name].negotiator.history
        assert [n.outcome for n in mine] == [Outcome.BOTH_ADOPT], [(n.session, n.reason) for n in mine]
        assert robots[name].result is not None  # the hook gave the spec to run
    # S's running spec and its file hold both promises; the second phi^nego was built on the first
    assert {"g1'", "g2'"} <= s.guarantees(), s.guarantees()
    assert {"g1'", "g2'"} <= {" ".join(c.text.split()) for c in load_spec(s.path).sys_safety}
    assert any(" ".join(c.text.split()) == "g1'" for c in answered[1].star.sys_safety) or \
        any(" ".join(c.text.split()) == "g2'" for c in answered[1].star.sys_safety)
    assert s.negotiator.epoch == 2 and s.negotiator.current is None
    assert s.strategy.counters.negotiations == 2


def test_a_three_robot_cycle_keeps_every_promise(tmp_path):
    """A needs B's x, B needs C's y, C needs A's z, all at once: the robots negotiate in some order,
    one negotiation at a time each; every pair ends 4.8.1 on both sides and every robot runs (and has
    written) the promise it made."""
    gate = threading.Barrier(3, timeout=60)
    specs = {"A": (["x_B"], ["z"], ["x_B'"]), "B": (["y_C"], ["x"], ["y_C'"]),
             "C": (["z_A"], ["y"], ["z_A'"])}
    classes = {
        "A": Classes("A", {"B": Peer("B", {"x_B": "x"}, {}), "C": Peer("C", {}, {"z": "z_A"})}),
        "B": Classes("B", {"C": Peer("C", {"y_C": "y"}, {}), "A": Peer("A", {}, {"x": "x_B"})}),
        "C": Classes("C", {"A": Peer("A", {"z_A": "z"}, {}), "B": Peer("B", {}, {"y": "y_C"})}),
    }
    robots = {r: Robot(r, robot_spec(r, *specs[r]), classes[r], tmp_path, gate) for r in "ABC"}
    for robot in robots.values():
        robot.connect(robots)
    threads = [robots["A"].start("x_B"), robots["B"].start("y_C"), robots["C"].start("z_A")]
    for thread in threads:
        thread.join(180)
    sessions: dict[str, list] = {}
    for robot in robots.values():
        for n in robot.negotiator.history:
            sessions.setdefault(n.session.split("#")[0], []).append(n.outcome)
    assert sessions == {s: [Outcome.BOTH_ADOPT] * 2 for s in ("A->B", "B->C", "C->A")}, sessions
    for name, promise in (("B", "x'"), ("C", "y'"), ("A", "z'")):
        robot = robots[name]
        assert promise in robot.guarantees(), (name, robot.guarantees())
        written = load_spec(robot.path)
        assert {" ".join(c.text.split()) for c in written.sys_safety} == \
            {" ".join(c.text.split()) for c in robot.strategy.characterizer.original.sys_safety}, name
        assert robot.negotiator.current is None and robot.result is not None
    assert not any(BUSY in r["reason"] for robot in robots.values() for r in robot.negotiator.reports())


def test_a_pair_negotiates_again_only_after_what_one_of_them_runs_changed():
    p_classes = Classes("P", {"Q": Peer("Q", {"x_Q": "x"}, {})})
    side = Negotiator(p_classes)
    assert side.may_initiate("Q") and side.session_for("Q") == "P->Q"
    side.partners[frozenset("PQ")] = (0, "P->Q")
    assert not side.may_initiate("Q")
    side.epoch = 1  # an adoption (with anyone) since
    assert side.may_initiate("Q") and side.session_for("Q") == "P->Q#1"
