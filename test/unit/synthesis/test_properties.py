"""Property tests (hypothesis) of extracted strategies, on seeded random realizable specs.

Every check evaluates the spec's formulas itself (``ltl_stack.spec.formula.evaluate``) and compares
positions with the independent reference solver's winning set, never with the engine's own BDDs.
"""
from __future__ import annotations

import functools
import itertools

import pytest
import reference_solver
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from random_specs import random_spec

from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis import AssumptionViolation, NoInitialState, synthesize

SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])


def valuations(names):
    return [dict(zip(names, bits)) for bits in itertools.product((False, True), repeat=len(names))]


def holds(clauses, current, nxt=None):
    return all(evaluate(c.formula, current, nxt) for c in clauses)


@functools.lru_cache(maxsize=512)
def solved(seed: int, robotics: bool, cooperative: bool):
    """(spec, synthesis result, reference winning positions as a set of valuation tuples)."""
    spec = random_spec(seed, max_inputs=3, max_outputs=3)
    result = synthesize(spec, robotics_semantics=robotics, cooperative=cooperative)
    game = reference_solver.build_game(spec)
    w = reference_solver.winning_positions(game)
    winning = {(x, y) for x in range(w.shape[0]) for y in range(w.shape[1]) if w[x, y]}
    return spec, result, winning


def position(spec, valuation) -> tuple[int, int]:
    x = sum(int(valuation[n]) << k for k, n in enumerate(spec.inputs))
    y = sum(int(valuation[n]) << k for k, n in enumerate(spec.outputs))
    return x, y


def admissible(spec, current):
    return [x for x in valuations(spec.inputs) if holds(spec.env_safety, current, x)]


seeds = st.integers(min_value=0, max_value=3000)
semantics = st.booleans()


def realizable_case(seed, robotics, cooperative=False):
    spec, result, winning = solved(seed, robotics, cooperative)
    assume(result.realizable)
    return spec, result.strategy, winning


@SETTINGS
@given(seed=seeds, robotics=semantics, choices=st.lists(st.integers(0, 63), min_size=1, max_size=25))
def test_every_step_keeps_sys_safety_and_stays_winning(seed, robotics, choices):
    spec, strategy, winning = realizable_case(seed, robotics)
    state = strategy.initial_state()
    current = state.valuation
    assert holds(spec.env_init, current) and holds(spec.sys_init, current), current
    assert position(spec, current) in winning
    for choice in choices:
        allowed = admissible(spec, current)
        got = strategy.admissible_inputs(state)
        assert sorted(map(str, got)) == sorted(map(str, allowed)), (got, allowed)
        if not allowed:
            break  # the environment cannot move without breaking its assumptions: the robot has won
        new_inputs = allowed[choice % len(allowed)]
        state = strategy.step(state, new_inputs)
        assert state.inputs == new_inputs, state
        nxt = state.valuation
        assert holds(spec.sys_safety, current, nxt), (current, nxt)
        assert position(spec, nxt) in winning, nxt
        assert 0 <= state.goal < max(1, len(spec.sys_liveness)), state
        current = nxt


@SETTINGS
@given(seed=seeds, robotics=semantics, choices=st.lists(st.integers(0, 63), min_size=1, max_size=8))
def test_assumption_violation_exactly_when_env_safety_breaks(seed, robotics, choices):
    spec, strategy, _ = realizable_case(seed, robotics)
    state = strategy.initial_state()
    for choice in choices:
        current = state.valuation
        for new_inputs in valuations(spec.inputs):
            broken = [c for c in spec.env_safety if not evaluate(c.formula, current, new_inputs)]
            if broken:
                with pytest.raises(AssumptionViolation) as info:
                    strategy.step(state, new_inputs)
                assert info.value.clauses == broken, (info.value.clauses, broken)
                for clause in broken:
                    assert clause.location in str(info.value), str(info.value)
            else:
                strategy.step(state, new_inputs)  # must not raise
        allowed = admissible(spec, current)
        if not allowed:
            break
        state = strategy.step(state, allowed[choice % len(allowed)])


@SETTINGS
@given(seed=seeds, robotics=semantics)
def test_initial_states_satisfy_init(seed, robotics):
    spec, strategy, winning = realizable_case(seed, robotics)
    for x in valuations(spec.inputs):
        if not holds(spec.env_init, x):
            with pytest.raises(NoInitialState):
                strategy.initial_state(inputs=x)
            continue
        if robotics:  # every position allowed by both init conditions is an initial state
            for y in valuations(spec.outputs):
                if holds(spec.sys_init, {**x, **y}):
                    state = strategy.initial_state(inputs=x, outputs=y)
                    assert (state.inputs, state.outputs) == (x, y), state
        state = strategy.initial_state(inputs=x)  # default semantics: some output answers x
        assert state.inputs == x and holds(spec.sys_init, state.valuation), state
        assert position(spec, state.valuation) in winning


def strongly_connected(succ: dict[int, list[int]]) -> list[set[int]]:
    """Tarjan-free SCCs for small graphs: mutual reachability by BFS from every node."""
    reach = {}
    for start in succ:
        seen, todo = {start}, [start]
        while todo:
            n = todo.pop()
            for m in succ[n]:
                if m not in seen:
                    seen.add(m)
                    todo.append(m)
        reach[start] = seen
    components, done = [], set()
    for n in succ:
        if n in done:
            continue
        comp = {m for m in reach[n] if n in reach[m]}
        done |= comp
        components.append(comp)
    return components


@SETTINGS
@given(seed=seeds, robotics=semantics)
def test_explicit_automaton_is_a_winning_strategy(seed, robotics):
    """Each state answers every admissible input once, within sys safety; and no cycle meets every
    env liveness while missing a goal forever (so on every fair run the goal index keeps cycling)."""
    spec, strategy, winning = realizable_case(seed, robotics)
    automaton = strategy.explicit(max_states=4000)
    states = {s.id: s for s in automaton.states}
    val = {s.id: {**s.inputs, **s.outputs} for s in automaton.states}
    assert automaton.initial
    for i in automaton.initial:
        assert holds(spec.env_init, val[i]) and holds(spec.sys_init, val[i]), val[i]
    if robotics:
        starts = {position(spec, val[i]) for i in automaton.initial}
        expected = {position(spec, {**x, **y}) for x in valuations(spec.inputs) for y in valuations(spec.outputs)
                    if holds(spec.env_init, x) and holds(spec.sys_init, {**x, **y})}
        assert starts == expected, (starts, expected)
    goals = [c.formula for c in spec.sys_liveness]
    for s in automaton.states:
        assert position(spec, val[s.id]) in winning
        assert 0 <= s.goal < max(1, len(goals))
        answered = [states[t].inputs for t in s.successors]
        assert sorted(map(str, answered)) == sorted(map(str, admissible(spec, val[s.id]))), s
        for t in s.successors:
            assert holds(spec.sys_safety, val[s.id], val[t]), (s, states[t])
    succ = {s.id: list(s.successors) for s in automaton.states}
    assumptions = [c.formula for c in spec.env_liveness]
    for goal in goals:
        # edges that do not meet the goal: a fair cycle among them would be a losing run
        avoiding = {n: [m for m in targets if not evaluate(goal, val[n], val[m])] for n, targets in succ.items()}
        for comp in strongly_connected(avoiding):
            edges = [(n, m) for n in comp for m in avoiding[n] if m in comp]
            if not edges:
                continue
            fair = all(any(evaluate(a, val[n], val[m]) for n, m in edges) for a in assumptions)
            assert not fair, f"a fair cycle never meets goal {goal}: {sorted(comp)}"


@functools.lru_cache(maxsize=512)
def cooperative_game_won(seed: int, robotics: bool) -> bool:
    """Reference: can the robot win without ever leaving the environment without an admissible input?"""
    game = reference_solver.build_game(random_spec(seed, max_inputs=3, max_outputs=3), cooperative=True)
    return reference_solver.realizable_from(game, reference_solver.winning_positions(game), robotics)


@SETTINGS
@given(seed=seeds, robotics=semantics, choices=st.lists(st.integers(0, 63), min_size=1, max_size=20))
def test_cooperative_strategy_never_traps_the_environment(seed, robotics, choices):
    """When the robot can win without trapping the environment (reference), the cooperative strategy
    says so (``fully_cooperative``) and never leaves the environment without an admissible input.
    Otherwise it is the ordinary strategy with a preference only: nothing strict to check."""
    spec, strategy, _ = realizable_case(seed, robotics, cooperative=True)
    fully = cooperative_game_won(seed, robotics)
    assert strategy.fully_cooperative == fully, (seed, robotics, fully)
    assume(fully)
    state = strategy.initial_state()
    for choice in choices:
        allowed = admissible(spec, state.valuation)
        if not allowed:
            break  # trapped from the start: the initial position was allowed by the init conditions
        state = strategy.step(state, allowed[choice % len(allowed)])
        assert admissible(spec, state.valuation), (seed, state)
