"""One robot's negotiations (both roles) and the glue to its resilient executor (thesis §4.8, Alg. 3 S.2).

``Negotiator`` decides whom to negotiate with, answers other robots' messages, keeps the reports, and
installs what was agreed in the robot's ``ResilientStrategy`` (``hook`` as initiator, ``serve`` as
responder). See the package docstring and docs/negotiation.md.
"""
from __future__ import annotations

import random
import threading
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable, Protocol

from ltl_stack.runtime.resilience.characterize import NegotiationAbort
from ltl_stack.runtime.resilience.negotiation.classes import Classes, Peer
from ltl_stack.runtime.resilience.negotiation.messages import (
    ABORT,
    BUSY,
    COMMIT,
    OFFER,
    OUTCOME,
    SIMULTANEOUS,
    Message,
    Outcome,
    Phase,
    offer_refusal,
)
from ltl_stack.runtime.resilience.negotiation.party import Negotiation, answer, confirm, drive
from ltl_stack.runtime.resilience.negotiation.staging import (
    commit_adopted,
    discard_staged,
    stage_adopted,
    write_adopted,
)
from ltl_stack.spec.formula import evaluate
from ltl_stack.spec.model import Clause, Spec


class NegotiationHost(Protocol):
    """What negotiation needs of a robot's resilient strategy (``runtime.resilience.characterize.ResilientStrategy``
    and the executor's ``BackgroundResilience`` implement it)."""

    lock: Any

    @property
    def aborted(self) -> bool: ...

    def negotiation_base(self) -> Spec: ...

    def rebase(self, spec: Spec) -> None: ...

    @property
    def spec_path(self) -> Path | None: ...

    def negotiation_held(self) -> None: ...

    def install_negotiated(self, spec: Spec, text: str, strategy: Any, inputs: Mapping[str, bool],
                           outputs: Mapping[str, bool], write: bool = True) -> Any: ...

    def abort(self, reason: str = ...) -> None: ...


def count_negotiation(strategy: NegotiationHost) -> None:
    """One more negotiation held by ``strategy``'s robot (``Counters.negotiations``, on ``~state``)."""
    strategy.negotiation_held()


def violated_clauses(spec: Spec, current: Mapping[str, bool], incoming: Mapping[str, bool]) -> list[Clause]:
    """The env-safety clauses of ``spec`` broken by the transition (``current`` position -> ``incoming``)."""
    now = {n: bool(v) for n, v in current.items()}
    nxt = {n: bool(v) for n, v in incoming.items()}
    return [c for c in spec.env_safety if not evaluate(c.formula, now, nxt)]


Transport = Callable[[Peer], Callable[[Message], Message]]


class Negotiator:
    """One robot's negotiations (both roles) and the reports for ``~state`` / the trace.
    ``transport(peer)`` gives the call that sends a message to ``peer`` and returns its answer (an
    in-process responder, or the ROS service).

    **One negotiation at a time** (§4.12: "prioritising and sequencing negotiations"): a robot is in at
    most one negotiation, as initiator or responder, from its offer until what it agreed is installed
    (``current``). An offer that arrives meanwhile is answered ``busy`` (nothing started, nothing used
    up) and its initiator tries again after a random pause of ``retry`` seconds, for up to
    ``answer_wait`` seconds: so each phi^nego is built on the spec the robot runs after every earlier
    adoption, whose system safety holds every promise made so far. A later negotiation that cannot be
    incorporated without breaking an earlier promise makes phi^nego unrealizable: Alg. 4 then gives
    4.8.2 (the other robot incorporates, or this one keeps its spec with all promises) or 4.8.3.

    **When a pair negotiates again.** ``epoch`` counts the adoptions this robot installed. A pair
    negotiates once per state of the world: the initiator starts again with a peer only when its own
    epoch changed since their last negotiation (another adoption changed what it runs); the session
    name carries that epoch (``A->B#2``), and the responder refuses a session it has already had at
    its current epoch ("once per pair")."""

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
        #: each pair that negotiated: (our epoch after it, its session)
        self.partners: dict[frozenset[str], tuple[int, str]] = {}
        #: adoptions installed so far (what this robot runs changed this many times by negotiation)
        self.epoch = 0
        #: the negotiation this robot is in, until what it agreed is installed (None: free)
        self.current: Negotiation | None = None
        #: how long an initiator that yielded, or that finds its peer busy, waits (seconds)
        self.answer_wait = 60.0
        #: the random pause before trying a busy peer again (seconds, lower and upper bound)
        self.retry = (0.1, 0.6)
        self.random = random.Random()
        #: called after every message handled and every negotiation started or ended (reports changed)
        self.on_change: Callable[[Negotiation], None] | None = None

    def _pair(self, peer: str) -> frozenset[str]:
        return frozenset((self.classes.robot, peer))

    def may_initiate(self, peer: str) -> bool:
        """Whether we may start a negotiation with ``peer``: never yet, or what we run changed since."""
        last = self.partners.get(self._pair(peer))
        return last is None or last[0] != self.epoch

    def session_for(self, peer: str) -> str:
        """The name of our next negotiation with ``peer``: ``me->peer``, ``#epoch`` once we adopted."""
        return f"{self.classes.robot}->{peer}" + (f"#{self.epoch}" if self.epoch else "")

    def choose(self, star: Spec, current: Mapping[str, bool], incoming: Mapping[str, bool]) -> str | None:
        """The peer to negotiate with: the first (declaration order) whose eAP inputs appear in the
        violated env-safety clauses and with whom we may negotiate (``may_initiate``)."""
        for peer in self.classes.peers_in(violated_clauses(star, current, incoming)):
            if self.may_initiate(peer):
                return peer
        return None

    def _busy(self) -> str | None:
        """Why a new negotiation cannot start now (under ``lock``), or None."""
        if self.current is not None:
            return f"{BUSY} {self.classes.robot} is negotiating with {self.current.peer.name}; try again"
        return None

    def _record(self, n: Negotiation) -> None:
        """A negotiation took place (under ``lock``): the pair negotiated at our current epoch."""
        self.partners[self._pair(n.peer.name)] = (self.epoch, n.session)

    def release(self, n: Negotiation, installed: bool = False) -> None:
        """``n`` is over and what it agreed (if ``installed``) runs: the next negotiation may start."""
        with self.lock:
            if installed and n.adopted is not None:
                self.epoch += 1
                self._record(n)
            if self.current is n:
                self.current = None

    def initiate(self, star: Spec, peer: str, incoming: Mapping[str, bool], outputs: Mapping[str, bool],
                 hold: bool = False, epoch: int | None = None) -> Negotiation:
        """Run Alg. 4 as the robot that detected the conflict. ``hold``: an adoption keeps this robot
        busy until the caller has installed it (``release``). ``epoch``: ours when ``star`` was read;
        an adoption installed since (a peer's negotiation we answered) makes ``star`` stale, and
        this one fails as busy so that the caller reads the spec again."""
        n = Negotiation(star, self.classes, peer, incoming=incoming, outputs=outputs, initiator=True,
                        synthesis_options=self.synthesis_options, session=self.session_for(peer))
        n.stage = self._stager(n)
        with self.lock:
            busy = self._busy()
            if busy is None and epoch is not None and epoch != self.epoch:
                busy = f"{BUSY} {self.classes.robot} has just adopted a new specification; reading it again"
            if busy is not None:  # we answer someone else: no negotiation of ours, nothing used up
                n.fail(busy)
                return n
            self.current = n
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
                if n.outcome is Outcome.FAILED and BUSY in n.reason:
                    self.history.remove(n)  # the peer was busy: no negotiation took place, none reported
                elif n.outcome is Outcome.FAILED and SIMULTANEOUS in n.reason:
                    self.yielded.add(peer)  # the peer initiates instead: answer theirs
                else:
                    self._record(n)
            if not (hold and n.adopted is not None):
                self.release(n)
        if not (n.outcome is Outcome.FAILED and BUSY in n.reason):
            self._changed(n)
        return n

    def wait_answered(self, peer: str, timeout: float) -> Negotiation | None:
        """After yielding to ``peer`` (simultaneous negotiation, ``respond``): wait up to ``timeout``
        seconds for the negotiation it started to end; that negotiation, or None."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                theirs = [m for m in self.history if not m.initiator and m.peer.name == peer]
                if theirs and theirs[-1].done and self.current is not theirs[-1]:
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

    def _refuse(self, message: Message, reason: str) -> tuple[Message, None]:
        return Message(ABORT, self.classes.robot, message.session, reason=reason), None

    def respond(self, message: Message, star: Spec, incoming: Mapping[str, bool], outputs: Mapping[str, bool],
                epoch: int | None = None, hold: bool = False) -> tuple[Message, Negotiation | None]:
        """Answer one message of a negotiation another robot started; returns our reply and the
        negotiation (done when it ended). ``epoch``: ours when ``star`` was read (an adoption
        installed since makes the offer wait: busy). ``hold``: an adoption keeps this robot busy
        until the caller installed it (``release``)."""
        peer, me = message.sender, self.classes.robot
        if message.kind == OFFER:
            if peer not in self.classes.peers:
                return self._refuse(message, f"{me} has no peer {peer!r}")
            base = f"{peer}->{me}"
            if message.session != base and not (message.session.startswith(base + "#")
                                                 and message.session[len(base) + 1:].isdigit()):
                return self._refuse(message, f"session {message.session[:60]!r} is not {base}[#k]")
            refusal = offer_refusal(message.text)
            if refusal is not None:  # nothing started: the real peer may still negotiate
                return self._refuse(message, refusal)
            mine = self.initiating.get(peer)
            crossing = mine is not None and not mine.done
            if crossing and me < peer:
                # both started at once: the robot whose name sorts first initiates, the other answers
                # (deterministic, and the outcome is the one of negotiating in turn)
                return self._refuse(message, f"{SIMULTANEOUS} {me} initiates (robots negotiate in the order of "
                                             "their names)")
            if crossing:  # ours was built on the spec before this one: it must not adopt anything
                crossing = mine.cancel(f"{SIMULTANEOUS} {peer} initiates (robots negotiate in the order of their "
                                       f"names); {me} answers it")
            if not crossing:
                if self.partners.get(self._pair(peer)) == (self.epoch, message.session):
                    return self._refuse(message, f"{me} already negotiated with {peer} (once per pair)")
                busy = self._busy()
                if busy is None and epoch is not None and epoch != self.epoch:
                    busy = f"{BUSY} {me} has just adopted a new specification; try again"
                if busy is not None:
                    return self._refuse(message, busy)
            else:
                self.yielded.add(peer)
            n = Negotiation(star, self.classes, peer, incoming=incoming, outputs=outputs, initiator=False,
                            synthesis_options=self.synthesis_options, session=message.session)
            n.stage = self._stager(n)
            self.current = n  # (a crossing offer takes over from our own, which the peer refuses)
            self.history.append(n)
            self.active[peer] = n
        elif message.kind == OUTCOME:  # either robot may ask again, in any role
            return Message(OUTCOME, me, message.session, reason=self.state_of(message.session, peer)), None
        else:
            n = self.active.get(peer)
            if message.kind == COMMIT and (n is None or n.session != message.session):
                done = self._session(message.session, peer)  # a repeated decision: confirm again
                if done is not None and done.adopted is not None:
                    return done.commit_message(), None
            if n is None or n.session != message.session:  # (a late message of an earlier session)
                return self._refuse(message, f"no negotiation with {peer} in progress"
                                    + (f" in session {message.session[:60]}" if n is not None else ""))
        reply = answer(n, message)
        if n.done:
            self._end(n, hold)
        self._changed(n)
        return reply, n

    def _session(self, session: str, peer: str) -> Negotiation | None:
        """The latest negotiation named ``session`` with ``peer`` (either role), or None."""
        with self.lock:
            found = [n for n in self.history if n.session == session and n.peer.name == peer]
        return found[-1] if found else None

    def state_of(self, session: str, peer: str) -> str:
        """What this robot knows of ``session`` (the answer to an ``outcome`` question): committed
        (it adopted), aborted (it ended without adopting), prepared (responder waiting for the
        decision), pending (still negotiating), unknown (no such session: nothing was adopted)."""
        n = self._session(session, peer)
        if n is None:
            return "unknown"
        if n.adopted is not None:
            return "committed"
        if n.phase is Phase.PREPARED:
            return "prepared"
        return "aborted" if n.done else "pending"

    def settle(self, strategy: Any = None, controller: Any = None) -> int:
        """The commit protocol after a lost message (call it periodically; the ROS endpoint does): an
        initiator whose adoption is unconfirmed sends its decision again; a responder prepared without
        the decision asks the initiator for the session's outcome and adopts (installed in
        ``strategy``/``controller`` when given) or ends FAILED. Returns how many negotiations moved;
        a peer that cannot be reached is asked again next time."""
        moved = 0
        with self.lock:
            waiting = [n for n in self.history if n.unresolved]
        for n in waiting:
            if self.transport is None:
                break
            call = self.transport(n.peer)
            if n.initiator:
                if confirm(n, call):
                    moved += 1
                    self._changed(n)
                continue
            try:
                reply = call(Message(OUTCOME, self.classes.robot, n.session))
            except (TimeoutError, ConnectionError, OSError):
                continue
            if reply.kind != OUTCOME or reply.reason not in ("committed", "aborted", "unknown"):
                continue
            with self.lock:
                if not n.unresolved:  # the decision arrived meanwhile (and was installed there)
                    continue
                if reply.reason == "committed":
                    n.receive(Message(COMMIT, n.peer.name, n.session))
                else:
                    n.fail(f"{n.peer.name} did not adopt ({reply.reason}): nothing adopted")
                self._end(n, hold=True)
            self._changed(n)
            moved += 1
            if strategy is not None:
                count_negotiation(strategy)
            if n.adopted is not None and strategy is not None:
                self._install(n, strategy, controller)
            else:
                if n.adopted is not None:
                    self.commit(n)
                self.release(n, installed=n.adopted is not None)
        return moved

    def _end(self, n: Negotiation, hold: bool) -> None:
        """The responder's negotiation ``n`` ended (under ``lock``)."""
        if self.active.get(n.peer.name) is n:
            self.active.pop(n.peer.name)
        if n.adopted is None:
            discard_staged(n.staged)
        if not (n.outcome is Outcome.FAILED and n._nego is None):
            self._record(n)  # (an offer refused before it was read is no negotiation)
        if not (hold and n.adopted is not None):
            self.release(n)

    def expire(self, peer: str, reason: str) -> Negotiation | None:
        """The responder's timeout: the initiator went silent mid-negotiation."""
        with self.lock:
            n = self.active.get(peer)
            if n is None or n.phase is Phase.PREPARED:  # bound by our status 2: ask (``settle``), not fail
                return None
            n.fail(reason)
            self._end(n, hold=False)
        self._changed(n)
        return n

    def reports(self) -> list[dict[str, Any]]:
        return [n.report() for n in self.history]

    # --- with a ResilientStrategy (runtime.resilience.characterize) -------------------------------------------------
    def hook(self, strategy: Any, observation: Any) -> Spec | None:
        """``ResilientStrategy(negotiate=negotiator.hook)`` (the executor's negotiation hook,
        docs/resilience.md): Alg. 3 line 9. Negotiates with the peer whose eAP inputs the violated
        clauses mention, on the spec the robot runs now (after every earlier adoption); a busy peer
        is tried again after a random pause, for up to ``answer_wait`` seconds. On adoption the
        negotiated spec becomes the strategy's base spec phi* (later characterizations start from it
        with empty EC sets, Alg. 4 line 2), is written atomically to the characterized-spec path,
        and is returned for the strategy to run. Alg. 3 by cause (§4.4): None — the strategy goes to
        S.1, explanation and the user — when no peer is involved, the pair already negotiated, or the
        negotiation failed (a peer absent, silent or busy for too long is uncontrollable
        environment); ``NegotiationAbort`` when the robots negotiated and cannot agree (4.8.3, line 20)."""
        current = {**observation.current_inputs, **observation.current_outputs}
        deadline = time.monotonic() + self.answer_wait
        while True:
            with self.lock:
                epoch = self.epoch
            with strategy.lock:
                star = strategy.negotiation_base()
            peer = self.choose(star, current, observation.incoming)
            if peer is None:
                return None
            n = self.initiate(star, peer, observation.incoming, observation.current_outputs, hold=True, epoch=epoch)
            if not (n.outcome is Outcome.FAILED and BUSY in n.reason) or time.monotonic() > deadline:
                break
            time.sleep(self.random.uniform(*self.retry))
        if peer in self.yielded:  # we answer the peer's negotiation instead (serve installs and counts it)
            self.wait_answered(peer, self.answer_wait)
            with self.lock:
                self.yielded.discard(peer)
            return None
        if n.outcome is Outcome.FAILED and BUSY in n.reason:
            return None
        count_negotiation(strategy)
        if n.outcome in (Outcome.BOTH_ABORT, Outcome.ABORT_LINE_20):
            raise NegotiationAbort(f"negotiation with {peer}: {n.outcome.value}")
        adopted = n.adopted
        if adopted is None:
            return None
        try:
            with strategy.lock:  # the executor steps meanwhile
                strategy.rebase(adopted.spec)
            if not self.commit(n) and strategy.spec_path is not None:
                write_adopted(adopted, strategy.spec_path)
        finally:
            self.release(n, installed=True)
        return adopted.spec

    def serve(self, message: Message, strategy: Any, controller: Any, start_wait: float = 0.0) -> Message:
        """Answer a peer's message for the robot running ``controller`` (a ``runtime.Controller`` over
        ``strategy``, a ``ResilientStrategy``). The position is read under the controller's lock; the
        message (parsing, synthesis) is handled under the negotiator's lock only, so the controller
        keeps stepping meanwhile; an adopted spec is installed under the controller's lock
        (``strategy.adopt``) from the position the negotiation started at (the adopted spec's init;
        the controller's next step continues from there with the current readings); 4.8.3 / line 20
        abort the strategy (its safe outputs). This robot stays busy for other offers until then. A
        controller that has not started yet (inputs still silent) is waited for up to ``start_wait``
        seconds; then, and once aborted, the answer is an abort."""
        deadline = time.monotonic() + start_wait
        while controller.state is None and time.monotonic() < deadline:
            time.sleep(0.02)  # our controller starts once every input has reported (not under the lock)
        with controller.lock:
            state = controller.state
            aborted = strategy.aborted
            if state is None or aborted:
                why = "has aborted" if aborted else "has not started"
                return Message(ABORT, self.classes.robot, message.session, reason=f"{self.classes.robot} {why}")
            with self.lock:
                epoch = self.epoch
            star, inputs, outputs = strategy.negotiation_base(), dict(state.inputs), dict(state.outputs)
        with self.lock:
            reply, n = self.respond(message, star, inputs, outputs, epoch=epoch, hold=True)
        if n is None or not n.done:
            return reply
        count_negotiation(strategy)
        if n.adopted is not None:
            self._install(n, strategy, controller)
        elif n.outcome in (Outcome.BOTH_ABORT, Outcome.ABORT_LINE_20):
            with controller.lock:
                strategy.abort(f"negotiation with {n.peer.name}: {n.outcome.value}")
        return reply

    def _install(self, n: Negotiation, strategy: Any, controller: Any) -> None:
        """The responder's adoption of ``n``: its staged file committed, its spec installed under the
        controller's lock from the position the negotiation started at (its init); then the robot is
        free for the next negotiation."""
        try:
            written = self.commit(n)
            with controller.lock:
                state = strategy.install_negotiated(n.adopted.spec, n.adopted.text, n.adopted.strategy, n.incoming,
                                                    n.outputs, write=not written)
                if state is not None:  # (the executor node continues with the current readings itself)
                    controller.state = state
        finally:
            self.release(n, installed=True)
