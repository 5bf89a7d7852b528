"""Vacuity: is a realizable spec realizable only because nothing can be asked of the robot?

A GR(1) spec is an implication, assumptions -> guarantees (thesis Def. 3.4.2). When no play meets the
environment's assumptions, every controller "wins" by default and its strategy means nothing; when
the spec has no guarantees, any controller does. Both are realizable and both deserve a word
(issue 24: the thesis' Spec. 2 as printed is such a spec, and nothing said so).

``assumptions_satisfiable`` asks whether some infinite play starts in an initial position, keeps the
safety of both sides at every step and meets every environment goal infinitely often: the fair
states of the transition relation ``env_trans & sys_trans`` with the environment's goals as fairness
(Emerson–Lei's greatest fixpoint of least fixpoints, on the game's BDDs).
"""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.synthesis.game import BACKEND, Game, _backend


@dataclass(frozen=True)
class Vacuity:
    """What ``check`` found; ``warnings`` is empty for a spec that means something."""

    has_guarantees: bool
    assumptions_satisfiable: bool
    #: the assumptions can be met by some play if the robot ignores its own safety requirements
    assumptions_satisfiable_alone: bool
    warnings: tuple[str, ...]


def fair_states(game: Game, trans: object, more: object = None, within: object = None) -> object:
    """States from which a path along ``trans & more`` (over current and next variables) meets every
    environment goal infinitely often (goals may mention the next step: met on a transition).
    ``more`` is kept apart so that the two relations are never conjoined whole (CUDD's and-exists);
    ``within`` bounds the states (the greatest fixpoint starts there)."""
    bdd = game.bdd
    nxt = game.variables_next
    extra = bdd.true if more is None else more

    def pre(target: object) -> object:
        if BACKEND == "cudd":
            return _backend.and_exists(trans, extra & target, nxt)
        return bdd.exist(nxt, trans & extra & target)

    z = bdd.true if within is None else within
    while True:
        game.deadline.check()
        z_next = game.prime(z)
        new = z
        for goal in game.env_goals:
            reach_goal = pre(goal & z_next)
            y = bdd.false
            while True:
                game.deadline.check()
                y_new = z & (reach_goal | pre(game.prime(y)))
                if y_new == y:
                    break
                y = y_new
            new &= y
        if new == z:
            return z
        z = new


def check(game: Game, winning: object = None) -> Vacuity:
    """Whether the spec of ``game`` has guarantees and whether its assumptions can be met.

    With the robot's ``winning`` positions (a realizable spec's solution), the plays considered stay
    in them, as every play of a winning strategy does: the question is then whether the strategy can
    ever meet an environment that keeps its assumptions, and the fixpoint works on a smaller set."""
    spec = game.spec
    has_guarantees = bool(spec.sys_init or spec.sys_safety or spec.sys_liveness)
    bdd = game.bdd
    alone = (game.env_init & fair_states(game, game.env_trans)) != bdd.false
    if winning is None:
        fair = fair_states(game, game.env_trans, game.sys_trans)
    else:
        fair = fair_states(game, game.env_trans, game.sys_trans & game.prime(winning), winning)
    together = alone and (game.env_init & game.sys_init & fair) != bdd.false
    warnings = []
    if not has_guarantees:
        warnings.append("the spec has no guarantees (no [SYS_INIT], [SYS_TRANS] or [SYS_LIVENESS] clause): any "
                        "controller meets it")
    if not alone:
        warnings.append("no play meets the environment's assumptions (initial condition, safety and goals "
                        "together): the spec is realizable only because the environment can never keep them")
    elif not together:
        warnings.append("no play that keeps the robot's requirements meets the environment's assumptions: the spec "
                        "is realizable only because the environment can never keep them (the strategy is vacuous)")
    return Vacuity(has_guarantees, together, alone, tuple(warnings))
