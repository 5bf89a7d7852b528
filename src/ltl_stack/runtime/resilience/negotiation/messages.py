"""The messages of Alg. 4 (thesis §4.8) and how a negotiation can end, from one party's view.

``Message`` is what the ROS service carries, field by field; ``Outcome`` names the thesis' cases
(4.8.1-4.8.3, Alg. 4 line 20) plus a fault. ``offer_refusal`` bounds what an offer may hold before
anyone parses it; ``report_lines`` renders a finished negotiation's report for people.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Any

from ltl_stack.spec.model import Spec
from ltl_stack.synthesis.strategy import SymbolicStrategy

#: bounds of a received offer: its text and its clauses; larger offers are refused in one line
MAX_OFFER_BYTES = 64 * 1024
MAX_OFFER_CLAUSES = 200
#: the sections an offer may hold (Alg. 4 line 3: assumptions to guarantee, goals to assume)
OFFER_SECTIONS = ("[SYS_TRANS]", "[ENV_LIVENESS]")
OFFER, STATUS, ABORT = "offer", "status", "abort"
#: the commit protocol: the initiator's decision after both realizable statuses 2 (the responder's
#: reply, also ``commit``, confirms its adoption), and a question about a session's outcome that
#: either robot may ask again until it has the answer (reply ``outcome``, the state in ``reason``)
COMMIT, OUTCOME = "commit", "outcome"
#: how a status 2 says the adopted spec could not be written (two-phase adoption)
WRITE_FAILED = "cannot write its adopted specification"
#: the refusal of an offer that crossed ours (both robots started at once)
SIMULTANEOUS = "simultaneous negotiation:"
#: the refusal of an offer while this robot is in another negotiation (robots negotiate one at a time)
BUSY = "busy:"


@dataclass(frozen=True)
class Message:
    """One message of Alg. 4 (what the ROS service carries, field by field)."""

    kind: str                   # offer, status, abort
    sender: str
    session: str                # "<initiator>-><responder>": one negotiation per pair
    round: int = 0              # 1 or 2 for a status (Alg. 4 lines 10 and 18)
    text: str = ""              # offer: structured spec text in the receiver's names
    english: tuple[str, ...] = ()  # offer: the same clauses in words (for people)
    realizable: bool = False    # status
    reason: str = ""            # abort / status: why
    nonce: str = ""             # authentication (``auth``): when and something unguessable; "" unsigned
    mac: str = ""               # HMAC of every other field (``auth.mac``); "" unsigned

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "sender": self.sender, "session": self.session, "round": self.round,
                "text": self.text, "english": list(self.english), "realizable": self.realizable,
                "reason": self.reason, "nonce": self.nonce, "mac": self.mac}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Message:
        return cls(str(data["kind"]), str(data["sender"]), str(data["session"]), int(data.get("round", 0)),
                   str(data.get("text", "")), tuple(str(s) for s in data.get("english", ())),
                   bool(data.get("realizable", False)), str(data.get("reason", "")), str(data.get("nonce", "")),
                   str(data.get("mac", "")))


class Phase(Enum):
    NEW = "new"
    OFFERED = "offered"               # our offer sent
    SYNTHESIZED = "synthesized"       # the peer's offer received, phi^nego synthesized (status 1 known)
    DECIDED = "decided"               # the peer's status 1 received, phi* known (status 2 known)
    PREPARED = "prepared"             # responder: both statuses 2 realizable, phi* staged; waiting for the decision
    DONE = "done"


class Outcome(Enum):
    """How a negotiation ended, from one party's view (thesis §4.8.1-4.8.3, plus faults)."""

    BOTH_ADOPT = "4.8.1: both robots adopt their negotiated specifications"
    ADOPTED_PEERS = "4.8.2: this robot incorporated the peer's specification; the peer keeps its own"
    KEPT_OWN = "4.8.2: the peer incorporated this robot's specification; this robot resynthesized its own"
    BOTH_ABORT = "4.8.3: neither robot can incorporate the other's specification; both abort"
    ABORT_LINE_20 = "Alg. 4 line 20: a specification after negotiation is unrealizable; both abort"
    FAILED = "failed (fault); nothing adopted"
    #: the initiator decided and adopted; the responder has not confirmed its adoption yet (the
    #: decision is sent again until it does; the responder, bound by its status 2, adopts on receipt)
    UNCONFIRMED = "this robot adopted its negotiated specification; the peer has not confirmed its adoption yet"

    @property
    def adopts(self) -> bool:
        return self in (Outcome.BOTH_ADOPT, Outcome.ADOPTED_PEERS, Outcome.KEPT_OWN, Outcome.UNCONFIRMED)


@dataclass
class Adoption:
    """The spec (and its text and strategy) a party runs after a successful negotiation."""

    spec: Spec
    text: str
    strategy: SymbolicStrategy
    incorporated: bool          # phi^nego (the peer's assumptions and goals) or phi* with new init


class ProtocolFault(Exception):
    """A message that breaks the protocol (garbled, out of order, from someone else)."""


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


def report_lines(report: Mapping[str, Any], robot: str = "") -> list[str]:
    """A finished negotiation's report (``Negotiation.report()``) as lines for people: who started or
    answered it and the outcome, then each clause sent and received (in words)."""
    role = "started" if report["initiator"] else "answered"
    who = f"{robot} " if robot else ""
    lines = [f"{who}{role} negotiation {report['session']}: {report['outcome']}"
             + (f" ({report['reason']})" if report.get("case") == Outcome.FAILED.name else "")]
    lines += [f"  sent to {report['peer']}: {line}" for line in report["sent"]]
    lines += [f"  received from {report['peer']}: {line}" for line in report["received"]]
    lines += [f"  not sent (not observable by {report['peer']}): {line}" for line in report.get("dropped", [])]
    return lines
