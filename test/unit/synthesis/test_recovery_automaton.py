"""Independent model check of exported recovery automata (``explicit(recovery=True)``).

Only the automaton (as written to JSON and read back) and the spec's formulas evaluated here are
used; winning positions come from the explicit reference solver, not from the engine:

- every edge satisfies the system safety;
- every (state, input) for which some next output satisfies the system safety has exactly one edge;
  none has an edge when no output does;
- from a winning state an admissible input never leads out of W, and that edge is the ordinary
  strategy's (not marked recovery, and the same target as in the automaton without recovery);
- an edge is marked recovery exactly when the input breaks env safety or the state is outside W;
- the automaton without recovery is exactly the part of it that ordinary edges reach.
"""
from __future__ import annotations

import functools
import itertools
import json

import recovery_reference
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from random_specs import random_spec

from ltl_stack.spec import parse_structured
from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis import Automaton, synthesize

SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])


def valuations(names):
    return [dict(zip(names, bits, strict=True)) for bits in itertools.product((False, True), repeat=len(names))]


def key(inputs: dict, names: list[str]) -> tuple:
    return tuple(bool(inputs[n]) for n in names)


def model_check(spec, automaton: Automaton, plain: Automaton, winning) -> dict:
    """Assert the properties of the module docstring; returns counts for the caller."""
    by_id = {s.id: s for s in automaton.states}
    outputs = valuations(spec.outputs)
    inputs = valuations(spec.inputs)
    counts = {"edges": 0, "recovery": 0}
    for s in automaton.states:
        current = {**s.inputs, **s.outputs}
        here_winning = winning(current)
        assert set(s.recovery) <= set(s.successors)
        answered = {}
        for t in s.successors:
            target = by_id[t]
            k = key(target.inputs, spec.inputs)
            assert k not in answered, f"state {s.id} answers {target.inputs} twice"
            answered[k] = target
            nxt = {**target.inputs, **target.outputs}
            assert all(evaluate(c.formula, current, nxt) for c in spec.sys_safety), (s, target)
            admissible = all(evaluate(c.formula, current, target.inputs) for c in spec.env_safety)
            assert (t in s.recovery) == (not (here_winning and admissible)), (s.id, t)
            if here_winning and admissible:
                assert winning(nxt), f"{s.id} -> {t} leaves W on an admissible input"
        for x in inputs:
            can = any(all(evaluate(c.formula, current, {**x, **y}) for c in spec.sys_safety) for y in outputs)
            assert (key(x, spec.inputs) in answered) == can, (s.id, x, can)
        counts["edges"] += len(s.successors)
        counts["recovery"] += len(s.recovery)
    # the ordinary automaton is the part reached without recovery edges, state for state
    ordinary = set(automaton.initial)
    todo = list(automaton.initial)
    while todo:
        n = todo.pop()
        for t in by_id[n].successors:
            if t not in by_id[n].recovery and t not in ordinary:
                ordinary.add(t)
                todo.append(t)
    assert len(ordinary) == len(plain.states)
    for s in plain.states:
        twin = automaton.find(s.inputs, s.outputs, s.goal)
        assert twin is not None and twin.id in ordinary
        plain_targets = sorted((key(plain.states[t].inputs, spec.inputs), key(plain.states[t].outputs, spec.outputs),
                                plain.states[t].goal) for t in s.successors)
        rec_targets = sorted((key(by_id[t].inputs, spec.inputs), key(by_id[t].outputs, spec.outputs), by_id[t].goal)
                             for t in twin.successors if t not in twin.recovery)
        assert plain_targets == rec_targets, s.id
    return counts


def roundtrip(automaton: Automaton) -> Automaton:
    return Automaton.from_json(json.loads(json.dumps(automaton.to_json())))


@functools.lru_cache(maxsize=128)
def solved(seed: int, robotics: bool):
    spec = random_spec(seed, max_inputs=3, max_outputs=3)
    result = synthesize(spec, robotics_semantics=robotics, cooperative=False)
    return spec, result


@SETTINGS
@given(seed=st.integers(0, 3000), robotics=st.booleans())
def test_recovery_automata_of_random_specs_pass_the_model_check(seed, robotics):
    spec, result = solved(seed, robotics)
    assume(result.realizable)
    reference = recovery_reference.build(spec)
    automaton = roundtrip(result.strategy.explicit(max_states=4000, recovery=True))
    plain = result.strategy.explicit(max_states=4000)
    assert automaton.metadata.get("recovery") is True
    model_check(spec, automaton, plain, lambda v: bool(reference.winning[reference.index(spec, v)]))


PROBE = """\
[INPUT]
person
door
[OUTPUT]
stop
[ENV_TRANS]
door'
[SYS_TRANS]
person' -> stop'
"""


def test_probe_automaton_marks_violating_inputs_as_recovery_in_every_format():
    spec = parse_structured(PROBE, "probe.structuredslugs")
    strategy = synthesize(spec).strategy
    automaton = strategy.explicit(recovery=True)
    counts = model_check(spec, roundtrip(automaton), strategy.explicit(), lambda v: True)
    # 8 states x 4 inputs, the 2 inputs with door=0 are recovery edges
    assert counts == {"edges": 32, "recovery": 16}
    for s in automaton.states:
        for t in s.recovery:
            assert automaton.states[t].inputs["door"] is False
            if automaton.states[t].inputs["person"]:
                assert automaton.states[t].outputs["stop"] is True
    slugs = automaton.to_slugs_json()
    assert sum(len(n.get("recovery", [])) for n in slugs["nodes"].values()) == 16
    back = Automaton.from_slugs_json(json.loads(json.dumps(slugs)), inputs=spec.inputs)
    assert [s.recovery for s in back.states] == [s.recovery for s in automaton.states]
    dot = automaton.to_dot()
    assert dot.count("style=dashed") == 16
    assert "recovery" not in json.dumps(strategy.explicit().to_json())
