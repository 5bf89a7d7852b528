"""What the executor node publishes in each mode and phase, free of ROS (thesis ch. 4, Lemma 1(a)).

Lemma 1(a) asks that every move the robot makes keeps the system safety rho_s whenever some move
does. Strategy moves (normal steps, recovery moves, thesis §4.6) keep it by construction; the
outputs the node publishes when it does *not* take a strategy move — a violation with recovery off
(``--no-recovery``: holding, characterizing, waiting for the user), a violation no recovery move
answers, the phases of negotiation — come from the ``--on-violation`` policy, and ``OutputGuard``
makes them keep rho_s too:

* ``hold``: the outputs of the controller's last state when they keep rho_s from that state with the
  current inputs, else the valuation that keeps rho_s with the fewest outputs changed;
* ``all-false``: the valuation that keeps rho_s with the fewest outputs true;
* only when no output valuation keeps rho_s the policy's valuation is published as it is, and the
  guard names the clauses that cannot be kept together (``file:line``; the node logs them as ERROR).

The node (``ltl_stack.ros.executor``) only wires these decisions to topics and /diagnostics.
"""
from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from ltl_stack.spec.english import clause_to_english
from ltl_stack.spec.model import Clause
from ltl_stack.spec.valuation import format_valuation
from ltl_stack.synthesis.game import Game, prime_name
from ltl_stack.synthesis.recovery import unkeepable_clauses


@dataclass(frozen=True)
class Guarded:
    """The outputs to publish; ``unkeepable`` names the rho_s clauses no valuation keeps (then
    ``outputs`` is the wanted valuation, unchanged)."""

    outputs: dict[str, bool]
    unkeepable: list[Clause] = field(default_factory=list)

    @property
    def safe(self) -> bool:
        return not self.unkeepable


def nearest_safe_outputs(game: Game, position: Mapping[str, bool], inputs: Mapping[str, bool],
                         wanted: Mapping[str, bool]) -> Guarded:
    """The output valuation keeping rho_s (``game.sys_trans``) for the move from ``position`` (every
    input and output) to (``inputs``, outputs) that differs from ``wanted`` in the fewest outputs
    (ties: ``wanted``'s value in spec order); ``wanted`` itself when it keeps rho_s. The search
    counts differences over the outputs rho_s constrains here: O(k^2) BDD operations for k of them."""
    bdd = game.bdd
    assign = game.assignment({p: bool(position[p]) for p in game.variables},
                             {p: bool(inputs[p]) for p in game.inputs})
    allowed = bdd.let(assign, game.sys_trans)  # over the next outputs
    wanted = {p: bool(wanted[p]) for p in game.outputs}
    if bdd.let({prime_name(p): v for p, v in wanted.items()}, allowed) == bdd.true:
        return Guarded(wanted)
    if allowed == bdd.false:
        return Guarded(wanted, unkeepable_clauses(game, assign))
    support = bdd.support(allowed)
    names = [p for p in game.outputs if prime_name(p) in support]
    exact = [bdd.true]  # exact[j]: the valuations of the names seen so far with j changes
    for name in names:
        same = bdd.var(prime_name(name)) if wanted[name] else ~bdd.var(prime_name(name))
        grown = [bdd.false] * (len(exact) + 1)
        for j, u in enumerate(exact):
            grown[j] |= u & same
            grown[j + 1] |= u & ~same
        exact = grown
    for u in exact:
        candidates = allowed & u
        if candidates != bdd.false:
            break
    chosen = dict(wanted)
    for name in names:  # wanted's value first, in spec order: deterministic
        value = wanted[name]
        rest = bdd.let({prime_name(name): value}, candidates)
        if rest == bdd.false:
            value = not value
            rest = bdd.let({prime_name(name): value}, candidates)
        chosen[name] = value
        candidates = rest
    return Guarded(chosen)


def current_mode(aborted: bool, violation: bool, resilient: str | None, recovered: bool) -> str:
    """``~state``'s mode: normal, recovering, holding, characterizing, waiting_for_user or aborted.

    ``violation``: the controller holds a violation (no recovery move was taken); ``resilient``: the
    resilient strategy's mode (None without characterization); ``recovered``: the latest update
    took a recovery move."""
    if aborted:
        return "aborted"
    if resilient is not None:
        if resilient in ("normal", "recovering") and violation:
            return "holding"
        if resilient == "normal" and recovered:
            return "recovering"
        return resilient
    if violation:
        return "holding"
    return "recovering" if recovered else "normal"


def mode_text(mode: str, policy: str, recovery: bool, aborted: str | None) -> str:
    """The first words of the "mode" diagnostic status."""
    return {"normal": "normal", "recovering": "recovering: recovery moves keep the system safety",
            "holding": f"holding: no recovery move; outputs by --on-violation {policy}, kept safe (Lemma 1(a))",
            "characterizing": "characterizing: resynthesizing (recovery moves meanwhile)"
            if recovery else "characterizing: resynthesizing (holding meanwhile, kept safe)",
            "waiting_for_user": "waiting for the user: unrealizable after environment characterization; call "
                                "~add_env_liveness with an environment liveness assumption, or ~abort",
            "aborted": f"aborted ({aborted}): every output is false"}[mode]


def liveness_refusal(characterize: bool, started: bool, mode: str) -> str | None:
    """Why ``~add_env_liveness`` is not taken now (exit 1, nothing changes), or None: it is Alg. 3
    line 6, the user's answer once environment characterization found no realizable spec."""
    if not characterize:
        return ("environment characterization is off: start the executor with --characterize or "
                "--characterized-spec FILE (docs/resilience.md)")
    if mode == "aborted":
        return "already aborted: every output is false"
    if not started:
        return "not ready: the controller has not started yet (waiting for every input to report)"
    if mode != "waiting_for_user":
        return (f"not waiting for the user (mode {mode}): an environment liveness assumption is taken after "
                "environment characterization found no realizable specification (docs/resilience.md)")
    return None


def policy_text(policy: str, unsafe: bool) -> str:
    """How the outputs follow the ``--on-violation`` policy, for the violation report."""
    if unsafe:
        return f"no output valuation keeps the system safety: publishing the {policy} valuation as it is"
    if policy == "hold":
        return "holding the last outputs (the nearest valuation keeping the system safety if they do not)"
    return "the fewest outputs true that keep the system safety"


def english(clause: Any) -> str:
    """The env-safety clause in Structured English, or "" when it cannot be rendered."""
    try:
        return clause_to_english(clause, "env_safety")
    except Exception:  # noqa: BLE001 - a rendering problem must not hide the violation itself
        return ""


def shown(clause: Any) -> str:
    """``file:line: text`` and, when it says more, the Structured English in parentheses."""
    words = english(clause)
    text = f"{clause.location}: {clause.text}"
    return f"{text} ({words})" if words and words.strip() != (clause.text or "").strip() else text


@dataclass(frozen=True)
class ViolationReport:
    """One violation as the node reports it: the log line / diagnostic message, the diagnostic's
    key-value pairs and the ``--json`` event (without the outputs)."""

    text: str
    values: list[tuple[str, str]]
    event: dict[str, Any]


def violation_report(violation: Any, result: Any, unkeepable: list[Clause], readings: Mapping[str, bool],
                     state_id: int, recovered: bool, policy: str) -> ViolationReport:
    """The report of an environment-assumption violation: the broken clauses (``file:line``, text and
    English), how the robot answered — a recovery move (``result``: its kind), or the ``policy``'s
    outputs kept safe — and, when no move keeps the system safety, the guarantees that cannot all be
    kept (the recovery's, else the policy guard's ``unkeepable``)."""
    broken = violation.clauses or (result.violated if result is not None else [])
    clauses = [f"{c.location}: {c.text}" for c in broken] or ["(no single clause)"]
    meanings = [english(c) for c in broken]
    parts = [f"{c} ({m})" if m else c for c, m in zip(clauses, meanings + [""] * len(clauses), strict=False)]
    unsafe = [f"{c.location}: {c.text}" for c in (result.unsafe if result is not None else unkeepable)]
    kind = result.kind.value if result is not None else None
    inputs = format_valuation(readings)
    if recovered:
        text = (f"environment assumption violated by inputs {inputs}: {'; '.join(parts)}; "
                f"recovering ({kind}), now in state {state_id}")
    else:
        cannot = (f"; no move keeps the system safety, these guarantees cannot all be kept: {'; '.join(unsafe)}"
                  if unsafe else "")
        text = (f"environment assumption violated by inputs {inputs} from state {state_id}: {'; '.join(parts)}"
                f"{cannot}; {policy_text(policy, bool(unkeepable))}, waiting for admissible inputs")
    values = [("clause", c) for c in clauses] + [("meaning", m) for m in meanings if m] + [
        ("unsafe_clause", c) for c in unsafe] + [
        ("inputs", inputs), ("state", str(state_id)), ("policy", f"recovery ({kind})" if recovered else policy)]
    event: dict[str, Any] = {"event": "violation", "state": state_id, "inputs": dict(readings), "clauses": clauses,
                             "recovered": recovered, "kind": kind}
    if unsafe:
        event["unsafe"] = unsafe
    return ViolationReport(text, values, event)


def game_of(strategy: Any) -> Game | None:
    """The game whose rho_s the running strategy keeps: the symbolic strategy's (for a resilient
    one, the strategy in place now), else one built from an explicit strategy's spec."""
    inner = getattr(strategy, "strategy", None)  # ResilientStrategy / BackgroundResilience
    if inner is not None and getattr(inner, "game", None) is not None:
        return inner.game
    symbolic = getattr(strategy, "symbolic", None)  # RecoveringStrategy
    if symbolic is not None:
        return symbolic.game
    if getattr(strategy, "game", None) is not None:
        return strategy.game
    spec = getattr(strategy, "spec", None)
    return Game(spec) if spec is not None else None


class OutputGuard:
    """The Controller's ``guard``: the policy's outputs made to keep rho_s (module docstring)."""

    def __init__(self, strategy: Any) -> None:
        self.strategy = strategy
        self._game: Game | None = None
        self._explicit = getattr(strategy, "strategy", None) is None and getattr(strategy, "symbolic", None) is None \
            and getattr(strategy, "game", None) is None

    def game(self) -> Game | None:
        if self._explicit:  # a saved automaton: build its game once
            if self._game is None:
                self._game = game_of(self.strategy)
            return self._game
        return game_of(self.strategy)

    def __call__(self, state: Any, inputs: Mapping[str, bool], wanted: Mapping[str, bool]) -> Guarded:
        game = self.game()
        if game is None or state is None or any(p not in inputs for p in game.inputs):
            return Guarded(dict(wanted))
        return nearest_safe_outputs(game, {**state.inputs, **state.outputs}, inputs, wanted)


def strategy_source(original: str, resilient: Any | None) -> tuple[str, int]:
    """``~state``'s ``spec_file`` and ``strategy_generation``: the file the running strategy was
    synthesized from and how many strategies were put in place after the one of start-up.

    ``resilient`` is the node's ``BackgroundResilience`` (None without characterization). After a
    resynthesis or an adoption the running spec is the characterized/adopted file, "" when it was
    not written to one (no path, or the write failed)."""
    if resilient is None or resilient.counters.resyntheses == 0:
        return (os.path.abspath(original) if original else ""), 0
    path = resilient.characterizer.path
    written = path is not None and getattr(resilient, "write_error", None) is None
    return (os.path.abspath(path) if written else ""), resilient.counters.resyntheses


__all__ = ["Guarded", "OutputGuard", "ViolationReport", "current_mode", "english", "game_of", "liveness_refusal",
           "shown", "violation_report", "mode_text", "nearest_safe_outputs", "policy_text", "strategy_source"]
