"""Explicit strategy extraction: thesis Alg. 1, lines 1-18.

Starting from every winning initial position with goal 0, breadth first, each state gets exactly
one successor per next input admissible under env safety; the successor's outputs are chosen by the
symbolic strategy (earliest Y iterate of the current goal, ``SymbolicStrategy._move``) and the goal
index advances when the move reaches the goal. Recovery transitions (lines 19-25) would be added
where ``_move`` returns None.

This enumerates the automaton and is meant for export, viewing and small specs; executing a
strategy needs only ``SymbolicStrategy.step``.
"""
from __future__ import annotations

from collections import deque

from ltl_stack.synthesis.automaton import Automaton, AutomatonState
from ltl_stack.synthesis.errors import SynthesisError
from ltl_stack.synthesis.strategy import State, SymbolicStrategy


class TooManyStates(SynthesisError):
    """The explicit automaton exceeds ``max_states``."""


def _bits_of(values: tuple[bool, ...]) -> int:
    return sum(int(v) << k for k, v in enumerate(values))


def initial_states(strategy: SymbolicStrategy) -> list[State]:
    """Every winning initial position (goal 0 unless already met there), ordered by ``State.id``."""
    game = strategy.game
    bdd = game.bdd
    result = []
    for a in bdd.pick_iter(strategy.initial, care_vars=set(game.variables)):
        result.append(strategy.start_state({n: bool(a[n]) for n in game.inputs},
                                           {n: bool(a[n]) for n in game.outputs}))
    result.sort(key=lambda s: s.id)
    return result


def extract(strategy: SymbolicStrategy, *, max_states: int | None = None, progress=None) -> Automaton:
    game = strategy.game
    bdd = game.bdd
    names = game.variables
    nxt_names = game.variables_next
    n_in = len(game.inputs)
    goals = len(strategy.relations)
    numbers: dict[tuple[tuple[bool, ...], int], int] = {}
    states: list[AutomatonState] = []
    todo: deque[tuple[tuple[bool, ...], int, int]] = deque()
    skip_cache: dict[tuple[tuple[bool, ...], int], int] = {}

    def number(values: tuple[bool, ...], goal: int) -> int:
        key = (values, goal)
        n = numbers.get(key)
        if n is None:
            n = numbers[key] = len(states)
            if max_states is not None and n >= max_states:
                raise TooManyStates(f"the explicit strategy has more than {max_states} states")
            states.append(AutomatonState(n, dict(zip(game.inputs, values[:n_in], strict=True)),
                                         dict(zip(game.outputs, values[n_in:], strict=True)), goal))
            todo.append((values, goal, n))
        return n

    def skip(values: tuple[bool, ...], goal: int) -> int:
        key = (values, goal)
        g = skip_cache.get(key)
        if g is None:
            g = skip_cache[key] = strategy._skip_satisfied(
                dict(zip(game.inputs, values[:n_in], strict=True)),
                dict(zip(game.outputs, values[n_in:], strict=True)), goal)
        return g

    initial = [number(tuple(s.valuation.values()), s.goal) for s in initial_states(strategy)]
    moves_of = [strategy.deterministic(j) & game.env_trans for j in range(goals)]
    care = set(nxt_names)
    while todo:
        values, goal, n = todo.popleft()
        here = dict(zip(names, values, strict=True))
        moves = bdd.let(here, moves_of[goal])
        reached = bdd.let(here, strategy.reached[goal])
        edges = []
        for goal_reached, part in ((True, moves & reached), (False, moves & ~reached)):
            start_goal = (goal + 1) % goals if goal_reached else goal
            for a in bdd.pick_iter(part, care_vars=care):
                target = tuple(bool(a[v]) for v in nxt_names)
                edges.append((_bits_of(target[:n_in]), number(target, skip(target, start_goal))))
        # Admissible inputs without a move (none from winning states) would get Alg. 1's
        # recovery transitions (lines 19-25) here.
        edges.sort()
        states[n].successors = [t for _, t in edges]
        if progress and len(states) % 5000 == 0:
            progress(f"explicit strategy: {len(states)} states, {len(todo)} to expand")
    meta = {"cooperative": strategy.cooperative,
            "robotics_semantics": strategy.solution.robotics_semantics,
            "source": getattr(game.spec, "source", "")}
    return Automaton(list(game.inputs), list(game.outputs), states, initial, len(game.sys_goals), meta)
