"""Explicit strategy extraction: thesis Alg. 1, lines 1-18.

Starting from every winning initial position with goal 0, breadth first, each state gets exactly
one successor per next input admissible under env safety; the successor's outputs are chosen by the
symbolic strategy (earliest Y iterate of the current goal, ``SymbolicStrategy._move``) and the goal
index advances when the move reaches the goal.

With ``recovery=True`` (Alg. 1 lines 19-25, ``ltl_stack.synthesis.recovery``) every (state, input)
for which some move satisfies sys safety gets one edge: inputs that break env safety, and every
input from states outside W (which only recovery edges reach). Those edges are the recovery
relation's moves (the same ones ``SymbolicStrategy.step_result`` takes) and are listed in
``AutomatonState.recovery``; edges from winning states on admissible inputs are the ordinary ones.

This enumerates the automaton and is meant for export, viewing and small specs; executing a
strategy needs only ``SymbolicStrategy.step``.
"""
from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Any, Protocol

from ltl_stack.synthesis.automaton import Automaton, AutomatonState
from ltl_stack.synthesis.errors import LimitReached
from ltl_stack.synthesis.game import BACKEND
from ltl_stack.synthesis.state import State

Progress = Callable[[str], None]


class TooManyStates(LimitReached):
    """The explicit automaton exceeds ``max_states`` (``Exit.LIMIT``)."""


class SymbolicStrategy(Protocol):
    """What extraction needs of ``strategy.SymbolicStrategy`` (which imports this module)."""

    game: Any
    solution: Any
    cooperative: bool
    initial: Any
    winning: Any
    relations: list
    reached: list

    def start_state(self, inputs: dict[str, bool], outputs: dict[str, bool]) -> State: ...

    def deterministic(self, j: int) -> Any: ...

    def recovery_relations(self) -> Any: ...

    def _skip_satisfied(self, inputs: dict[str, bool], outputs: dict[str, bool], goal: int) -> int: ...


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


def extract(strategy: SymbolicStrategy, *, max_states: int | None = None, progress: Progress | None = None,
            recovery: bool = False) -> Automaton:
    """The explicit automaton of ``strategy`` (with recovery edges when ``recovery``);
    ``TooManyStates`` past ``max_states``."""
    if recovery:
        return _extract_with_recovery(strategy, max_states, progress)
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
    check = game.deadline.check
    while todo:
        check()
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
        edges.sort()
        states[n].successors = [t for _, t in edges]
        if progress and len(states) % 5000 == 0:
            progress(f"explicit strategy: {len(states)} states, {len(todo)} to expand")
    meta = {"cooperative": strategy.cooperative,
            "robotics_semantics": strategy.solution.robotics_semantics,
            "source": getattr(game.spec, "source", "")}
    return Automaton(list(game.inputs), list(game.outputs), states, initial, len(game.sys_goals), meta)


def _codes(bdd, u, bit_of: dict[str, int]) -> list[int]:
    """Every satisfying valuation of ``u`` over the variables of ``bit_of`` (which must cover its
    support) as an integer with bit ``bit_of[v]`` set when v is true.

    Bottom-up over the BDD's nodes (each node's valuations of the variables below it computed
    once), skipped variables expanded with integer arithmetic: ``pick_iter`` builds one dict per
    valuation, which dominated the recovery export (millions of edges on thesis Ex. 8)."""
    if u == bdd.false:
        return []
    if BACKEND != "cudd":  # pragma: no cover - the autoref fallback
        return [sum(1 << bit_of[v] for v, val in a.items() if val)
                for a in bdd.pick_iter(u, care_vars=set(bit_of))]
    order = sorted(bit_of, key=bdd.level_of_var)
    position = {v: k for k, v in enumerate(order)}
    bits = [1 << bit_of[v] for v in order]
    end = len(order)
    memo: dict = {}

    def expand(codes: list[int], start: int, stop: int) -> list[int]:
        for k in range(start, stop):  # variables skipped between two nodes are free
            codes = codes + [c | bits[k] for c in codes]
        return codes

    def index(f) -> int:
        return end if f == bdd.true or f == bdd.false else position[f.var]

    def below(f) -> list[int]:
        """Valuations of the variables from f's own on."""
        if f == bdd.true:
            return [0]
        if f == bdd.false:
            return []
        found = memo.get(f)
        if found is not None:
            return found
        k = position[f.var]
        low, high = (~f.low, ~f.high) if f.negated else (f.low, f.high)
        codes = expand(below(low), k + 1, index(low)) + \
            [c | bits[k] for c in expand(below(high), k + 1, index(high))]
        memo[f] = codes
        return codes

    try:
        return expand(below(u), 0, index(u))
    finally:
        memo.clear()  # the recursive closure is a reference cycle: drop its BDD nodes now


def _extract_with_recovery(strategy: SymbolicStrategy, max_states: int | None,
                           progress: Progress | None) -> Automaton:
    """``extract`` with Alg. 1 lines 19-25: positions are coded as integers (input k is bit k,
    output k bit n_in + k) because recovery automata answer every input of every state."""
    game = strategy.game
    bdd = game.bdd
    n_in = len(game.inputs)
    n_vars = len(game.variables)
    in_mask = (1 << n_in) - 1
    goals = len(strategy.relations)
    current_bit = {v: k for k, v in enumerate(game.variables)}
    next_bit = {v: k for k, v in enumerate(game.variables_next)}
    input_bit = {v: k for k, v in enumerate(game.inputs_next)}
    numbers: dict[int, int] = {}
    states: list[AutomatonState] = []
    codes: list[int] = []
    todo: deque[int] = deque()
    skip_cache: dict[int, int] = {}
    target_of: dict[int, int] = {}  # next position | goal the move starts it with -> state number

    def valuation(code: int) -> dict[str, bool]:
        return {v: bool(code >> k & 1) for v, k in current_bit.items()}

    def number(code: int, goal: int) -> int:
        key = code | goal << n_vars
        n = numbers.get(key)
        if n is None:
            n = numbers[key] = len(states)
            if max_states is not None and n >= max_states:
                raise TooManyStates(f"the explicit strategy has more than {max_states} states")
            values = valuation(code)
            states.append(AutomatonState(n, {v: values[v] for v in game.inputs},
                                         {v: values[v] for v in game.outputs}, goal))
            codes.append(code)
            todo.append(n)
        return n

    def skip(code: int, goal: int) -> int:
        key = code | goal << n_vars
        g = skip_cache.get(key)
        if g is None:
            values = valuation(code)
            g = skip_cache[key] = strategy._skip_satisfied({v: values[v] for v in game.inputs},
                                                           {v: values[v] for v in game.outputs}, goal)
        return g

    initial = []
    for s in initial_states(strategy):
        code = sum(1 << current_bit[v] for v, val in s.valuation.items() if val)
        initial.append(number(code, s.goal))
    rec = strategy.recovery_relations()
    # winning position & admissible input: the ordinary move; anything else: recovery
    ordinary = strategy.winning & game.env_trans
    moves_of = [(ordinary & strategy.deterministic(j) & game.env_trans) | (~ordinary & rec.deterministic(j))
                for j in range(goals)]
    check = game.deadline.check
    while todo:
        check()
        n = todo.popleft()
        goal = states[n].goal
        here = valuation(codes[n])
        moves = bdd.let(here, moves_of[goal])
        reached = bdd.let(here, strategy.reached[goal])
        marked = set(_codes(bdd, bdd.let(here, ~ordinary), input_bit))
        edges = []
        for goal_reached, part in ((True, moves & reached), (False, moves & ~reached)):
            start_goal = (goal + 1) % goals if goal_reached else goal
            shift = start_goal << n_vars
            for code in _codes(bdd, part, next_bit):
                t = target_of.get(code | shift)
                if t is None:
                    t = target_of[code | shift] = number(code, skip(code, start_goal))
                x = code & in_mask
                edges.append((x, t, x in marked))
        edges.sort()
        states[n].successors = [t for _, t, _ in edges]
        states[n].recovery = [t for _, t, r in edges if r]
        if progress and len(states) % 5000 == 0:
            progress(f"explicit strategy: {len(states)} states, {len(todo)} to expand")
    meta = {"cooperative": strategy.cooperative,
            "robotics_semantics": strategy.solution.robotics_semantics,
            "source": getattr(game.spec, "source", ""), "recovery": True}
    return Automaton(list(game.inputs), list(game.outputs), states, initial, len(game.sys_goals), meta)
