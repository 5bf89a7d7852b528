"""The symbolic strategy (initial_state, step), Alg. 1 extraction and the exports, on small specs."""
from __future__ import annotations

import json

import pytest
from random_specs import make_spec, random_spec

from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis import AssumptionViolation, Automaton, NoInitialState, State, synthesize


def strategy_of(spec, **kw):
    result = synthesize(spec, **kw)
    assert result.realizable, spec
    return result.strategy


def test_output_copies_input_step_by_step():
    strategy = strategy_of(make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"]))
    state = strategy.initial_state({"i": False})
    got = []
    for value in (True, True, False, True):
        state = strategy.step(state, {"i": value})
        got.append(state.outputs["o"])
    assert got == [True, True, False, True], got


def test_goals_are_cycled_and_counted():
    # two goals, o and !o, nothing else: the robot alternates and the goal index follows.
    strategy = strategy_of(make_spec(["i"], ["o"], sys_liveness=["o", "! o"]))
    state = strategy.initial_state({"i": False}, {"o": False})
    assert (state.goal, state.outputs) == (0, {"o": False})
    trace = []
    for _ in range(4):
        state = strategy.step(state, {"i": False})
        trace.append((state.outputs["o"], state.goal))
    assert trace == [(True, 1), (False, 0), (True, 1), (False, 0)], trace


def test_waits_for_the_environment_goal():
    # o may rise only with i'; the goal is o. Until i comes, the robot waits with o false.
    strategy = strategy_of(make_spec(["i"], ["o"], sys_safety=["| ! o' | o i'"], sys_liveness=["o"],
                                     env_liveness=["i"]))
    state = strategy.initial_state({"i": False}, {"o": False})
    outs = []
    for value in (False, False, True):
        state = strategy.step(state, {"i": value})
        outs.append(state.outputs["o"])
    assert outs == [False, False, True], outs


def test_assumption_violation_names_the_clause():
    spec = make_spec(["i"], ["o"], env_safety=["1", "| ! i ! i'"], file="toy.slugsin")
    strategy = strategy_of(spec)
    state = strategy.initial_state({"i": True})
    with pytest.raises(AssumptionViolation) as info:
        strategy.step(state, {"i": True})
    got = [(c.text, c.location) for c in info.value.clauses]
    assert got == [("| ! i ! i'", "toy.slugsin:2")], got
    assert "toy.slugsin:2" in str(info.value) and "| ! i ! i'" in str(info.value), str(info.value)


def test_no_initial_state_says_why():
    spec = make_spec(["i"], ["o"], env_init=["! i"], sys_init=["o"], file="init.slugsin")
    strategy = strategy_of(spec)
    with pytest.raises(NoInitialState, match=r"violates env_init \(init.slugsin:1"):
        strategy.initial_state({"i": True})
    with pytest.raises(NoInitialState, match="sys_init"):
        strategy.initial_state({"i": False}, {"o": False})
    assert strategy.initial_state().valuation == {"i": False, "o": True}


def test_step_rejects_missing_inputs():
    strategy = strategy_of(make_spec(["i", "j"], ["o"]))
    state = strategy.initial_state()
    with pytest.raises(ValueError, match="missing inputs j"):
        strategy.step(state, {"i": True})


def test_state_ids_are_stable():
    a = State({"i": True}, {"o": False, "p": True}, 0)
    b = State({"i": True}, {"o": False, "p": True}, 2)
    assert (a.id, b.id) == (0b101, 0b101 + (2 << 3)), (a.id, b.id)
    assert a == State({"i": True}, {"o": False, "p": True}, 0) and a != b


def test_explicit_automaton_of_a_toy_spec():
    # o copies i'; one goal (true). Initial positions are env_init & sys_init & W: all four
    # valuations. Each state has one successor per next input, with o' = i'.
    strategy = strategy_of(make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"]))
    automaton = strategy.explicit()
    got = sorted((tuple(s.inputs.values()), tuple(s.outputs.values()), len(s.successors))
                 for s in automaton.states)
    assert got == [((False,), (False,), 2), ((False,), (True,), 2),
                   ((True,), (False,), 2), ((True,), (True,), 2)], got
    assert sorted(automaton.initial) == [0, 1, 2, 3], automaton.initial
    for s in automaton.states:
        targets = [automaton.states[t] for t in s.successors]
        assert all(t.inputs["i"] == t.outputs["o"] for t in targets), s


def test_explicit_respects_safety_on_random_specs():
    checked = 0
    for seed in range(25):
        spec = random_spec(seed)
        for cooperative in (False, True):
            result = synthesize(spec, robotics_semantics=True, cooperative=cooperative)
            if not result.realizable:
                continue
            automaton = result.strategy.explicit()
            for s in automaton.states:
                cur = {**s.inputs, **s.outputs}
                for t in s.successors:
                    nxt = {**automaton.states[t].inputs, **automaton.states[t].outputs}
                    assert all(evaluate(c.formula, cur, nxt) for c in spec.sys_safety), (seed, s)
                    assert all(evaluate(c.formula, cur, nxt) for c in spec.env_safety), (seed, s)
            checked += 1
    assert checked >= 5, checked


def test_exports_round_trip(tmp_path):
    strategy = strategy_of(make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"], sys_liveness=["o", "! o"],
                                     env_liveness=["i", "! i"]))
    automaton = strategy.explicit()
    doc = automaton.to_json()
    again = Automaton.from_json(json.loads(json.dumps(doc)))
    assert again.to_json() == doc
    slugs = automaton.to_slugs_json()
    assert sorted(slugs) == ["nodes", "slugs", "variables", "version"], sorted(slugs)
    assert slugs["variables"] == ["i", "o"]
    node = slugs["nodes"]["0"]
    assert sorted(node) == ["rank", "state", "trans"] and len(node["state"]) == 2, node
    path = tmp_path / "s.json"
    path.write_text(json.dumps(slugs))
    loaded = Automaton.load(path, inputs=["i"])
    assert [(s.inputs, s.outputs, s.goal, s.successors) for s in loaded.states] == \
        [(s.inputs, s.outputs, s.goal, s.successors) for s in automaton.states]
    dot = automaton.to_dot()
    assert dot.startswith('digraph "strategy" {') and dot.count("->") == \
        sum(len(s.successors) for s in automaton.states), dot


def test_explicit_automaton_moves_are_moves_of_the_strategy():
    """The export may pick another allowed move than ``step`` (one that re-uses an existing state),
    but only moves of the goal's strategy relation, and the goal advances past one or more of the
    goals the move reaches in a row (``step`` past the first)."""
    reused = 0
    for seed in range(12):
        result = synthesize(random_spec(seed), robotics_semantics=True, cooperative=bool(seed % 2))
        if not result.realizable:
            continue
        strategy = result.strategy
        game = strategy.game
        bdd = game.bdd
        goals = len(strategy.relations)
        automaton = strategy.explicit()
        for s in automaton.states:
            here = State(dict(s.inputs), dict(s.outputs), s.goal)
            for t in s.successors:
                target = automaton.states[t]
                assign = game.assignment(here.valuation, {**target.inputs, **target.outputs})
                assert bdd.let(assign, strategy.relations[s.goal]) == bdd.true, (seed, s.id, t)
                allowed, g = set(), s.goal
                for _ in range(goals):
                    if bdd.let(assign, strategy.reached[g]) != bdd.true:
                        break
                    g = (g + 1) % goals
                    allowed.add(strategy._skip_satisfied(target.inputs, target.outputs, g))
                allowed = allowed or {strategy._skip_satisfied(target.inputs, target.outputs, s.goal)}
                assert target.goal in allowed, (seed, s.id, t, target.goal, allowed)
                got = strategy.step(here, target.inputs)
                assert got.goal in allowed
                reused += (got.outputs, got.goal) != (target.outputs, target.goal)
    assert reused > 0  # the preference for existing states does something on these specs
