"""Integrative negotiation between two robots without ROS (thesis §4.8, Alg. 4; Def. 4.3.1, Table 4.1).

**Proposition classes.** Which inputs abstract another robot's behaviour (eAP_r, Table 4.1's
pi^r_{prop,r'}) and which are global sensors (Sen_G) is declared in the robot's *mapping* file, under
the top-level key ``negotiation:`` (the mapping already says which topic feeds each input, so it is
where "this input is robot A's openDoor" belongs; the spec stays a plain GR(1) spec)::

    negotiation:
      robot: D                       # this robot's name, as its peers call it
      global_sensors: [ingredientArrived]        # Sen_G: same name for every robot
      peers:
        A:
          service: /kitchen/A/negotiate         # optional (ROS adapter); default <peer ns>/negotiate
          eap: {openDoor_A: openDoor}           # eAP_D about A: my input -> A's proposition
          shares: {road_c: road_c_D}            # my proposition -> A's input that abstracts it

``eap`` and ``shares`` together are the translation table between the two namespaces: a formula
sent to A is renamed with it (Sen_G names unchanged), and A parses it against its own declarations.

**phi^{t(r_env)}_{e,r}** (§4.8): the env-safety clauses of the spec that mention an eAP input about
r_env (``assumptions_about``).

**Alg. 4 for one party** (``Negotiation``), driven by messages (``Message``) in this order, the same
for both robots (the transport decides who sends first; the initiator sends, the responder answers):

1. ``offer()`` (line 3): phi^{t(r_env)}_{e,r} and phi^g_{s,r}, renamed into r_env's names, as
   structured spec text (``[SYS_TRANS]`` / ``[ENV_LIVENESS]`` of the receiver) — the received
   assumptions become system safety and the received goals environment liveness (line 5), except
   that a received assumption no next move of the receiver can keep (no next-state output of its
   own) is kept through the activations its completion sensors report (``road_c'`` -> ``road'``), or,
   when no move of the receiver can keep it, becomes an environment assumption of the receiver
   (``split_by_ownership``: a robot guarantees only what it controls);
2. ``receive(offer)`` (lines 4-9): parse it against our propositions (garbled text or an unknown
   name is a fault), phi^nego = init from the current state (lines 6-7: incoming inputs, current
   outputs), original env safety phi^t_e (line 2: the EC disjuncts are dropped), phi*^t_s /\\ received
   assumptions, phi*^g_e /\\ received goals; synthesize;
3. ``status(1)`` / ``receive(status 1)`` (lines 10-17): if phi^nego is realizable it becomes phi*;
   else if the peer's is, phi* is resynthesized with the new init (4.8.2); else both abort (4.8.3);
4. ``status(2)`` / ``receive(status 2)`` (lines 18-21): phi* is adopted only when both phi* are
   realizable; otherwise abort (line 20).

Faults — a message out of order, garbled spec text, a peer that sends ``abort``, a timeout or a
vanished peer reported by the transport (``fail``) — end the negotiation as ``FAILED``: nothing is
adopted (no half-adopted spec). The party that started it (its own spec is unrealizable, Alg. 3)
then aborts with safe outputs; the responder keeps the controller it was running, which is still
correct for its own spec. A party adopts only after it synthesized a realizable phi* *and* received
the peer's realizable second status (``adopted`` is None otherwise).
"""
from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any, Callable

from ltl_stack.errors import UserError
from ltl_stack.fileio import write_atomic
from ltl_stack.runtime.characterize import NegotiationAbort
from ltl_stack.runtime.mapping import Mapping as MappingFile
from ltl_stack.spec import SpecError, clause_to_english, formula_to_infix, parse_structured, write_slugsin
from ltl_stack.spec.formula import And, Formula, Not, Var, evaluate, variables
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.spec.ops import map_vars
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.explain_render import explanation_text
from ltl_stack.synthesis.strategy import SymbolicStrategy

#: bounds of a received offer (issue 23): its text and its clauses; larger offers are refused in one line
MAX_OFFER_BYTES = 64 * 1024
MAX_OFFER_CLAUSES = 200
#: the sections an offer may hold (Alg. 4 line 3: assumptions to guarantee, goals to assume)
OFFER_SECTIONS = ("[SYS_TRANS]", "[ENV_LIVENESS]")
HEADERS = {"env_init": "ENV_INIT", "sys_init": "SYS_INIT", "env_safety": "ENV_TRANS",
           "sys_safety": "SYS_TRANS", "env_liveness": "ENV_LIVENESS", "sys_liveness": "SYS_LIVENESS"}
OFFER, STATUS, ABORT = "offer", "status", "abort"
#: how a status 2 says the adopted spec could not be written (two-phase adoption)
WRITE_FAILED = "cannot write its adopted specification"
#: the refusal of an offer that crossed ours (both robots started at once)
SIMULTANEOUS = "simultaneous negotiation:"


class NegotiationError(UserError):
    """A ``negotiation:`` declaration that cannot be used (``file:line: message``, exit code 2)."""

    def __init__(self, file: str, line: int, message: str) -> None:
        self.file, self.line, self.message = file, line, message
        super().__init__(f"{file}:{line}: {message}" if line else f"{file}: {message}")


# --- proposition classes (Def. 4.3.1) -------------------------------------------------------------
@dataclass(frozen=True)
class Peer:
    """A collaborative robot and the translation table between its namespace and ours."""

    name: str
    eap: dict[str, str]           # our input -> the peer's proposition it abstracts (eAP about the peer)
    shares: dict[str, str]        # our proposition -> the peer's input that abstracts it
    service: str | None = None

    @property
    def table(self) -> dict[str, str]:
        """Our name -> the peer's name, for every proposition both robots know."""
        return {**self.shares, **self.eap}


@dataclass(frozen=True)
class Classes:
    """The proposition classes of one robot: its name, eAP per peer, Sen_G."""

    robot: str
    peers: dict[str, Peer] = field(default_factory=dict)
    global_sensors: tuple[str, ...] = ()
    file: str = "<memory>"
    line: int = 0

    def eap(self, peer: str | None = None) -> set[str]:
        """eAP_r (about ``peer``, or about any peer)."""
        peers = [self.peers[peer]] if peer is not None else list(self.peers.values())
        return {name for p in peers for name in p.eap}

    def peers_in(self, clauses: list[Clause]) -> list[str]:
        """The peers whose behaviour the clauses mention (through eAP inputs), in declaration order."""
        names = {v.name for c in clauses for v in variables(c.formula)}
        return [p for p, peer in self.peers.items() if names & set(peer.eap)]

    def check(self, spec: Spec) -> list[str]:
        """Problems of this declaration against ``spec`` (empty: usable)."""
        where = f"{self.file}:{self.line}" if self.line else self.file
        problems = []
        inputs, props = set(spec.inputs), set(spec.propositions)
        for name in self.global_sensors:
            if name not in inputs:
                problems.append(f"{where}: negotiation.global_sensors: {name!r} is not an input of {spec.source}")
        for peer in self.peers.values():
            for name in peer.eap:
                if name not in inputs:
                    problems.append(f"{where}: negotiation.peers.{peer.name}.eap: {name!r} is not an input of "
                                    f"{spec.source}")
                if name in self.global_sensors:
                    problems.append(f"{where}: negotiation.peers.{peer.name}.eap: {name!r} is also a global sensor")
            for name in peer.shares:
                if name not in props:
                    problems.append(f"{where}: negotiation.peers.{peer.name}.shares: {name!r} is not a proposition "
                                    f"of {spec.source}")
            seen: dict[str, str] = {}
            for mine, theirs in peer.table.items():
                if theirs in seen and seen[theirs] != mine:
                    problems.append(f"{where}: negotiation.peers.{peer.name}: {seen[theirs]!r} and {mine!r} both "
                                    f"translate to {theirs!r}")
                seen[theirs] = mine
        return problems


def classes_from_data(data: Any, file: str = "<memory>", line: int = 0) -> Classes:
    """The ``negotiation:`` value of a mapping (see the module docstring); ``NegotiationError`` when malformed."""
    def fail(message: str) -> NegotiationError:
        return NegotiationError(file, line, f"negotiation: {message}")

    if not isinstance(data, dict):
        raise fail("expected a mapping with robot:, peers: and optionally global_sensors:")
    unknown = set(data) - {"robot", "peers", "global_sensors"}
    if unknown:
        raise fail(f"unknown key(s) {', '.join(sorted(map(str, unknown)))} (expected robot, peers, global_sensors)")
    robot = data.get("robot")
    if not isinstance(robot, str) or not robot.strip():
        raise fail("robot: must name this robot")
    sensors = data.get("global_sensors") or []
    if not isinstance(sensors, list) or not all(isinstance(s, str) for s in sensors):
        raise fail("global_sensors: must be a list of input names")
    peers_data = data.get("peers") or {}
    if not isinstance(peers_data, dict):
        raise fail("peers: must map robot names to {eap:, shares:, service:}")
    peers = {}
    for name, value in peers_data.items():
        if not isinstance(value, dict):
            raise fail(f"peers.{name}: expected a mapping with eap:, shares:, service:")
        bad = set(value) - {"eap", "shares", "service"}
        if bad:
            raise fail(f"peers.{name}: unknown key(s) {', '.join(sorted(map(str, bad)))} (expected eap, shares, service)")
        tables = {}
        for key in ("eap", "shares"):
            table = value.get(key) or {}
            if not isinstance(table, dict) or not all(isinstance(k, str) and isinstance(v, str)
                                                      for k, v in table.items()):
                raise fail(f"peers.{name}.{key}: must map proposition names to proposition names")
            tables[key] = dict(table)
        service = value.get("service")
        if service is not None and not isinstance(service, str):
            raise fail(f"peers.{name}.service: must be a ROS service name")
        if str(name) == robot:
            raise fail(f"peers.{name}: a robot does not negotiate with itself")
        peers[str(name)] = Peer(str(name), tables["eap"], tables["shares"], service)
    return Classes(robot.strip(), peers, tuple(sensors), file, line)


def classes_from_mapping(mapping: MappingFile) -> Classes | None:
    """The proposition classes a mapping declares (its ``negotiation:`` key), None when it has none."""
    if mapping.negotiation is None:
        return None
    return classes_from_data(mapping.negotiation, mapping.file, mapping.negotiation_line)


def negotiation_classes(mapping: MappingFile | None, spec: Spec) -> Classes | None:
    """The classes a mapping declares, checked against ``spec`` (``NegotiationError`` listing every
    problem); None without a mapping or a ``negotiation:`` key."""
    classes = classes_from_mapping(mapping) if mapping is not None else None
    if classes is not None:
        problems = classes.check(spec)
        if problems:
            raise NegotiationError(classes.file, classes.line,
                                   "; ".join(p.split(": ", 1)[1] if ": " in p else p for p in problems))
    return classes


def assumptions_about(spec: Spec, classes: Classes, peer: str) -> list[Clause]:
    """phi^{t(r_env)}_{e,r} (§4.8): the env-safety clauses that mention an eAP input about ``peer``."""
    eap = classes.eap(peer)
    return [c for c in spec.env_safety if any(v.name in eap for v in variables(c.formula))]


#: name endings of completion sensors (activation-completion, thesis §4.3): ``R_c`` / ``R_rc`` / ``a_ac``
#: report that the robot's own output ``R`` / ``a`` took effect
COMPLETION_SUFFIXES = ("_rc", "_ac", "_c")


def action_of(sensor: str, outputs: list[str]) -> str | None:
    """The receiver's output whose completion ``sensor`` reports (``road_c`` -> ``road``), or None."""
    for suffix in COMPLETION_SUFFIXES:
        if sensor.endswith(suffix) and sensor[:-len(suffix)] in outputs:
            return sensor[:-len(suffix)]
    return None


def offer_refusal(text: str) -> str | None:
    """Why an offer's text is refused before it is parsed (one line), or None: larger than
    ``MAX_OFFER_BYTES`` or ``MAX_OFFER_CLAUSES``, or declaring a section other than ``[SYS_TRANS]``
    and ``[ENV_LIVENESS]`` (an offer may not declare propositions or touch the receiver's init)."""
    size = len(text.encode("utf-8", "replace"))
    if size > MAX_OFFER_BYTES:
        return f"offer refused: {size} bytes (at most {MAX_OFFER_BYTES})"
    clauses = 0
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if stripped.startswith("[") and stripped.endswith("]"):
            if stripped not in OFFER_SECTIONS:
                return (f"offer refused: line {number} declares {stripped[:40]}; an offer holds only "
                        f"{' and '.join(OFFER_SECTIONS)}")
            continue
        clauses += 1
    if clauses > MAX_OFFER_CLAUSES:
        return f"offer refused: {clauses} clauses (at most {MAX_OFFER_CLAUSES})"
    return None


def caller_refusal(caller: str, sender: str, peers: Mapping[str, str]) -> str | None:
    """Why a message whose transport says it comes from node ``caller`` and which names ``sender``
    is refused, or None. ``peers`` maps each declared peer to the node that serves its negotiation
    (its ``~negotiate`` service's node): only that node may speak for it. ROS 1 does not
    authenticate the caller id; this keeps honest misconfigurations and stray nodes out, not an
    attacker (docs/negotiation.md)."""
    if sender not in peers:
        return f"{sender!r} is not a declared peer ({', '.join(peers) or 'none'})"
    if caller != peers[sender]:
        return f"a message for {sender} from node {caller or '(unknown)'}, not from {peers[sender]}"
    return None


def split_by_ownership(clauses: list[Clause], inputs: list[str],
                       outputs: list[str]) -> tuple[list[Clause], list[Clause]]:
    """Received assumptions (Alg. 4 line 5) by who can keep them: ``(guarantees, assumptions)``.

    * a clause that mentions a next-state output of the receiver is its guarantee as it is (it keeps
      it by its next move, as A's ``openDoor'`` in Example 13);
    * a clause over the receiver's own completion sensors (``road_c'``: the robot *is* in road) is
      kept by the receiver through the activations they complete: it becomes the guarantee with each
      next-state completion sensor replaced by its activation (``road'``), which the receiver
      controls — D promising "never in the kitchen" promises never to head there;
    * a clause whose next-state inputs include a sensor the receiver does not complete (a global
      sensor, another robot's proposition) cannot be kept by any move: it becomes an environment
      assumption of the receiver, never a guarantee it could be forced to break."""
    mine = set(outputs)
    guarantees, assumptions = [], []
    for clause in clauses:
        used = variables(clause.formula)
        if any(v.primed and v.name in mine for v in used):
            guarantees.append(clause)
            continue
        sensed = {v.name for v in used if v.primed and v.name in inputs}
        actions = {name: action_of(name, outputs) for name in sensed}
        if sensed and all(actions.values()):
            formula = rename_next(clause.formula, actions)
            guarantees.append(Clause(formula, formula_to_infix(formula), clause.file, clause.line))
        else:
            assumptions.append(clause)
    return guarantees, assumptions


def rename_next(f: Formula, table: Mapping[str, str]) -> Formula:
    """``f`` with each next-state variable ``x'`` in ``table`` renamed to ``table[x]'``."""
    return map_vars(f, lambda v: Var(table[v.name], True) if v.primed and v.name in table else v)


def rename(f: Formula, table: Mapping[str, str]) -> Formula:
    """``f`` with every variable ``x`` renamed to ``table[x]`` (``KeyError`` for a name not in it)."""
    return map_vars(f, lambda v: Var(table[v.name], v.primed))


# --- messages ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Message:
    """One message of Alg. 4 (what the ROS service carries, field by field)."""

    kind: str                   # offer, status, abort
    sender: str
    session: str                # "<initiator>-><responder>": one negotiation per pair
    round: int = 0              # 1 or 2 for a status (Alg. 4 lines 10 and 18)
    text: str = ""              # offer: structured spec text in the receiver's names
    english: tuple[str, ...] = ()  # offer: the same clauses in Structured English (for people)
    realizable: bool = False    # status
    reason: str = ""            # abort / status: why

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "sender": self.sender, "session": self.session, "round": self.round,
                "text": self.text, "english": list(self.english), "realizable": self.realizable,
                "reason": self.reason}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Message:
        return cls(str(data["kind"]), str(data["sender"]), str(data["session"]), int(data.get("round", 0)),
                   str(data.get("text", "")), tuple(str(s) for s in data.get("english", ())),
                   bool(data.get("realizable", False)), str(data.get("reason", "")))


class Phase(Enum):
    NEW = "new"
    OFFERED = "offered"               # our offer sent
    SYNTHESIZED = "synthesized"       # the peer's offer received, phi^nego synthesized (status 1 known)
    DECIDED = "decided"               # the peer's status 1 received, phi* known (status 2 known)
    DONE = "done"


class Outcome(Enum):
    """How a negotiation ended, from one party's view (thesis §4.8.1-4.8.3, plus faults)."""

    BOTH_ADOPT = "4.8.1: both robots adopt their negotiated specifications"
    ADOPTED_PEERS = "4.8.2: this robot incorporated the peer's specification; the peer keeps its own"
    KEPT_OWN = "4.8.2: the peer incorporated this robot's specification; this robot resynthesized its own"
    BOTH_ABORT = "4.8.3: neither robot can incorporate the other's specification; both abort"
    ABORT_LINE_20 = "Alg. 4 line 20: a specification after negotiation is unrealizable; both abort"
    FAILED = "failed (fault); nothing adopted"

    @property
    def adopts(self) -> bool:
        return self in (Outcome.BOTH_ADOPT, Outcome.ADOPTED_PEERS, Outcome.KEPT_OWN)


@dataclass
class Adoption:
    """The spec (and its text and strategy) a party runs after a successful negotiation."""

    spec: Spec
    text: str
    strategy: SymbolicStrategy
    incorporated: bool          # phi^nego (the peer's assumptions and goals) or phi* with new init


class ProtocolFault(Exception):
    """A message that breaks the protocol (garbled, out of order, from someone else)."""


# --- one party ----------------------------------------------------------------------------------------
class Negotiation:
    """Alg. 4 for one party (see the module docstring). ``star`` is phi*_r (the original spec, or the
    spec adopted in an earlier negotiation); ``original`` gives phi^t_e (line 2); ``incoming`` and
    ``outputs`` are the current position (lines 6-7)."""

    def __init__(self, star: Spec, classes: Classes, peer: str, *, incoming: Mapping[str, bool],
                 outputs: Mapping[str, bool], original: Spec | None = None, initiator: bool = True,
                 synthesis_options: Mapping[str, Any] | None = None, clock=time.monotonic,
                 wall_clock=time.time, stage: Callable[[Spec, str], Any] | None = None) -> None:
        if peer not in classes.peers:
            raise ValueError(f"{classes.robot} has no peer {peer!r} (declared: {', '.join(classes.peers) or 'none'})")
        self.star = star
        self.original = original if original is not None else star
        self.classes = classes
        self.me = classes.robot
        self.peer = classes.peers[peer]
        self.initiator = initiator
        self.session = f"{self.me}->{peer}" if initiator else f"{peer}->{self.me}"
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
        self.sent: list[str] = []          # Structured English, for ~state / the trace
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
        #: two-phase adoption (issue 23): writes phi* aside before our realizable status 2 is sent
        #: (returns what ``commit`` needs; raises ``OSError``); None: nothing to write
        self.stage = stage
        self.staged: Any = None
        self._stage_error = ""

    # --- line 3: what we send -----------------------------------------------------------------------
    def offer(self) -> Message:
        """Our phi^{t(r_env)}_{e,r} and phi^g_{s,r} in the peer's names (Alg. 4 line 3)."""
        if self._offer is not None:
            return self._offer
        if self.phase is not Phase.NEW:
            raise ProtocolFault(f"offer requested in phase {self.phase.value}")
        table = {**{s: s for s in self.classes.global_sensors}, **self.peer.table}
        lines = [f"# Alg. 4 line 3: {self.me}'s assumptions about {self.peer.name} (phi^t(r_env)_e) and goals "
                 f"(phi^g_s), in {self.peer.name}'s names",
                 f"# session {self.session}"]
        english = []
        sections = (("sys_safety", assumptions_about(self.original, self.classes, self.peer.name), "assumption"),
                    ("env_liveness", list(self.star.sys_liveness), "goal"))
        for section, clauses, what in sections:
            lines.append(f"[{HEADERS[section]}]")
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
                lines.append(formula_to_infix(renamed))
                english.append(f"{what} ({clause.location}): {clause_to_english(renamed, section)}")
        text = "\n".join(lines) + "\n"
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
        guarantees, sensed = split_by_ownership(received.sys_safety, self.star.inputs, self.star.outputs)
        self.received = [f"assumption of {self.peer.name}: {clause_to_english(c, 'sys_safety')}" for c in guarantees]
        self.received += [f"assumption of {self.peer.name} over what this robot cannot control (kept as an "
                          f"assumption): {clause_to_english(c, 'env_safety')}" for c in sensed]
        self.received += [f"goal of {self.peer.name}: {clause_to_english(c, 'env_liveness')}"
                          for c in received.env_liveness]
        self._note(f"received {len(received.sys_safety)} assumption(s) ({len(sensed)} kept as assumptions) and "
                   f"{len(received.env_liveness)} goal(s) from {self.peer.name}")
        # lines 5-9; a received clause this robot's next outputs cannot satisfy is an assumption (ownership)
        extra = {"sys_safety": guarantees, "env_safety": sensed, "env_liveness": received.env_liveness}
        try:
            spec, text = self._spec(self.star, extra, "phi^nego (Alg. 4 line 8)")
        except SpecError as err:
            raise ProtocolFault(f"garbled specification text: {err}") from None
        strategy = self._synthesize(spec)
        self._nego = (spec, text, strategy)
        self._status[1] = strategy is not None
        self._note(f"phi^nego {'realizable' if strategy is not None else 'unrealizable'} (line 9)")
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
        self.adopted = Adoption(spec, text, strategy, incorporated)
        if incorporated and self._peer_status.get(1):
            outcome = Outcome.BOTH_ADOPT
        elif incorporated:
            outcome = Outcome.ADOPTED_PEERS
        else:
            outcome = Outcome.KEPT_OWN
        self._end(outcome, "adopted " + ("phi^nego" if incorporated else "phi* with the new init"))

    def fail(self, reason: str) -> None:
        """A fault (timeout, peer gone, garbled text, protocol error): nothing is adopted."""
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
        out = [f"# {self.me}: {what}, negotiated with {self.peer.name} (thesis §4.8, Alg. 4) "
               f"at {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(self.wall_clock()))}",
               f"# from {base.source}. It loads like any spec: synthesize FILE, controller_executor FILE.", "",
               "[INPUT]", *base.inputs, "", "[OUTPUT]", *base.outputs, ""]
        for section in SECTIONS:
            out.append(f"[{HEADERS[section]}]")
            if section in ("env_init", "sys_init"):
                names, values = ((base.inputs, self.incoming) if section == "env_init" else (base.outputs, self.outputs))
                out.append(f"# Alg. 4 line {6 if section == 'env_init' else 7}: the current "
                           f"{'inputs' if section == 'env_init' else 'outputs'}")
                literals = [Var(n) if values[n] else Not(Var(n)) for n in names]
                out.append(formula_to_infix(literals[0] if len(literals) == 1 else And(tuple(literals))))
            else:
                clauses = self.original.env_safety if section == "env_safety" else base.section(section)
                if section == "env_safety":
                    out.append("# Alg. 4 line 2: the original environment safety (no characterization disjuncts)")
                for c in clauses:
                    out.append(f"# {c.location}: {' '.join(c.text.split())}")
                    out.append(formula_to_infix(c.formula))
                for c in extra.get(section, []):
                    origin = {"sys_safety": "assumption", "env_safety": "assumption no move of ours keeps, kept as "
                              "an assumption (ownership, docs/negotiation.md)"}.get(section, "goal")
                    out.append(f"# Alg. 4 line 5: {origin} of {self.peer.name} ({c.text.strip()})")
                    out.append(formula_to_infix(c.formula))
            out.append("")
        text = "\n".join(out)
        return parse_structured(text, f"<{self.me} negotiated with {self.peer.name}>"), text


def write_adopted(adoption: Adoption, path: str | Path) -> None:
    """Write an adopted spec atomically (structured text; slugsin for a ``.slugsin`` path)."""
    path = Path(path)
    if path.suffix == ".slugsin":
        write_atomic(path, write_slugsin(adoption.spec, comments=True))
    else:
        write_atomic(path, adoption.text)


def stage_adopted(spec: Spec, text: str, path: str | Path, session: str) -> Path:
    """Phase one of a two-phase adoption: the spec written next to ``path`` under a name of its own
    (``OSError`` when it cannot be: the folder is gone, not writable, ``path`` is a folder). Returns
    the staged file for ``commit_adopted``."""
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(21, "is a folder", str(path))
    staged = path.with_name(f".{path.name}.{session.replace('>', '').replace('/', '_')}.staged")
    write_atomic(staged, write_slugsin(spec, comments=True) if path.suffix == ".slugsin" else text)
    return staged


def commit_adopted(staged: Path, path: str | Path) -> None:
    """Phase two: the staged file replaces ``path`` (one rename in one folder)."""
    staged.replace(path)


def discard_staged(staged: Path | None) -> None:
    """A negotiation that did not end in adoption leaves no staged file behind."""
    if staged is not None:
        with contextlib.suppress(OSError):
            staged.unlink()


def report_lines(report: Mapping[str, Any], robot: str = "") -> list[str]:
    """A finished negotiation's report (``Negotiation.report()``) as lines for people: who started or
    answered it and the outcome, then each clause sent and received (Structured English)."""
    role = "started" if report["initiator"] else "answered"
    who = f"{robot} " if robot else ""
    lines = [f"{who}{role} negotiation {report['session']}: {report['outcome']}"
             + (f" ({report['reason']})" if report.get("case") == Outcome.FAILED.name else "")]
    lines += [f"  sent to {report['peer']}: {line}" for line in report["sent"]]
    lines += [f"  received from {report['peer']}: {line}" for line in report["received"]]
    lines += [f"  not sent (not observable by {report['peer']}): {line}" for line in report.get("dropped", [])]
    return lines


# --- the transport-independent drivers ----------------------------------------------------------------
def answer(responder: Negotiation, message: Message) -> Message:
    """The responder's side of one exchange: take ``message``, return ours (an abort on a fault)."""
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
    return reply


def drive(initiator: Negotiation, call: Callable[[Message], Message]) -> None:
    """The initiator's side: offer, status 1, status 2 (Alg. 4 lines 3-4, 10, 18), each sent with
    ``call(message) -> reply``. A transport error (``TimeoutError``, ``ConnectionError``, ``OSError``:
    timeout, peer gone) is a fault; after a fault on our side the peer is told (best effort)."""
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
            initiator.fail(f"{initiator.peer.name} did not answer: {err}")
            return
        initiator.receive(reply)
    if not initiator.done:
        initiator.fail("negotiation ended early")
    if initiator.outcome is Outcome.FAILED and not initiator.reason.startswith(f"{initiator.peer.name} aborted"):
        try:
            call(initiator.abort_message())
        except (TimeoutError, ConnectionError, OSError):
            pass


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
