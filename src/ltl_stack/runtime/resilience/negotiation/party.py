"""Alg. 4 for one party (thesis §4.8): ``Negotiation`` and the transport-independent drivers.

``Negotiation`` is one robot's side of one negotiation, driven by messages in this order, the same for
both robots: offer (line 3), status 1 (lines 10-17), status 2 (lines 18-21); ``drive`` sends the
initiator's messages through a call, ``answer`` gives the responder's reply to one message. See the
package docstring for the steps and the faults.
"""
from __future__ import annotations

import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

from ltl_stack.runtime.resilience.negotiation.classes import Classes, assumptions_about, rename
from ltl_stack.runtime.resilience.negotiation.messages import (
    ABORT,
    COMMIT,
    OFFER,
    STATUS,
    WRITE_FAILED,
    Adoption,
    Message,
    Outcome,
    Phase,
    ProtocolFault,
    offer_refusal,
)
from ltl_stack.runtime.resilience.negotiation.ownership import Ownership, split_by_ownership
from ltl_stack.spec import SpecError, clause_in_words, parse_structured
from ltl_stack.spec.formula import And, Not, Var, variables
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.spec.writer import Entry, write_spec_text
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.explain_render import explanation_text
from ltl_stack.synthesis.strategy import SymbolicStrategy


class Negotiation:
    """Alg. 4 for one party (see the module docstring). ``star`` is phi*_r (the original spec, or the
    spec adopted in an earlier negotiation); ``original`` gives phi^t_e (line 2); ``incoming`` and
    ``outputs`` are the current position (lines 6-7)."""

    def __init__(self, star: Spec, classes: Classes, peer: str, *, incoming: Mapping[str, bool],
                 outputs: Mapping[str, bool], original: Spec | None = None, initiator: bool = True,
                 synthesis_options: Mapping[str, Any] | None = None, clock=time.monotonic,
                 wall_clock=time.time, stage: Callable[[Spec, str], Any] | None = None,
                 session: str | None = None) -> None:
        if peer not in classes.peers:
            raise ValueError(f"{classes.robot} has no peer {peer!r} (declared: {', '.join(classes.peers) or 'none'})")
        self.star = star
        self.original = original if original is not None else star
        self.classes = classes
        self.me = classes.robot
        self.peer = classes.peers[peer]
        self.initiator = initiator
        #: "<initiator>-><responder>", with "#<k>" after the initiator's k-th adoption (a pair may
        #: negotiate again once what one of them runs has changed: ``sessions.Negotiator``)
        self.session = session or (f"{self.me}->{peer}" if initiator else f"{peer}->{self.me}")
        self.incoming = {n: bool(incoming[n]) for n in star.inputs}
        self.outputs = {n: bool(outputs[n]) for n in star.outputs}
        self.synthesis_options = dict(synthesis_options or {})
        self.clock, self.wall_clock = clock, wall_clock
        self.started = wall_clock()
        self.finished: float | None = None
        self.phase = Phase.NEW
        self.outcome: Outcome | None = None
        self.reason = ""
        self.adopted: Adoption | None = None
        self.explanation = ""
        self.sent: list[str] = []          # clauses in words, for ~state / the trace
        self.received: list[str] = []
        self.dropped: list[str] = []       # our goals the peer cannot express (not sent)
        self.log: list[str] = []           # what happened, in order
        self.syntheses = 0                 # at most two (§4.9)
        self._offer: Message | None = None
        self._nego: tuple[Spec, str, SymbolicStrategy | None] | None = None
        self._nego_reason = ""
        self._star_candidate: tuple[Spec, str, SymbolicStrategy | None, bool] | None = None
        self._status: dict[int, bool] = {}
        self._peer_status: dict[int, bool] = {}
        #: two-phase adoption (staging): writes phi* aside before our realizable status 2 is sent
        #: (returns what ``commit`` needs; raises ``OSError``); None: nothing to write
        self.stage = stage
        self.staged: Any = None
        self._stage_error = ""
        #: the case agreed (4.8.1/4.8.2) once both statuses 2 are realizable; ``outcome`` becomes it when
        #: this robot adopted and knows the peer did (commit protocol)
        self.agreed: Outcome | None = None
        self._prepared: Adoption | None = None
        #: the responder's reply to each (kind, round) it handled: a duplicate gets the same reply
        self.answered: dict[tuple[str, int], Message] = {}
        #: serializes ``receive``, ``fail`` and ``cancel`` (another thread may cancel an initiation)
        self._lock = threading.RLock()
        #: how each received assumption is kept (``ownership.split_by_ownership``), once the offer is read
        self.ownership: Ownership | None = None

    # --- line 3: what we send -----------------------------------------------------------------------
    def offer(self) -> Message:
        """Our phi^{t(r_env)}_{e,r} and phi^g_{s,r} in the peer's names (Alg. 4 line 3)."""
        if self._offer is not None:
            return self._offer
        if self.phase is not Phase.NEW:
            raise ProtocolFault(f"offer requested in phase {self.phase.value}")
        table = {**{s: s for s in self.classes.global_sensors}, **self.peer.table}
        header = [f"# Alg. 4 line 3: {self.me}'s assumptions about {self.peer.name} (phi^t(r_env)_e) and goals "
                  f"(phi^g_s), in {self.peer.name}'s names",
                  f"# session {self.session}"]
        english = []
        sections = (("sys_safety", assumptions_about(self.original, self.classes, self.peer.name), "assumption"),
                    ("env_liveness", list(self.star.sys_liveness), "goal"))
        entries: dict[str, list[Entry]] = {}
        for section, clauses, what in sections:
            lines = entries.setdefault(section, [])
            for clause in clauses:
                missing = sorted({v.name for v in variables(clause.formula) if v.name not in table})
                if missing:
                    note = (f"{what} {clause.location} mentions {', '.join(missing)}, which {self.peer.name} "
                            "does not observe")
                    if what == "assumption":
                        # the peer cannot guarantee what it cannot see: say so, it then cannot incorporate
                        lines.append(f"# untranslatable {note}")
                        lines.append("FALSE")
                        english.append(f"{what} {clause.location} cannot be expressed for {self.peer.name}")
                    else:
                        self.dropped.append(note)  # one env liveness fewer for the peer: sound (it assumes less)
                    continue
                renamed = rename(clause.formula, table)
                lines.append(f"# {self.me} {clause.location}: {' '.join(clause.text.split())}")
                lines.append(renamed)
                english.append(f"{what} ({clause.location}): {clause_in_words(renamed, section)}")
        text = write_spec_text(entries, header=header)
        self.sent = english
        self._offer = Message(OFFER, self.me, self.session, 0, text, tuple(english))
        if self.phase is Phase.NEW:
            self.phase = Phase.OFFERED
        self._note(f"sent {len(english)} clause(s) to {self.peer.name}"
                   + (f"; {len(self.dropped)} goal(s) not expressible for it" if self.dropped else ""))
        return self._offer

    # --- receiving ------------------------------------------------------------------------------------
    def receive(self, message: Message) -> None:
        """Take the peer's next message; a protocol fault ends the negotiation as FAILED."""
        with self._lock:
            self._receive(message)

    def cancel(self, reason: str) -> bool:
        """End a negotiation that has not ended (FAILED, nothing adopted), from any thread: our
        initiation whose peer's offer we answer instead. False when it had already ended."""
        with self._lock:
            if self.phase is Phase.DONE:
                return False
            self.fail(reason)
            return True

    def _receive(self, message: Message) -> None:
        if message.kind == COMMIT and message.sender == self.peer.name and message.session == self.session:
            self._on_commit()
            return
        if self.phase is Phase.DONE:
            return
        try:
            if message.sender != self.peer.name or message.session != self.session:
                raise ProtocolFault(f"message from {message.sender!r} (session {message.session!r}) in the "
                                    f"negotiation {self.session}")
            if message.kind == ABORT:
                raise ProtocolFault(f"{self.peer.name} aborted the negotiation: {message.reason or 'no reason'}")
            if message.kind == OFFER:
                self._on_offer(message)
            elif message.kind == STATUS:
                self._on_status(message)
            else:
                raise ProtocolFault(f"unknown message kind {message.kind!r}")
        except ProtocolFault as fault:
            self.fail(str(fault))

    def _on_offer(self, message: Message) -> None:
        if self.phase is Phase.NEW and not self.initiator:
            self.offer()
        if self.phase is not Phase.OFFERED:
            raise ProtocolFault(f"offer received in phase {self.phase.value}")
        decl = ["[INPUT]", *self.star.inputs, "[OUTPUT]", *self.star.outputs]
        where = f"offer from {self.peer.name}"
        refusal = offer_refusal(message.text)
        if refusal is not None:
            raise ProtocolFault(refusal)
        try:
            received = parse_structured(message.text + "\n" + "\n".join(decl) + "\n", where)
        except SpecError as err:
            raise ProtocolFault(f"garbled specification text: {err}") from None
        if received.env_safety or received.sys_init or received.env_init or received.sys_liveness:
            raise ProtocolFault(f"{where}: only [SYS_TRANS] and [ENV_LIVENESS] may be sent")
        owned = split_by_ownership(received.sys_safety, self.star, {**self.incoming, **self.outputs})
        self.ownership = owned
        self.received = [f"assumption of {self.peer.name}: {clause_in_words(c, 'sys_safety')}"
                         for c in owned.by_move + owned.rewritten]
        self.received += [f"assumption of {self.peer.name} over what this robot senses, kept as sent (a guarantee "
                          f"only if its moves can keep it): {clause_in_words(c, 'sys_safety')}" for c in owned.literal]
        self.received += [f"goal of {self.peer.name}: {clause_in_words(c, 'env_liveness')}"
                          for c in received.env_liveness]
        self._note(f"received {len(received.sys_safety)} assumption(s) ({len(owned.rewritten)} kept through our "
                   f"activations, {len(owned.literal)} over our sensors kept as sent) and "
                   f"{len(received.env_liveness)} goal(s) from {self.peer.name}")
        # lines 5-9: every received assumption is a guarantee (ownership decides only its form)
        extra = {"sys_safety": owned.guarantees, "env_liveness": received.env_liveness}
        try:
            spec, text = self._spec(self.star, extra, "phi^nego (Alg. 4 line 8)")
        except SpecError as err:
            raise ProtocolFault(f"garbled specification text: {err}") from None
        strategy = self._synthesize(spec)
        self._nego = (spec, text, strategy)
        self._status[1] = strategy is not None
        self._note(f"phi^nego {'realizable' if strategy is not None else 'unrealizable'} (line 9)")
        if strategy is None and owned.literal:
            self._note(f"this robot cannot guarantee what it only senses: {len(owned.literal)} received clause(s) "
                       f"over its sensors ({', '.join(c.location for c in owned.literal)}) are in phi^nego")
        self.phase = Phase.SYNTHESIZED

    def status(self, round_: int) -> Message:
        """Our synthesis status for exchange ``round_`` (Alg. 4 line 10 or 18); a status 2 whose spec
        could not be written aside says so (the peer then fails too: nothing adopted on either side)."""
        if round_ not in self._status:
            raise ProtocolFault(f"status {round_} requested in phase {self.phase.value}")
        reason = self._stage_error if round_ == 2 else ""
        return Message(STATUS, self.me, self.session, round_, realizable=self._status[round_], reason=reason)

    def _on_status(self, message: Message) -> None:
        expected = 1 if self.phase is Phase.SYNTHESIZED else 2 if self.phase is Phase.DECIDED else None
        if expected is None or message.round != expected:
            raise ProtocolFault(f"status {message.round} received in phase {self.phase.value}")
        self._peer_status[message.round] = bool(message.realizable)
        if expected == 2 and message.reason.startswith(WRITE_FAILED):
            raise ProtocolFault(f"{self.peer.name} {message.reason[:300]}")
        if expected == 1:
            self._decide(bool(message.realizable))
        else:
            self._finish(bool(message.realizable))

    def _decide(self, peer_nego: bool) -> None:
        """Lines 11-17."""
        spec, text, strategy = self._nego
        if strategy is not None:
            self._star_candidate = (spec, text, strategy, True)
            self._status[2] = True
            self._note("phi* <- phi^nego (line 12)")
            self._stage(spec, text)
        elif peer_nego:
            star_spec, star_text = self._spec(self.star, {}, "phi* with the new init (Alg. 4 line 14)")
            star_strategy = self._synthesize(star_spec)
            self._star_candidate = (star_spec, star_text, star_strategy, False)
            self._status[2] = star_strategy is not None
            if star_strategy is not None:
                self._stage(star_spec, star_text)
            self._note(f"{self.peer.name} can incorporate our specification; phi* with the new init is "
                       f"{'realizable' if star_strategy is not None else 'unrealizable'} (lines 14-15)")
        else:
            self._status[2] = False
            self._end(Outcome.BOTH_ABORT, "neither robot can incorporate the other's specification (line 17)",
                      explain_spec=spec, keep_phase=True)
        self.phase = Phase.DECIDED

    def _finish(self, peer_star: bool) -> None:
        """Lines 18-21."""
        if self.outcome is Outcome.BOTH_ABORT:
            self.phase = Phase.DONE
            return
        spec, text, strategy, incorporated = self._star_candidate
        if self._stage_error:
            self.fail(f"this robot {self._stage_error}")
            return
        if strategy is None or not peer_star:
            who = "ours" if strategy is None else f"{self.peer.name}'s"
            self._end(Outcome.ABORT_LINE_20, f"phi* ({who}) is unrealizable (line 20)",
                      explain_spec=spec if strategy is None else None)
            return
        adoption = Adoption(spec, text, strategy, incorporated)
        if incorporated and self._peer_status.get(1):
            self.agreed = Outcome.BOTH_ADOPT
        elif incorporated:
            self.agreed = Outcome.ADOPTED_PEERS
        else:
            self.agreed = Outcome.KEPT_OWN
        what = "phi^nego" if incorporated else "phi* with the new init"
        if self.initiator:  # the decision: commit; we adopt, the peer is told (``commit_message``)
            self.adopted = adoption
            self._end(Outcome.UNCONFIRMED, f"adopted {what}; {self.peer.name} has not confirmed yet")
        else:  # bound by our status 2: we adopt when the initiator's decision arrives
            self._prepared = adoption
            self.phase = Phase.PREPARED
            self._note(f"prepared to adopt {what}: waiting for {self.peer.name}'s decision")

    def _on_commit(self) -> None:
        """The commit protocol: the initiator's decision (responder) or the responder's confirmation
        (initiator). Repeated messages change nothing."""
        if self.initiator:
            if self.outcome is Outcome.UNCONFIRMED and self.agreed is not None:
                self.outcome, self.reason = self.agreed, f"adopted; {self.peer.name} confirmed its adoption"
                self._note(f"{self.agreed.value}: {self.reason}")
        elif self.phase is Phase.PREPARED and self._prepared is not None:
            self.adopted = self._prepared
            self._end(self.agreed, f"adopted on {self.peer.name}'s decision")

    def commit_message(self) -> Message:
        """The initiator's decision (after both realizable statuses 2), or the responder's confirmation."""
        return Message(COMMIT, self.me, self.session)

    @property
    def unresolved(self) -> bool:
        """Whether this party still waits for the peer (the commit protocol): an initiator whose
        adoption is not confirmed, a responder prepared without the decision."""
        return self.outcome is Outcome.UNCONFIRMED or self.phase is Phase.PREPARED

    def fail(self, reason: str) -> None:
        """A fault (timeout, peer gone, garbled text, protocol error): nothing is adopted."""
        with self._lock:
            if self.phase is Phase.DONE:
                return
            self.adopted = None
            self._end(Outcome.FAILED, reason)

    def _stage(self, spec: Spec, text: str) -> None:
        """Phase one of the adoption: phi* written aside before our realizable status 2 (a failure
        turns the status into a refusal that names it)."""
        if self.stage is None:
            return
        try:
            self.staged = self.stage(spec, text)
        except OSError as err:
            self._status[2] = False
            self._stage_error = f"{WRITE_FAILED} {getattr(err, 'filename', '') or ''}: {err.strerror or err}"
            self._note(self._stage_error)

    def abort_message(self) -> Message:
        return Message(ABORT, self.me, self.session, reason=self.reason or "aborted")

    @property
    def done(self) -> bool:
        return self.phase is Phase.DONE

    def report(self) -> dict[str, Any]:
        """What ``~state`` / the trace show: with whom, what was sent and received, outcome."""
        return {"peer": self.peer.name, "session": self.session, "initiator": self.initiator,
                "phase": self.phase.value, "outcome": self.outcome.value if self.outcome else None,
                "case": self.outcome.name if self.outcome else None, "reason": self.reason,
                "sent": list(self.sent), "received": list(self.received), "dropped": list(self.dropped),
                "status": {str(k): v for k, v in self._status.items()},
                "peer_status": {str(k): v for k, v in self._peer_status.items()},
                "explanation": self.explanation, "log": list(self.log), "started": self.started,
                "finished": self.finished, "syntheses": self.syntheses}

    # --- internals --------------------------------------------------------------------------------------
    def _end(self, outcome: Outcome, reason: str, explain_spec: Spec | None = None, keep_phase: bool = False) -> None:
        self.outcome, self.reason = outcome, reason
        self.finished = self.wall_clock()
        if explain_spec is not None:
            try:
                self.explanation = explanation_text(explain(explain_spec, robotics_semantics=self.synthesis_options.get(
                    "robotics_semantics", True)))
            except Exception as err:  # noqa: BLE001 - an explanation must never turn an abort into a crash
                self.explanation = f"(no explanation: {err})"
        if not keep_phase:
            self.phase = Phase.DONE
        self._note(f"{outcome.value}: {reason}")

    def _note(self, message: str) -> None:
        self.log.append(message)

    def _synthesize(self, spec: Spec) -> SymbolicStrategy | None:
        self.syntheses += 1
        result = synthesize(spec, **self.synthesis_options)
        return result.strategy if result.realizable else None

    def _spec(self, base: Spec, extra: Mapping[str, list[Clause]], what: str) -> tuple[Spec, str]:
        """``base`` with init from the current position (lines 6-7), env safety phi^t_e of ``original``
        (line 2) and ``extra`` clauses appended, as structured spec text and parsed back from it."""
        header = [f"# {self.me}: {what}, negotiated with {self.peer.name} (thesis §4.8, Alg. 4) "
                  f"at {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(self.wall_clock()))}",
                  f"# from {base.source}. It loads like any spec: synthesize FILE, controller_executor FILE.", ""]
        sections: dict[str, list[Entry]] = {}
        for section in SECTIONS:
            out = sections.setdefault(section, [])
            if section in ("env_init", "sys_init"):
                names, values = ((base.inputs, self.incoming) if section == "env_init" else (base.outputs, self.outputs))
                out.append(f"# Alg. 4 line {6 if section == 'env_init' else 7}: the current "
                           f"{'inputs' if section == 'env_init' else 'outputs'}")
                literals = [Var(n) if values[n] else Not(Var(n)) for n in names]
                out.append(literals[0] if len(literals) == 1 else And(tuple(literals)))
            else:
                clauses = self.original.env_safety if section == "env_safety" else base.section(section)
                if section == "env_safety":
                    out.append("# Alg. 4 line 2: the original environment safety (no characterization disjuncts)")
                for c in clauses:
                    out.append(f"# {c.location}: {' '.join(c.text.split())}")
                    out.append(c.formula)
                for c in extra.get(section, []):
                    origin = "assumption" if section == "sys_safety" else "goal"
                    out.append(f"# Alg. 4 line 5: {origin} of {self.peer.name} ({c.text.strip()})")
                    out.append(c.formula)
        text = write_spec_text(sections, header=header, inputs=base.inputs, outputs=base.outputs)
        return parse_structured(text, f"<{self.me} negotiated with {self.peer.name}>"), text


def answer(responder: Negotiation, message: Message) -> Message:
    """The responder's side of one exchange: take ``message``, return ours (an abort on a fault)."""
    if message.kind == COMMIT:
        responder.receive(message)
        return responder.commit_message() if responder.adopted is not None else responder.abort_message()
    key = (message.kind, message.round)
    if key in responder.answered and message.kind != ABORT:
        return responder.answered[key]  # a duplicated message: the same answer, nothing changes
    reply = None
    try:
        if message.kind == OFFER:
            reply = responder.offer()
        elif message.kind == STATUS:
            reply = responder.status(message.round)
    except ProtocolFault as fault:
        responder.fail(str(fault))
    responder.receive(message)
    if responder.outcome is Outcome.FAILED or reply is None:
        if responder.outcome is not Outcome.FAILED:
            responder.fail(f"unexpected {message.kind} message")
        return responder.abort_message()
    responder.answered[key] = reply
    return reply


def drive(initiator: Negotiation, call: Callable[[Message], Message]) -> None:
    """The initiator's side: offer, status 1, status 2 (Alg. 4 lines 3-4, 10, 18), each sent with
    ``call(message) -> reply``. A transport error (``TimeoutError``, ``ConnectionError``, ``OSError``:
    timeout, peer gone) is a fault; after a fault the peer is told (best effort: it may only have lost
    its reply). After both realizable statuses 2 the initiator decides and sends ``commit``
    (``confirm``): the commit protocol of docs/negotiation.md."""
    for make in (initiator.offer, lambda: initiator.status(1), lambda: initiator.status(2)):
        if initiator.done:
            break
        try:
            message = make()
        except ProtocolFault as fault:
            initiator.fail(str(fault))
            break
        try:
            reply = call(message)
        except (TimeoutError, ConnectionError, OSError) as err:
            initiator.fail(f"{initiator.peer.name} did not answer: {err}")  # (it is told below, best effort)
            break
        initiator.receive(reply)
    if not initiator.done:
        initiator.fail("negotiation ended early")
    if initiator.outcome is Outcome.UNCONFIRMED:  # tell the decision; a lost answer is asked again (``confirm``)
        confirm(initiator, call)
        return
    if initiator.outcome is Outcome.FAILED and not initiator.reason.startswith(f"{initiator.peer.name} aborted"):
        try:
            call(initiator.abort_message())
        except (TimeoutError, ConnectionError, OSError):
            pass


def confirm(initiator: Negotiation, call: Callable[[Message], Message]) -> bool:
    """Send the initiator's decision (commit) and take the responder's confirmation; True once
    confirmed. A transport error or any other answer leaves it unconfirmed: sent again later."""
    try:
        reply = call(initiator.commit_message())
    except (TimeoutError, ConnectionError, OSError) as err:
        initiator._note(f"{initiator.peer.name} did not confirm: {err}")
        return False
    if reply.kind == COMMIT:
        initiator.receive(reply)
    else:
        initiator._note(f"{initiator.peer.name} answered the decision with {reply.kind}: {reply.reason[:200]}")
    return initiator.outcome is not Outcome.UNCONFIRMED
