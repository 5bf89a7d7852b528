"""One robot's negotiations (both roles) and the glue to its resilient executor (thesis §4.8, Alg. 3 S.2).

``Negotiator`` decides whom to negotiate with, answers other robots' messages, keeps the reports, and
installs what was agreed in the robot's ``ResilientStrategy`` (``hook`` as initiator, ``serve`` as
responder). See the package docstring and docs/negotiation.md.
"""
from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from ltl_stack.runtime.characterize import NegotiationAbort
from ltl_stack.runtime.negotiation.classes import Classes, Peer
from ltl_stack.runtime.negotiation.messages import ABORT, OFFER, SIMULTANEOUS, Message, Outcome, offer_refusal
from ltl_stack.runtime.negotiation.party import Negotiation, answer, drive
from ltl_stack.runtime.negotiation.staging import commit_adopted, discard_staged, stage_adopted, write_adopted
from ltl_stack.spec.formula import evaluate
from ltl_stack.spec.model import Clause, Spec


def count_negotiation(strategy: Any) -> None:
    """One more negotiation held by ``strategy``'s robot, whatever its outcome (``Counters.negotiations``,
    published on ``~state``)."""
    counters = getattr(strategy, "counters", None)
    if counters is not None:
        with getattr(strategy, "lock", None) or contextlib.nullcontext():
            counters.negotiations += 1


def violated_clauses(spec: Spec, current: Mapping[str, bool], incoming: Mapping[str, bool]) -> list[Clause]:
    """The env-safety clauses of ``spec`` broken by the transition (``current`` position -> ``incoming``)."""
    now = {n: bool(v) for n, v in current.items()}
    nxt = {n: bool(v) for n, v in incoming.items()}
    return [c for c in spec.env_safety if not evaluate(c.formula, now, nxt)]


Transport = Callable[[Peer], Callable[[Message], Message]]


class Negotiator:
    """One robot's negotiations (both roles): whom to negotiate with, once per pair (§4.8), and the
    reports for ``~state`` / the trace. ``transport(peer)`` gives the call that sends a message to
    ``peer`` and returns its answer (an in-process responder, or the ROS service)."""

    def __init__(self, classes: Classes, *, transport: Transport | None = None,
                 synthesis_options: Mapping[str, Any] | None = None, path: str | Path | None = None) -> None:
        self.classes = classes
        #: where an adopted spec is written (the characterized-spec file); staged before status 2
        self.path = Path(path) if path is not None else None
        self.transport = transport
        self.synthesis_options = dict(synthesis_options or {})
        self.history: list[Negotiation] = []
        self.active: dict[str, Negotiation] = {}   # responder side, by peer
        self.initiating: dict[str, Negotiation] = {}  # initiator side while its messages are exchanged
        #: peers whose offer we answered while our own offer to them was in flight (simultaneous start)
        self.yielded: set[str] = set()
        #: one message handled at a time, never under the controller's lock (the robot keeps stepping)
        self.lock = threading.RLock()
        self.partners: set[frozenset[str]] = set()
        #: how long an initiator that yielded waits for the negotiation it answers (seconds)
        self.answer_wait = 60.0
        #: called after every message handled and every negotiation started or ended (reports changed)
        self.on_change: Callable[[Negotiation], None] | None = None

    def choose(self, star: Spec, current: Mapping[str, bool], incoming: Mapping[str, bool]) -> str | None:
        """The peer to negotiate with: the first (declaration order) whose eAP inputs appear in the
        violated env-safety clauses and with whom we have not negotiated yet."""
        for peer in self.classes.peers_in(violated_clauses(star, current, incoming)):
            if frozenset((self.classes.robot, peer)) not in self.partners:
                return peer
        return None

    def initiate(self, star: Spec, peer: str, incoming: Mapping[str, bool], outputs: Mapping[str, bool]) -> Negotiation:
        """Run Alg. 4 as the robot that detected the conflict."""
        n = Negotiation(star, self.classes, peer, incoming=incoming, outputs=outputs, initiator=True,
                        synthesis_options=self.synthesis_options)
        n.stage = self._stager(n)
        with self.lock:
            self.partners.add(frozenset((self.classes.robot, peer)))
            self.history.append(n)
            self.initiating[peer] = n
        try:
            if self.transport is None:
                n.fail("no transport to reach the peer")
            else:
                self._changed(n)
                drive(n, self.transport(self.classes.peers[peer]))
        finally:
            if n.adopted is None:
                discard_staged(n.staged)
            with self.lock:
                self.initiating.pop(peer, None)
                if n.outcome is Outcome.FAILED and SIMULTANEOUS in n.reason:
                    # the peer initiates instead: no negotiation of ours took place, answer theirs
                    self.partners.discard(frozenset((self.classes.robot, peer)))
                    self.yielded.add(peer)
        self._changed(n)
        return n

    def wait_answered(self, peer: str, timeout: float) -> Negotiation | None:
        """After yielding to ``peer`` (simultaneous negotiation, ``respond``): wait up to ``timeout``
        seconds for the negotiation it started to end; that negotiation, or None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                theirs = [m for m in self.history if not m.initiator and m.peer.name == peer]
            if theirs and theirs[-1].done:
                return theirs[-1]
            time.sleep(0.02)
        return None

    def _stager(self, n: Negotiation) -> Callable[[Spec, str], Path] | None:
        if self.path is None:
            return None
        path = self.path
        return lambda spec, text: stage_adopted(spec, text, path, n.session)

    def commit(self, n: Negotiation) -> bool:
        """Phase two of ``n``'s adoption (both parties sent a realizable status 2): the staged spec
        replaces the adopted-spec file; a negotiation that did not adopt drops its staged file. True
        when the file was written."""
        if n.adopted is None or n.staged is None or self.path is None:
            discard_staged(n.staged)
            return False
        commit_adopted(n.staged, self.path)
        return True

    def _changed(self, n: Negotiation) -> None:
        if self.on_change is not None:
            self.on_change(n)

    def respond(self, message: Message, star: Spec, incoming: Mapping[str, bool],
                outputs: Mapping[str, bool]) -> tuple[Message, Negotiation | None]:
        """Answer one message of a negotiation another robot started; returns our reply and the
        negotiation (done when it ended)."""
        peer = message.sender
        if message.kind == OFFER:
            if peer not in self.classes.peers:
                return Message(ABORT, self.classes.robot, message.session,
                               reason=f"{self.classes.robot} has no peer {peer!r}"), None
            refusal = offer_refusal(message.text)
            if refusal is not None:  # nothing started: the real peer may still negotiate
                return Message(ABORT, self.classes.robot, message.session, reason=refusal), None
            if frozenset((self.classes.robot, peer)) in self.partners:
                mine = self.initiating.get(peer)
                if mine is None or mine.done:
                    return Message(ABORT, self.classes.robot, message.session,
                                   reason=f"{self.classes.robot} already negotiated with {peer} (once per pair)"), None
                # both started at once: the robot whose name sorts first initiates, the other answers
                # (deterministic, and the outcome is the one of negotiating in turn)
                if self.classes.robot < peer:
                    return Message(ABORT, self.classes.robot, message.session,
                                   reason=f"{SIMULTANEOUS} {self.classes.robot} initiates "
                                          f"(robots negotiate in the order of their names)"), None
                self.yielded.add(peer)
            n = Negotiation(star, self.classes, peer, incoming=incoming, outputs=outputs, initiator=False,
                            synthesis_options=self.synthesis_options)
            n.stage = self._stager(n)
            self.partners.add(frozenset((self.classes.robot, peer)))
            self.history.append(n)
            self.active[peer] = n
        else:
            n = self.active.get(peer)
            if n is None:
                return Message(ABORT, self.classes.robot, message.session,
                               reason=f"no negotiation with {peer} in progress"), None
        reply = answer(n, message)
        if n.done:
            self.active.pop(peer, None)
            if n.adopted is None:
                discard_staged(n.staged)
            if n.outcome is Outcome.FAILED and n._nego is None:
                # the offer itself was refused (garbled, foreign): no negotiation took place
                self.partners.discard(frozenset((self.classes.robot, peer)))
        self._changed(n)
        return reply, n

    def expire(self, peer: str, reason: str) -> Negotiation | None:
        """The responder's timeout: the initiator went silent mid-negotiation."""
        n = self.active.pop(peer, None)
        if n is not None:
            n.fail(reason)
            self._changed(n)
        return n

    def reports(self) -> list[dict[str, Any]]:
        return [n.report() for n in self.history]

    # --- with a ResilientStrategy (runtime.characterize) -------------------------------------------------
    def hook(self, strategy: Any, observation: Any) -> Spec | None:
        """``ResilientStrategy(negotiate=negotiator.hook)`` (the executor's negotiation hook,
        docs/resilience.md): Alg. 3 line 9. Negotiates with the peer whose eAP inputs the violated
        clauses mention (once per pair). On adoption the negotiated spec becomes the strategy's base
        spec phi* (later characterizations start from it with empty EC sets, Alg. 4 line 2), is
        written atomically to the characterized-spec path, and is returned for the strategy to run.
        Alg. 3 by cause (§4.4): None — the strategy goes to S.1, explanation and the user — when no
        peer is involved, the pair already negotiated, or the negotiation failed (a peer absent or
        silent is uncontrollable environment); ``NegotiationAbort`` when the robots negotiated and
        cannot agree (4.8.3, line 20)."""
        star = strategy.characterizer.original
        current = {**observation.current_inputs, **observation.current_outputs}
        peer = self.choose(star, current, observation.incoming)
        if peer is None:
            return None
        n = self.initiate(star, peer, observation.incoming, observation.current_outputs)
        if peer in self.yielded:  # we answer the peer's negotiation instead (serve installs and counts it)
            self.wait_answered(peer, self.answer_wait)
            with self.lock:
                self.yielded.discard(peer)
            return None
        count_negotiation(strategy)
        if n.outcome in (Outcome.BOTH_ABORT, Outcome.ABORT_LINE_20):
            raise NegotiationAbort(f"negotiation with {peer}: {n.outcome.value}")
        adopted = n.adopted
        if adopted is None:
            return None
        with getattr(strategy, "lock", None) or contextlib.nullcontext():  # the executor steps meanwhile
            old = strategy.characterizer
            strategy.characterizer = type(old)(adopted.spec, path=old.path, synthesis_options=old.synthesis_options)
        if not self.commit(n) and old.path is not None:
            write_adopted(adopted, old.path)
        return adopted.spec

    def serve(self, message: Message, strategy: Any, controller: Any, start_wait: float = 0.0) -> Message:
        """Answer a peer's message for the robot running ``controller`` (a ``runtime.Controller`` over
        ``strategy``, a ``ResilientStrategy``). The position is read under the controller's lock; the
        message (parsing, synthesis) is handled under the negotiator's lock only, so the controller
        keeps stepping meanwhile; an adopted spec is installed under the controller's lock
        (``strategy.adopt``) from the position the negotiation started at (the adopted spec's init;
        the controller's next step continues from there with the current readings); 4.8.3 / line 20
        abort the strategy (its safe outputs). A controller that has not started yet (inputs still
        silent) is waited for up to ``start_wait`` seconds; then, and once aborted, the answer is an
        abort."""
        deadline = time.monotonic() + start_wait
        while controller.state is None and time.monotonic() < deadline:
            time.sleep(0.02)  # our controller starts once every input has reported (not under the lock)
        with controller.lock:
            state = controller.state
            aborted = getattr(strategy, "mode", None) is not None and strategy.mode.value == "aborted"
            if state is None or aborted:
                why = "has aborted" if aborted else "has not started"
                return Message(ABORT, self.classes.robot, message.session, reason=f"{self.classes.robot} {why}")
            star, inputs, outputs = strategy.characterizer.original, dict(state.inputs), dict(state.outputs)
        with self.lock:
            reply, n = self.respond(message, star, inputs, outputs)
        if n is not None and n.done:
            written = self.commit(n)
            count_negotiation(strategy)
            with controller.lock:
                if n.adopted is not None:  # from the position the negotiation started at (its init)
                    state = strategy.adopt(n.adopted.spec, n.adopted.text, n.adopted.strategy, n.incoming, n.outputs,
                                           write=not written)
                    installed = getattr(strategy, "on_installed", None)
                    if installed is not None:  # the executor node: continue with the current readings, publish
                        installed(state)
                    else:
                        controller.state = state
                elif n.outcome in (Outcome.BOTH_ABORT, Outcome.ABORT_LINE_20):
                    strategy.abort(f"negotiation with {n.peer.name}: {n.outcome.value}")
        return reply
