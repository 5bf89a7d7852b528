"""Vacuity: is a realizable spec realizable only because nothing can be asked of the robot?

A GR(1) spec is an implication, assumptions -> guarantees (thesis Def. 3.4.2). When no play meets the
environment's assumptions, every controller "wins" by default and its strategy means nothing; when
the spec has no guarantees, any controller does. Both are realizable and both deserve a word
(the thesis' Spec. 2 as printed is such a spec).

``assumptions_satisfiable`` asks whether some infinite play starts in an initial position, keeps the
safety of both sides at every step and meets every environment goal infinitely often: whether an
initial position lies among the fair states of the joint moves (``Game.pre_exists``) with the
environment's goals as fairness, Emerson–Lei's greatest fixpoint of least fixpoints

    nu Z. /\\_k mu Y. Z & (pre(goal_k & Z') | pre(Y'))

The check runs after every realizable verdict, so it must cost a small part of the solve:

- only the joint question is asked first; the environment's moves alone (``assumptions_satisfiable_alone``,
  which the joint answer implies) are examined only when the joint answer is "no";
- the greatest fixpoint starts at the robot's winning positions (every play of a winning strategy
  stays there), whose first predecessor the solve already knows (``Solution.cpre_winning``: from a
  winning position every admissible input has an answer that stays winning);
- it is iterated chaotically, one goal at a time with Z updated at once (the same fixpoint: each
  step is monotone and only removes states; the iteration ends when a whole round of goals removes
  nothing), and it stops as soon as an iterate no longer meets the initial positions: the iterates
  only shrink, so the answer is then "no";
- each least fixpoint grows by the predecessors of its newest layer only (``pre_exists`` distributes
  over union), and every predecessor goes through the game's own ``pre_exists``, which quantifies
  the outputs with the system's relation and the inputs with the environment's, never the two
  relations conjoined.

``check`` calls ``game.deadline.check()`` before every predecessor, like the solve.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

from ltl_stack.synthesis.game import Game
from ltl_stack.synthesis.relation import Relation

Progress = Callable[[str], None]

#: seconds of checking after which ``check`` reports its progress
QUIET_FOR = 1.0
#: the command's budget for the check (``budget_for``): this share of the solve's CPU time, and at
#: least this many CPU seconds. A last resort for games unlike the benchmark's, where the check
#: takes a few per cent of the solve; ``synthesize --full-vacuity-check`` lifts it
BUDGET_SHARE = 0.5
BUDGET_FLOOR = 2.0


def budget_for(solve_cpu: float) -> float:
    """CPU seconds the command grants the check after a solve that took ``solve_cpu`` CPU seconds."""
    return max(BUDGET_FLOOR, BUDGET_SHARE * solve_cpu)


@dataclass(frozen=True)
class Vacuity:
    """What ``check`` found; ``warnings`` is empty for a spec that means something."""

    has_guarantees: bool
    assumptions_satisfiable: bool | None
    #: the assumptions can be met by some play if the robot ignores its own safety requirements
    assumptions_satisfiable_alone: bool | None
    warnings: tuple[str, ...]
    #: False when the check stopped at its ``budget``: the answers not found yet are None
    complete: bool = True


class OverBudget(Exception):
    """The check used up its budget of CPU time (``check``'s ``budget``)."""


@dataclass
class Counts:
    """How much work ``fair_states`` did (read by tests; one instance per ``check``)."""

    #: greatest fixpoints run to convergence (an early "no" does not count)
    full_fixpoints: int = 0
    #: greatest fixpoints started
    fixpoints: int = 0
    #: predecessor computations
    pres: int = 0


def fair_states(game: Game, sys_rel: Relation, within: object, initial: object | None = None, *,
                counts: Counts | None = None, progress: Progress | None = None,
                moving: object | None = None, stop: Callable[[], None] | None = None) -> object:
    """The states of ``within`` from which a path of joint moves (the environment's safety and
    ``sys_rel``) stays in ``within`` and meets every environment goal infinitely often (goals may
    mention the next step: met on a transition).

    With ``initial``, stop with the current iterate as soon as it no longer meets ``initial`` (the
    fixpoint then does not meet it either; the result is exact only as to that). ``moving``, when
    known, is the set whose states of ``within`` are exactly those with a joint move into ``within``:
    while Z is still ``within``, a goal without next-state variables then needs no predecessor.
    ``stop`` is called before every predecessor (and may raise); by default the game's deadline."""
    bdd = game.bdd
    check = game.deadline.check if stop is None else stop
    counts = counts if counts is not None else Counts()
    counts.fixpoints += 1

    def pre(target: object) -> object:
        check()
        counts.pres += 1
        return game.pre_exists(target, sys_rel)

    goals = game.env_goals
    z = within
    unchanged = 0  # goals in a row whose least fixpoint removed nothing from z
    k = 0
    while unchanged < len(goals):
        goal = goals[k % len(goals)]
        k += 1
        # mu Y. z & (pre(goal & z') | pre(Y')), grown by the predecessors of its newest layer
        if moving is not None and z == within and not game.liveness_has_next:
            y = z & goal & moving  # pre(goal & z') is goal & pre(z') for a goal on the current state
        else:
            y = z & pre(goal & game.prime(z))
        layer = y
        while layer != bdd.false and y != z:  # y cannot grow past z
            layer = z & pre(game.prime(layer)) & ~y
            y |= layer
        if progress is not None:
            progress(f"vacuity check: environment goal {(k - 1) % len(goals) + 1} of {len(goals)}, "
                     f"round {(k - 1) // len(goals) + 1}")
        if y == z:
            unchanged += 1
            continue
        unchanged = 0
        z = y
        if initial is not None and (z & initial) == bdd.false:
            return z
    counts.full_fixpoints += 1
    return z


def check(game: Game, winning: object = None, progress: Progress | None = None,
          counts: Counts | None = None, cpre_winning: object = None, budget: float | None = None) -> Vacuity:
    """Whether the spec of ``game`` has guarantees and whether its assumptions can be met.

    With the robot's ``winning`` positions (a realizable spec's solution), the plays considered stay
    in them, as every play of a winning strategy does: the question is then whether the strategy can
    ever meet an environment that keeps its assumptions, and the fixpoint works on a smaller set.
    ``cpre_winning`` is the solve's ``Solution.cpre_winning``: where it holds every winning position
    (as it does after a complete solve), each winning position from which the environment has an
    admissible input has a joint move that stays winning, so the first predecessor of the fixpoint
    is known without computing it. ``progress`` hears about the check once it has run for
    ``QUIET_FOR`` seconds. With a ``budget`` (seconds of this process' CPU time) the check gives up
    once it is spent: ``complete`` False and the answers not found by then None (the joint one is
    found first; when it is "no" the spec is vacuous whatever the other)."""
    spec = game.spec
    has_guarantees = bool(spec.sys_init or spec.sys_safety or spec.sys_liveness)
    start = time.perf_counter()

    def told(message: str) -> None:
        if progress is not None and time.perf_counter() - start > QUIET_FOR:
            progress(message)

    counts = counts if counts is not None else Counts()
    deadline = game.deadline.check
    spent_at = None if budget is None else time.process_time() + budget

    def stop() -> None:
        deadline()
        if spent_at is not None and time.process_time() > spent_at:
            raise OverBudget

    found: list[bool] = []  # assumptions_satisfiable, then ..._alone, as they are known
    try:
        _satisfiable(game, winning, cpre_winning, counts, told, stop, found)
    except OverBudget:
        pass
    together, alone = (found + [None, None])[:2]
    warnings = []
    if not has_guarantees:
        warnings.append("the spec has no guarantees (no [SYS_INIT], [SYS_TRANS] or [SYS_LIVENESS] clause): any "
                        "controller meets it")
    if alone is False:
        warnings.append("no play meets the environment's assumptions (initial condition, safety and goals "
                        "together): the spec is realizable only because the environment can never keep them")
    elif together is False:
        warnings.append("no play that keeps the robot's requirements meets the environment's assumptions: the spec "
                        "is realizable only because the environment can never keep them (the strategy is vacuous)")
    return Vacuity(has_guarantees, together, alone, tuple(warnings), complete=len(found) == 2)


def _satisfiable(game: Game, winning: object, cpre_winning: object, counts: Counts, told: Progress,
                 stop: Callable[[], None], found: list[bool]) -> None:
    """Append ``assumptions_satisfiable`` and then ``assumptions_satisfiable_alone`` (see ``check``)
    to ``found``."""
    bdd = game.bdd
    within = bdd.true if winning is None else winning
    initial = game.env_init & game.sys_init & within
    moving = None
    if winning is not None and cpre_winning is not None and not game.env_sees_outputs_next \
            and (winning & ~cpre_winning) == bdd.false:
        moving = game.alive()  # an admissible input exists
    together = initial != bdd.false and \
        (fair_states(game, game.sys_rel, within, initial, counts=counts, progress=told, moving=moving,
                     stop=stop) & initial) != bdd.false
    found.append(together)
    alone = together
    if not together:  # the joint answer implies this one; only a "no" needs it
        alone = game.env_init != bdd.false and \
            (fair_states(game, Relation(bdd, []), bdd.true, game.env_init, counts=counts, progress=told, stop=stop)
             & game.env_init) != bdd.false
    found.append(alone)
