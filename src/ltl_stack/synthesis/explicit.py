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


def _bits(values: dict[str, bool]) -> int:
    return sum(int(v) << k for k, v in enumerate(values.values()))


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
    numbers: dict[tuple, int] = {}
    states: list[AutomatonState] = []
    todo: deque[tuple[State, int]] = deque()

    def number(s: State) -> int:
        key = (s.id, s.goal)
        n = numbers.get(key)
        if n is None:
            n = numbers[key] = len(states)
            if max_states is not None and n >= max_states:
                raise TooManyStates(f"the explicit strategy has more than {max_states} states")
            states.append(AutomatonState(n, dict(s.inputs), dict(s.outputs), s.goal))
            todo.append((s, n))
        return n

    initial = [number(s) for s in initial_states(strategy)]
    inputs_next = game.inputs_next
    care = set(inputs_next)
    while todo:
        s, n = todo.popleft()
        here = game.assignment(s.valuation)
        admissible = bdd.let(here, game.env_trans)
        moves = []
        for a in bdd.pick_iter(admissible, care_vars=care):
            moves.append({name: bool(a[inputs_next[k]]) for k, name in enumerate(game.inputs)})
        moves.sort(key=_bits)
        succ = []
        for new_inputs in moves:
            assign = {**here, **{inputs_next[k]: v for k, v in enumerate(new_inputs.values())}}
            outputs = strategy._move(s, new_inputs, assign)
            if outputs is None:
                continue  # Alg. 1 lines 19-25 would add a recovery transition here.
            succ.append(number(strategy._successor(s, new_inputs, outputs)))
        states[n].successors = succ
        if progress and len(states) % 5000 == 0:
            progress(f"explicit strategy: {len(states)} states, {len(todo)} to expand")
    meta = {"cooperative": strategy.cooperative,
            "robotics_semantics": strategy.solution.robotics_semantics,
            "source": getattr(game.spec, "source", "")}
    return Automaton(list(game.inputs), list(game.outputs), states, initial, len(game.sys_goals), meta)
