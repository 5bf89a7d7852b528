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
import json

import recovery_reference
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from random_specs import random_spec

from ltl_stack.spec import parse_structured
from ltl_stack.synthesis import Automaton, synthesize

SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])


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
    recovery_reference.model_check(spec, automaton, plain, lambda v: bool(reference.winning[reference.index(spec, v)]))


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
    counts = recovery_reference.model_check(spec, roundtrip(automaton), strategy.explicit(), lambda v: True)
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
