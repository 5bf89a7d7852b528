"""The Lemma 1(a) output guard: the outputs the executor publishes when it takes no strategy move, kept
safe, free of ROS (thesis ch. 4, Lemma 1(a)).

Lemma 1(a) asks that every move the robot makes keeps the system safety rho_s whenever some move
does. Strategy moves (normal steps, recovery moves, thesis §4.6) keep it by construction; the
outputs the node publishes when it does *not* take a strategy move — a violation with recovery off
(``--no-recovery``: holding, characterizing, waiting for the user), a violation no recovery move
answers, inputs unknown, the phases of negotiation — come from the ``--on-violation`` policy, and
``OutputGuard`` makes them keep rho_s too:

* ``hold``: the outputs of the controller's last state when they keep rho_s with the current inputs
  from the position last *published* (not the last state: after a policy valuation the two differ,
  and guarantees tying consecutive outputs, ``stop -> brake'``, are about what the robot did), else
  the valuation that keeps rho_s with the fewest outputs changed;
* ``all-false``: the valuation that keeps rho_s with the fewest outputs true;
* only when no output valuation keeps rho_s the policy's valuation is published as it is, and the
  guard names the clauses that cannot be kept together (``file:line``; the node logs them as ERROR).

What the node reports about these outputs is ``node_reports``.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ltl_stack.spec.model import Clause
from ltl_stack.synthesis.game import Game, prime_name
from ltl_stack.synthesis.recovery import unkeepable_clauses, unsatisfiable_core

__all__ = ["Guarded", "OutputGuard", "game_of", "nearest_safe_outputs", "safe_initial_outputs"]


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
                         wanted: Mapping[str, bool], unknown: Sequence[str] = ()) -> Guarded:
    """The output valuation keeping rho_s (``game.sys_trans``) for the move from ``position`` (every
    input and output) to (``inputs``, outputs) that differs from ``wanted`` in the fewest outputs
    (ties: ``wanted``'s value in spec order); ``wanted`` itself when it keeps rho_s. The search
    counts differences over the outputs rho_s constrains here: O(k^2) BDD operations for k of them.

    ``unknown``: inputs whose next value is not known (stale readings): the valuation must keep rho_s
    for *every* value of them — the next outputs allowed are ``forall unknown'. rho_s`` with the
    known values put in, one exact BDD quantification."""
    bdd = game.bdd
    unknown_next = [prime_name(p) for p in game.inputs if p in unknown]
    assign = game.assignment({p: bool(position[p]) for p in game.variables},
                             {p: bool(inputs[p]) for p in game.inputs if p not in unknown})
    allowed = game.sys_rel.restrict(assign)  # over the next outputs (and the unknown next inputs)
    if unknown_next:
        allowed = bdd.forall(unknown_next, allowed)
    wanted = {p: bool(wanted[p]) for p in game.outputs}
    if bdd.let({prime_name(p): v for p, v in wanted.items()}, allowed) == bdd.true:
        return Guarded(wanted)
    if allowed == bdd.false:
        return Guarded(wanted, unkeepable_clauses(game, assign, unknown_next))
    return Guarded(_nearest(bdd, allowed, wanted, game.outputs, prime_name))


def _nearest(bdd: Any, allowed: Any, wanted: dict[str, bool], outputs: Sequence[str], name_of: Any) -> dict[str, bool]:
    """The valuation of ``outputs`` (BDD variables ``name_of(p)``) in ``allowed`` (not false) that
    differs from ``wanted`` in the fewest outputs; ties: ``wanted``'s value in spec order."""
    support = bdd.support(allowed)
    names = [p for p in outputs if name_of(p) in support]
    exact = [bdd.true]  # exact[j]: the valuations of the names seen so far with j changes
    for name in names:
        same = bdd.var(name_of(name)) if wanted[name] else ~bdd.var(name_of(name))
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
        rest = bdd.let({name_of(name): value}, candidates)
        if rest == bdd.false:
            value = not value
            rest = bdd.let({name_of(name): value}, candidates)
        chosen[name] = value
        candidates = rest
    return chosen


def safe_initial_outputs(game: Game, inputs: Mapping[str, bool], wanted: Mapping[str, bool],
                         unknown: Sequence[str]) -> Guarded:
    """Before the start, with the inputs ``unknown`` never heard of: the output valuation nearest to
    ``wanted`` that the robot may hold whatever they do — it keeps ``[SYS_INIT]`` for every value of
    them, and rho_s for every move that keeps these outputs, the known ``inputs`` and changes only
    them (``forall u. sys_init  &  forall u, u'. rho_s[o' := o]``, exact BDD quantifications, no
    environment assumption relied on: their values are not known). When none does, ``wanted`` with
    the clauses that cannot be kept together (``synthesis.recovery.unsatisfiable_core``)."""
    bdd = game.bdd
    known = {p: bool(inputs[p]) for p in game.inputs if p not in unknown and p in inputs}
    free = [p for p in game.inputs if p not in known]
    assign = game.assignment(known, known)
    held = {prime_name(p): bdd.var(p) for p in game.outputs}  # o' := o

    def restricted(u: Any, kept: bool) -> Any:
        u = bdd.let(assign, u) if assign else u
        if kept:
            u = bdd.let(held, u)
        names = free + [prime_name(p) for p in free] if kept else free
        return bdd.forall(names, u) if names else u

    clauses = [(c, restricted(u, False)) for c, u in game.clauses("sys_init")]
    clauses += [(c, restricted(u, True)) for c, u in game.clauses("sys_safety")]
    allowed = bdd.true
    for _, u in clauses:
        allowed &= u
    wanted = {p: bool(wanted[p]) for p in game.outputs}
    if allowed == bdd.false:
        return Guarded(wanted, unsatisfiable_core(bdd, clauses))
    return Guarded(_nearest(bdd, allowed, wanted, game.outputs, lambda p: p))


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

    def __call__(self, position: Mapping[str, bool], inputs: Mapping[str, bool],
                 wanted: Mapping[str, bool], unknown: Sequence[str] = ()) -> Guarded:
        """``wanted`` made to keep rho_s for the move from ``position`` (the inputs and outputs
        last published) to ``inputs``, for every value of the ``unknown`` inputs."""
        game = self.game()
        if game is None or any(p not in inputs and p not in unknown for p in game.inputs) \
                or any(p not in position for p in game.variables):
            return Guarded(dict(wanted))
        return nearest_safe_outputs(game, position, inputs, wanted, unknown)

    def initial(self, inputs: Mapping[str, bool], wanted: Mapping[str, bool], unknown: Sequence[str]) -> Guarded:
        """``wanted`` made to keep ``[SYS_INIT]`` for every value of the never-heard ``unknown`` inputs
        (``safe_initial_outputs``); ``wanted`` as it is without a game."""
        game = self.game()
        if game is None:
            return Guarded(dict(wanted))
        return safe_initial_outputs(game, inputs, wanted, unknown)
