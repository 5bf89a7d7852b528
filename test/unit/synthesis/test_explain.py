"""Unrealizability explanations: kinds, minimal cores, the environment side and the counterstrategy.

Cores and the cooperative check are verified with the independent explicit solver
(``reference_solver``); counterstrategies are verified as graphs: env moves respect env safety, the
robot's answers are all there, and every cycle keeps some goal unmet while meeting every env liveness.
"""
from __future__ import annotations

import itertools
import json

import pytest
import reference_solver
from helpers import require_shared
from random_specs import make_spec, random_spec

from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis.explain import DEADLOCK, INIT, LIVELOCK, explain
from ltl_stack.synthesis.explain_render import counterstrategy_dot, explanation_dict, explanation_text


def with_core(spec, core):
    return (spec.with_section("sys_safety", [c for s, c in core if s == "sys_safety"])
                .with_section("sys_liveness", [c for s, c in core if s == "sys_liveness"]))


def check_core(spec, explanation, robotics):
    """The core is unrealizable and removing any one clause of it makes it realizable."""
    core = explanation.core
    assert not reference_solver.is_realizable(with_core(spec, core), robotics_semantics=robotics), core
    for k in range(len(core)):
        smaller = core[:k] + core[k + 1:]
        assert reference_solver.is_realizable(with_core(spec, smaller), robotics_semantics=robotics), (k, core)


def check_assumption_core(spec, explanation):
    assert explanation.cooperative_possible == reference_solver.cooperative_possible(spec)
    if explanation.cooperative_possible:
        assert explanation.assumption_core == []
        return
    core = explanation.assumption_core

    def env_only(clauses):
        return (spec.with_section("env_safety", [c for s, c in clauses if s == "env_safety"])
                    .with_section("env_liveness", [c for s, c in clauses if s == "env_liveness"]))

    assert not reference_solver.cooperative_possible(env_only(core)), core
    for k in range(len(core)):
        assert reference_solver.cooperative_possible(env_only(core[:k] + core[k + 1:])), (k, core)


def all_valuations(names):
    for bits in itertools.product((False, True), repeat=len(names)):
        yield dict(zip(names, bits))


def holds(clauses, current, nxt=None):
    return all(evaluate(c.formula, current, nxt) for c in clauses)


def check_deadlock_path(spec, d):
    """The path is a legal play from an initial position that ends in a move with no safe answer."""
    current = d["start"]
    assert holds(spec.env_init, current) and holds(spec.sys_init, current), d
    for move in d["path"]:
        assert move["position"] == current
        assert holds(spec.env_safety, current, move["inputs_next"]), d
        current = {**move["inputs_next"], **move["outputs_next"]}
        assert holds(spec.sys_safety, move["position"], current), d
    assert current == d["position"] and holds(spec.env_safety, current, d["inputs_next"]), d
    assert not any(holds(spec.sys_safety, current, {**d["inputs_next"], **y}) for y in all_valuations(spec.outputs))


def strongly_connected_components(succ: dict[int, list[int]]) -> list[set[int]]:
    """Kosaraju's algorithm, iterative."""
    order, seen = [], set()
    for root in succ:
        if root in seen:
            continue
        seen.add(root)
        stack = [(root, iter(succ[root]))]
        while stack:
            node, it = stack[-1]
            nxt = next((n for n in it if n not in seen), None)
            if nxt is None:
                order.append(node)
                stack.pop()
            else:
                seen.add(nxt)
                stack.append((nxt, iter(succ[nxt])))
    pred = {n: [] for n in succ}
    for n, targets in succ.items():
        for t in targets:
            pred[t].append(n)
    components, done = [], set()
    for root in reversed(order):
        if root in done:
            continue
        comp, stack = set(), [root]
        done.add(root)
        while stack:
            n = stack.pop()
            comp.add(n)
            for p in pred[n]:
                if p not in done:
                    done.add(p)
                    stack.append(p)
        components.append(comp)
    return components


def has_cycle(nodes: set[int], edges: list[tuple[int, int]]) -> bool:
    succ = {n: [v for u, v in edges if u == n] for n in nodes}
    return any(len(c) > 1 or c_node in succ[c_node]
               for c in strongly_connected_components(succ) for c_node in [next(iter(c))])


def check_counterstrategy(spec, cs, robotics):
    """The graph is a winning strategy for the environment from a losing initial condition."""
    assert cs is not None and not cs.truncated
    states = {s.id: s for s in cs.states}
    val = {s.id: {**s.inputs, **s.outputs} for s in cs.states}
    # initial states: a losing initial condition, with every robot choice (default semantics)
    assert cs.initial
    first = states[cs.initial[0]]
    assert holds(spec.env_init, first.inputs)
    if robotics:
        assert len(cs.initial) == 1 and holds(spec.sys_init, val[first.id])
    else:
        answers = [y for y in all_valuations(spec.outputs) if holds(spec.sys_init, {**first.inputs, **y})]
        got = sorted(tuple(states[i].outputs.values()) for i in cs.initial)
        assert got == sorted(tuple(y.values()) for y in answers), got
    for s in cs.states:
        assert s.env_move is not None, s
        assert holds(spec.env_safety, val[s.id], s.env_move), s
        answers = [y for y in all_valuations(spec.outputs) if holds(spec.sys_safety, val[s.id], {**s.env_move, **y})]
        assert s.robot_stuck == (not answers), s
        got = sorted(tuple(states[t].outputs.values()) for t in s.successors)
        assert got == sorted(tuple(y.values()) for y in answers), s
        assert all(states[t].inputs == s.env_move for t in s.successors), s
    # every infinite play stays eventually in one SCC; there the env must block a goal and meet its goals
    succ = {s.id: list(s.successors) for s in cs.states}
    goals = [c.formula for c in spec.sys_liveness]
    assumptions = [c.formula for c in spec.env_liveness]
    for comp in strongly_connected_components(succ):
        edges = [(u, v) for u in comp for v in succ[u] if v in comp]
        if not edges:
            continue
        blocked = [j for j, g in enumerate(goals) if not any(evaluate(g, val[u], val[v]) for u, v in edges)]
        assert blocked, f"a cycle meets every goal: {sorted(comp)}"
        for a in assumptions:
            avoiding = [(u, v) for u, v in edges if not evaluate(a, val[u], val[v])]
            assert not has_cycle(comp, avoiding), f"a cycle avoids env liveness {a}: {sorted(comp)}"


HAND = {
    # env must keep i once it is true and starts with it; the robot must never see i'
    "deadlock": dict(env_init=["i"], env_safety=["| ! i i'"], sys_safety=["! i'", "| ! o o'"],
                     sys_liveness=["o"]),
    # the robot may never set o again, so the goal o is out of reach; the other goal is fine
    "livelock": dict(sys_init=["! o"], sys_safety=["! o'"], sys_liveness=["o", "! o"]),
    # the env may keep i forever (it satisfies i | o), the robot needs o then i'
    "env livelock": dict(sys_liveness=["& o i'"], env_liveness=["| i o"]),
    # no initial output satisfies sys_init when i holds
    "init": dict(env_init=["i"], sys_init=["& o ! o"]),
    # the env is made to keep i forever; the goal needs !i': weakening that assumption matters
    "assumption conflict": dict(env_init=["i"], env_safety=["| ! i i'"], sys_liveness=["! i'"]),
}


def hand_spec(name):
    return make_spec(["i"], ["o"], file=f"{name.replace(' ', '_')}.slugsin", **HAND[name])


@pytest.mark.parametrize("robotics", [True, False])
def test_deadlock(robotics):
    spec = hand_spec("deadlock")
    e = explain(spec, robotics_semantics=robotics, counterstrategy=True)
    assert (e.realizable, e.kind) == (False, DEADLOCK), (e.realizable, e.kind)
    assert [c.text for _, c in e.core] == ["! i'"], e.core
    assert e.deadlock is not None and e.deadlock["inputs_next"] == {"i": True}, e.deadlock
    assert e.cooperative_possible is False          # env safety forces i', sys safety forbids it
    assert [c.text for _, c in e.assumption_core] == ["| ! i i'"], e.assumption_core
    check_core(spec, e, robotics)
    check_assumption_core(spec, e)
    check_counterstrategy(spec, e.counterstrategy, robotics)
    assert all(s.robot_stuck for s in e.counterstrategy.states)
    text = explanation_text(e)
    assert "Deadlock" in text and "deadlock.slugsin:3: [sys_safety] ! i'" in text, text


def test_livelock_names_the_goal_that_fails():
    spec = hand_spec("livelock")
    e = explain(spec, counterstrategy=True)
    assert (e.kind, [c.text for c in e.failing_goals]) == (LIVELOCK, ["o"]), (e.kind, e.failing_goals)
    assert sorted(c.text for _, c in e.core) == ["! o'", "o"], e.core
    assert e.cooperative_possible is False and e.assumption_core == []
    check_core(spec, e, True)
    check_counterstrategy(spec, e.counterstrategy, True)
    text = explanation_text(e)
    assert "livelock.slugsin:3: [sys_liveness] o\n" in text, text
    assert "conflict among themselves" in text, text


@pytest.mark.parametrize("robotics", [True, False])
def test_livelock_caused_by_the_environment(robotics):
    spec = hand_spec("env livelock")
    e = explain(spec, robotics_semantics=robotics, counterstrategy=True)
    assert e.kind == LIVELOCK and e.cooperative_possible is True, (e.kind, e.cooperative_possible)
    assert [c.text for c in e.failing_goals] == ["& o i'"], e.failing_goals
    check_counterstrategy(spec, e.counterstrategy, robotics)
    assert "environment can prevent it" in explanation_text(e)


def test_init_failure_default_semantics():
    spec = hand_spec("init")
    e = explain(spec, robotics_semantics=False)
    assert (e.kind, e.losing_initial, e.core) == (INIT, {"i": True}, []), (e.kind, e.losing_initial, e.core)
    assert [c.text for c in e.init_clauses] == ["& o ! o"]
    assert "init.slugsin:2: [sys_init] & o ! o" in explanation_text(e)
    # robotics semantics: no position satisfies both init conditions, so nothing has to be won
    assert explain(spec, robotics_semantics=True).realizable


def test_robotics_init_failure_says_default_semantics_would_do():
    spec = make_spec(["i"], ["o"], file="bad_init.slugsin", sys_safety=["! o"])
    e = explain(spec, robotics_semantics=True, counterstrategy=True)
    assert e.losing_initial == {"i": e.losing_initial["i"], "o": True}, e.losing_initial
    assert e.realizable_with_default_init is True
    assert "restricting sys_init" in explanation_text(e)
    check_counterstrategy(spec, e.counterstrategy, True)


def test_assumption_core_names_the_conflicting_assumption():
    spec = hand_spec("assumption conflict")
    e = explain(spec)
    assert e.cooperative_possible is False
    assert [(s, c.text) for s, c in e.assumption_core] == [("env_safety", "| ! i i'")], e.assumption_core
    assert "weakening one of them matters" in explanation_text(e)
    check_assumption_core(spec, e)


def test_realizable_spec_has_nothing_to_explain():
    spec = make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"], sys_liveness=["o"], env_liveness=["i"])
    e = explain(spec, counterstrategy=True)
    assert e.realizable and e.kind is None and e.counterstrategy is None
    assert "realizable" in explanation_text(e)


def test_to_dict_is_json_and_counterstrategy_exports():
    e = explain(hand_spec("env livelock"), counterstrategy=True)
    data = json.loads(json.dumps(explanation_dict(e)))
    assert data["kind"] == LIVELOCK and data["failing_goals"][0]["line"] == 2, data
    assert data["counterstrategy"]["states"], data
    dot = counterstrategy_dot(e.counterstrategy)
    assert dot.startswith("digraph") and dot.count("->") >= len(e.counterstrategy.states), dot


def test_progress_is_reported():
    messages = []
    explain(hand_spec("livelock"), progress=messages.append)
    assert any(m.startswith("system core: 3/3 clauses tried") for m in messages), messages


def test_random_unrealizable_specs():
    """Cores, kinds, the environment side and counterstrategies on random unrealizable specs."""
    checked = {DEADLOCK: 0, LIVELOCK: 0, INIT: 0}
    for seed, robotics in itertools.product(range(120), (True, False)):
        spec = random_spec(seed, max_inputs=3, max_outputs=3)
        if reference_solver.is_realizable(spec, robotics_semantics=robotics):
            continue
        e = explain(spec, robotics_semantics=robotics, counterstrategy=True)
        assert not e.realizable, seed
        safety_only = spec.with_section("sys_liveness", []).with_section("env_liveness", [])
        if e.kind != INIT:
            expected = DEADLOCK if not reference_solver.is_realizable(safety_only, robotics_semantics=robotics) \
                else LIVELOCK
            assert e.kind == expected, (seed, robotics, e.kind)
            if e.kind == DEADLOCK:
                check_deadlock_path(spec, e.deadlock)
            check_counterstrategy(spec, e.counterstrategy, robotics)
        check_core(spec, e, robotics)
        check_assumption_core(spec, e)
        checked[e.kind] += 1
    assert checked[DEADLOCK] >= 5 and checked[LIVELOCK] >= 5, checked


BENCHMARKS = {
    # env goals a&!b and b&!a can be met without ever a&b: the goal a&b alone fails
    "unrealizable1": (LIVELOCK, ["& a b"], True),
    # the env may order rice forever (its liveness), and an order forbids delivering next
    "unrealizable_waiter_txt": (LIVELOCK, ["| ! order_rice ! deliver'", "deliver"], True),
    # delivering is forbidden outright: the robot's own requirements conflict
    "unrealizable_waiter2_txt": (LIVELOCK, ["! deliver'", "deliver"], False),
    # rough' always vs. goal !rough'; without the r clause the robot would win by making the env
    # break its assumption | ! q r (set r' false when q' holds), so all three clauses belong to the core
    "section_3_2_errorneous_spec": (LIVELOCK, None, False),
    "example_outermost_fixed_point_unrealizability": (DEADLOCK, None, None),
}


@pytest.mark.parametrize("name", sorted(BENCHMARKS))
def test_slugs_unrealizable_examples(name):
    from ltl_stack.spec import load_spec

    path = require_shared("specs", "benchmarks", "slugsin", f"{name}.slugsin")
    spec = load_spec(path)
    kind, core_texts, cooperative = BENCHMARKS[name]
    for robotics in (True, False):
        e = explain(spec, robotics_semantics=robotics)
        assert (e.realizable, e.kind) == (False, kind), (robotics, e.realizable, e.kind)
        if core_texts is not None:
            assert sorted(c.text for _, c in e.core) == sorted(core_texts), e.core
        if cooperative is not None:
            assert e.cooperative_possible is cooperative
        for _, clause in e.core:
            assert f"{clause.location}: " in explanation_text(e)
    if name == "section_3_2_errorneous_spec":
        assert e.core_candidates == 3 and len(e.core) == 3, e.core


def test_spheros_problem_is_realizable():
    from ltl_stack.spec import load_spec

    spec = load_spec(require_shared("specs", "spheros_problem", "spheros_problem.slugsin"))
    assert explain(spec).realizable and explain(spec, robotics_semantics=False).realizable


def test_synthesize_cli_explains_and_writes_the_counterstrategy(tmp_path, capsys):
    from ltl_stack.spec import write_slugsin
    from ltl_stack.synthesis.cli import main

    path = tmp_path / "env_livelock.slugsin"
    path.write_text(write_slugsin(hand_spec("env livelock")))
    out = tmp_path / "counter.json"
    code = main([str(path), "--robotics-semantics", "--explain", "--counterstrategy", str(out)])
    text = capsys.readouterr().out
    assert code == 10, (code, text)
    assert "Livelock" in text and "[sys_liveness] & o i'" in text, text
    data = json.loads(out.read_text())
    assert data["states"] and data["initial"], data


def test_counterstrategy_starts_where_the_robot_can_answer_the_initial_inputs():
    # for i no output satisfies sys_init (init failure); for !i the robot starts but loses the goal i'
    spec = make_spec(["i"], ["o"], file="two_ways.slugsin", sys_init=["| ! i & o ! o"], sys_liveness=["i'"])
    e = explain(spec, robotics_semantics=False, counterstrategy=True)
    assert (e.kind, e.losing_initial) == (INIT, {"i": True}), (e.kind, e.losing_initial)
    cs = e.counterstrategy
    assert [cs.states[k].inputs for k in cs.initial] == [{"i": False}, {"i": False}], cs.initial
    check_counterstrategy(spec, cs, robotics=False)


@pytest.mark.parametrize("inputs, outputs, sections, kind", [
    ([], ["o"], dict(sys_safety=["! o'"], sys_liveness=["o"]), LIVELOCK),
    (["i"], [], dict(sys_liveness=["i"]), LIVELOCK),
    ([], ["o"], dict(sys_safety=["0"]), DEADLOCK),
])
def test_specs_without_inputs_or_outputs(inputs, outputs, sections, kind, capsys):
    spec = make_spec(inputs, outputs, **sections)
    for robotics in (True, False):
        e = explain(spec, robotics_semantics=robotics, counterstrategy=True)
        assert (e.realizable, e.kind) == (False, kind), (robotics, e.kind)
        check_core(spec, e, robotics)
        check_counterstrategy(spec, e.counterstrategy, robotics)
    assert capsys.readouterr().out == ""  # no stray warnings from the BDD library


@pytest.mark.parametrize("robotics", [True, False])
def test_deadlock_path_shows_how_the_environment_forces_it(robotics):
    # the robot must raise o at once and keep it; i' while o holds leaves it no safe move
    spec = make_spec(["i"], ["o"], file="forced.slugsin", sys_init=["! o"], sys_safety=["o'", "| ! i' ! o"])
    e = explain(spec, robotics_semantics=robotics)
    d = e.deadlock
    assert (e.kind, d["steps"], d["start"]["o"], d["position"]["o"]) == (DEADLOCK, 1, False, True), d
    check_deadlock_path(spec, d)
    assert "forces it within 1 move(s)" in explanation_text(e), explanation_text(e)
    json.dumps(explanation_dict(e))
