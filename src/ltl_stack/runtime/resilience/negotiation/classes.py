"""Proposition classes of integrative negotiation (thesis Def. 4.3.1, Table 4.1), declared in a mapping.

Which inputs abstract another robot's behaviour (eAP_r) and which are global sensors (Sen_G) is
declared under the mapping's top-level key ``negotiation:`` (see the package docstring); this module
reads and checks that declaration and gives phi^{t(r_env)}_{e,r} (``assumptions_about``) and the
translation of formulas into a peer's names (``rename``).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ltl_stack.errors import UserError
from ltl_stack.runtime.resilience.negotiation.auth import Authenticator, load_authenticator
from ltl_stack.spec.formula import Formula, Var, variables
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import map_vars

if TYPE_CHECKING:  # the mapping reader checks this section with this module: no import back at run time
    from ltl_stack.runtime.config.mapping import Mapping as MappingFile


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
    secret_file: str | None = None  # the secret shared with this peer only (``auth``)

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
    #: the fleet's secret (``auth``): every peer without a ``secret_file`` of its own
    secret_file: str | None = None

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
    unknown = set(data) - {"robot", "peers", "global_sensors", "secret_file"}
    if unknown:
        raise fail(f"unknown key(s) {', '.join(sorted(map(str, unknown)))} (expected robot, peers, global_sensors, "
                   "secret_file)")
    secret_file = data.get("secret_file")
    if secret_file is not None and not isinstance(secret_file, str):
        raise fail("secret_file: must name a file")
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
        bad = set(value) - {"eap", "shares", "service", "secret_file"}
        if bad:
            raise fail(f"peers.{name}: unknown key(s) {', '.join(sorted(map(str, bad)))} (expected eap, shares, "
                       "service, secret_file)")
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
        pair_secret = value.get("secret_file")
        if pair_secret is not None and not isinstance(pair_secret, str):
            raise fail(f"peers.{name}.secret_file: must name a file")
        if str(name) == robot:
            raise fail(f"peers.{name}: a robot does not negotiate with itself")
        peers[str(name)] = Peer(str(name), tables["eap"], tables["shares"], service, pair_secret)
    return Classes(robot.strip(), peers, tuple(sensors), file, line, secret_file)


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


def classes_authenticator(classes: Classes) -> Authenticator | None:
    """The ``Authenticator`` of the secrets ``classes`` name (relative to the mapping's folder), None
    when it names none; ``SecretError`` (one line, exit code 2) for a file that cannot be used."""
    base = Path(classes.file).parent if classes.file != "<memory>" else Path(".")
    return load_authenticator(classes.robot, classes.secret_file,
                              {name: peer.secret_file for name, peer in classes.peers.items()}, base)


def assumptions_about(spec: Spec, classes: Classes, peer: str) -> list[Clause]:
    """phi^{t(r_env)}_{e,r} (§4.8): the env-safety clauses that mention an eAP input about ``peer``."""
    eap = classes.eap(peer)
    return [c for c in spec.env_safety if any(v.name in eap for v in variables(c.formula))]


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


def rename(f: Formula, table: Mapping[str, str]) -> Formula:
    """``f`` with every variable ``x`` renamed to ``table[x]`` (``KeyError`` for a name not in it)."""
    return map_vars(f, lambda v: Var(table[v.name], v.primed))
