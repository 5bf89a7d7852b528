"""The vacuity check as it was first written, kept as the test oracle of ``synthesis.vacuity``.

Two plain Emerson–Lei fixpoints (the environment's moves alone, then both players' moves within the
robot's winning positions), both always computed to the end, each predecessor one ``and_exists``
over all next-state variables; ``check`` returns what ``synthesis.vacuity.check`` must return.

``assumptions_satisfiable`` asks whether some infinite play starts in an initial position, keeps the
safety of both sides at every step and meets every environment goal infinitely often: the fair
states of the transition relation ``env_trans & sys_trans`` with the environment's goals as fairness
(Emerson–Lei's greatest fixpoint of least fixpoints, on the game's BDDs).
"""
from __future__ import annotations

from ltl_stack.synthesis.game import BACKEND, Game, _backend
from ltl_stack.synthesis.vacuity import Vacuity


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
