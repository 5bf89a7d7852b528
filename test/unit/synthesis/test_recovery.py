"""Recovery mode of the symbolic strategy (thesis §4.6, Alg. 1 lines 19-25).

Hand-made specs check each rule (the issue's door/person probe, "closer to W" vs Alg. 1's B_(j,c),
the safety-depth preference, the UNSAFE report); hypothesis checks the rules on random specs and
random input sequences that include violating inputs, against the explicit reference
(``recovery_reference``, which shares no code with the engine).
"""
from __future__ import annotations

import functools
import itertools

import pytest
import recovery_reference
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from random_specs import random_spec

from ltl_stack.spec import parse_structured
from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis import AssumptionViolation, synthesize
from ltl_stack.synthesis.recovery import StepKind, UnsafeStep

SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])

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

# Locations s a m g (winning: the robot walks s-a-m-g) and traps t1 t2 t3 (the environment may jam
# the robot there forever). A push (forbidden by the assumptions) forces the robot from s into a trap.
# t1 is one step from W (t1 -> a) but far from the goal; t2 is two steps from W (t2 -> t3 -> g) and
# two from the goal transition. "Closer to W" (§4.6.2's prose, what we implement) picks t1; Alg. 1's
# B_(j,c) alone would pick t2; keeping the current outputs (the deterministic tie-break) picks t2 too.
TRAPS = """\
[INPUT]
jam
push
[OUTPUT]
s
a
m
g
t1
t2
t3
[SYS_INIT]
s & !a & !m & !g & !t1 & !t2 & !t3
[ENV_TRANS]
!push'
[SYS_TRANS]
(s' & !a' & !m' & !g' & !t1' & !t2' & !t3') | (!s' & a' & !m' & !g' & !t1' & !t2' & !t3') | (!s' & !a' & m' & !g' & !t1' & !t2' & !t3') | (!s' & !a' & !m' & g' & !t1' & !t2' & !t3') | (!s' & !a' & !m' & !g' & t1' & !t2' & !t3') | (!s' & !a' & !m' & !g' & !t1' & t2' & !t3') | (!s' & !a' & !m' & !g' & !t1' & !t2' & t3')
s -> (s' | a' | t1' | t2')
a -> (a' | m' | s')
m -> (m' | g' | a')
g -> (g' | m')
t1 -> (t1' | a')
t2 -> (t2' | t3')
t3 -> (t3' | g')
((t1 | t2 | t3) & jam') -> ((t1' <-> t1) & (t2' <-> t2) & (t3' <-> t3))
push' -> (t1' | t2' | t3')
[SYS_LIVENESS]
g
"""

# From s a push forces the robot into z1 (it can stay there safely forever) or z2 (where the input q
# leaves it no safe move). Neither leads back to W: the safety-depth preference picks z1; keeping the
# current outputs alone would pick z2.
DEAD_ENDS = """\
[INPUT]
push
q
[OUTPUT]
s
g
z1
z2
[SYS_INIT]
s & !g & !z1 & !z2
[ENV_TRANS]
!push'
[SYS_TRANS]
(s' & !g' & !z1' & !z2') | (!s' & g' & !z1' & !z2') | (!s' & !g' & z1' & !z2') | (!s' & !g' & !z1' & z2')
s -> (s' | g' | z1' | z2')
g -> (g' | s')
z1 -> z1'
z2 -> z2'
!(z2 & q')
push' -> (z1' | z2')
[SYS_LIVENESS]
g
"""

NO_SAFE_MOVE = """\
[INPUT]
a
[OUTPUT]
o
[ENV_TRANS]
!a'
[SYS_TRANS]
a' -> o'
a' -> !o'
o' | !o'
"""


def strategy_of(text: str, name: str, **kwargs):
    result = synthesize(parse_structured(text, name), **kwargs)
    assert result.realizable
    return result.strategy


def true_outputs(state) -> list[str]:
    return [n for n, v in state.outputs.items() if v]


def test_probe_person_keeps_stop_when_the_door_assumption_breaks():
    """The issue's probe: without recovery the step raises; with it stop stays true."""
    strategy = strategy_of(PROBE, "probe.structuredslugs")
    start = strategy.initial_state(inputs={"person": False, "door": True})
    with pytest.raises(AssumptionViolation):
        strategy.step(start, {"person": True, "door": False})
    strategy.recovery = True
    state = start
    for _ in range(3):
        result = strategy.step_result(state, {"person": True, "door": False})
        assert result.kind is StepKind.RECOVER_TO_W
        assert result.state.outputs == {"stop": True}
        assert [c.location for c in result.violated] == ["probe.structuredslugs:7"]
        state = strategy.step(state, {"person": True, "door": False})
        assert state.outputs == {"stop": True}
    back = strategy.step_result(state, {"person": False, "door": True})
    assert back.kind is StepKind.NORMAL and back.violated == []


def test_recovery_prefers_the_position_closest_to_w():
    strategy = strategy_of(TRAPS, "traps.structuredslugs", cooperative=False)
    strategy.recovery = True
    start = strategy.initial_state(inputs={"jam": False, "push": False})
    assert true_outputs(start) == ["s"]
    result = strategy.step_result(start, {"jam": False, "push": True})
    assert result.kind is StepKind.RECOVER_TOWARDS_W
    assert true_outputs(result.state) == ["t1"], "t1 is one rho_s step from W, t2 two"
    assert not result.in_winning and result.recoverable
    # the violation ends: back into W at once, then the ordinary strategy takes over
    back = strategy.step_result(result.state, {"jam": False, "push": False})
    assert back.kind is StepKind.RECOVER_TO_W and true_outputs(back.state) == ["a"]
    normal = strategy.step_result(back.state, {"jam": False, "push": False})
    assert normal.kind is StepKind.NORMAL


def test_recovery_keeps_the_robot_where_it_is_while_jammed_outside_w():
    strategy = strategy_of(TRAPS, "traps.structuredslugs", cooperative=False)
    strategy.recovery = True
    state = strategy.step(strategy.initial_state(inputs={"jam": False, "push": False}), {"jam": False, "push": True})
    for _ in range(3):  # jam is allowed by the assumptions, but the robot is outside W
        result = strategy.step_result(state, {"jam": True, "push": False})
        assert result.kind is StepKind.RECOVER_TOWARDS_W and result.violated == []
        assert true_outputs(result.state) == ["t1"]
        state = result.state


def test_outside_the_recoverable_region_prefer_moves_that_stay_safe_longest():
    strategy = strategy_of(DEAD_ENDS, "dead_ends.structuredslugs", cooperative=False)
    strategy.recovery = True
    start = strategy.initial_state(inputs={"push": False, "q": False})
    result = strategy.step_result(start, {"push": True, "q": False})
    assert result.kind is StepKind.SAFE_ONLY and result.outside_recoverable
    assert true_outputs(result.state) == ["z1"], "z2 leaves no safe move once q comes"
    # z1 is safe forever, whatever comes
    state = result.state
    for q in (True, False, True):
        state = strategy.step(state, {"push": False, "q": q})
        assert true_outputs(state) == ["z1"]


def test_no_safe_move_is_reported_with_the_clauses_that_cannot_be_kept():
    strategy = strategy_of(NO_SAFE_MOVE, "nosafe.structuredslugs")
    strategy.recovery = True
    start = strategy.initial_state(inputs={"a": False})
    result = strategy.step_result(start, {"a": True})
    assert result.kind is StepKind.UNSAFE and result.state is None
    assert [c.location for c in result.unsafe] == ["nosafe.structuredslugs:8", "nosafe.structuredslugs:9"]
    assert [c.location for c in result.violated] == ["nosafe.structuredslugs:6"]
    with pytest.raises(UnsafeStep) as info:
        strategy.step(start, {"a": True})
    assert isinstance(info.value, AssumptionViolation)
    text = str(info.value)
    for where in ("nosafe.structuredslugs:6", "nosafe.structuredslugs:8", "nosafe.structuredslugs:9"):
        assert where in text, text
    assert "nosafe.structuredslugs:10" not in text


# --- random specs ---------------------------------------------------------------------------------

def valuations(names):
    return [dict(zip(names, bits)) for bits in itertools.product((False, True), repeat=len(names))]


@functools.lru_cache(maxsize=256)
def solved(seed: int, robotics: bool, cooperative: bool):
    spec = random_spec(seed, max_inputs=3, max_outputs=3)
    result = synthesize(spec, robotics_semantics=robotics, cooperative=cooperative)
    if not result.realizable:
        return spec, None, None
    reference = recovery_reference.build(spec, cooperative=cooperative and result.strategy.fully_cooperative)
    return spec, result.strategy, reference


def check_recovery_step(spec, strategy, reference, state, new_inputs):
    """One recovery step against the explicit rules; returns the result."""
    current = state.valuation
    outputs = valuations(spec.outputs)
    safe = recovery_reference.safe_moves(spec, current, new_inputs, outputs)
    broken = [c for c in spec.env_safety if not evaluate(c.formula, current, new_inputs)]
    result = strategy.step_result(state, new_inputs)
    assert result.violated == broken
    if not safe:
        assert result.kind is StepKind.UNSAFE and result.state is None
        assert result.unsafe
        assert not recovery_reference.safe_moves(spec.with_section("sys_safety", result.unsafe), current,
                                                 new_inputs, outputs), "the reported clauses can be kept"
        return result
    nxt = result.state.valuation
    assert result.state.inputs == new_inputs
    assert any(y == result.state.outputs for y in safe), "the move breaks sys safety"
    here = reference.index(spec, current)
    targets = [reference.index(spec, {**new_inputs, **y}) for y in safe]
    into_w = [t for t in targets if reference.winning[t]]
    got = reference.index(spec, nxt)
    if reference.winning[here] and not broken:
        assert result.kind is StepKind.NORMAL
    if into_w:
        assert result.kind in (StepKind.NORMAL, StepKind.RECOVER_TO_W) and reference.winning[got]
        return result
    recoverable = [reference.distance[t] for t in targets if reference.distance[t] > 0]
    if recoverable:
        assert result.kind is StepKind.RECOVER_TOWARDS_W
        assert reference.distance[got] == min(recoverable), "not the closest to W"
        return result
    assert result.kind is StepKind.SAFE_ONLY
    assert reference.depth[got] == max(reference.depth[t] for t in targets), "not the safest move"
    return result


seeds = st.integers(min_value=0, max_value=3000)


@SETTINGS
@given(seed=seeds, robotics=st.booleans(), cooperative=st.booleans(),
       choices=st.lists(st.integers(0, 63), min_size=1, max_size=20), tail=st.lists(st.integers(0, 63), max_size=12))
def test_recovery_steps_keep_sys_safety_and_follow_the_rules(seed, robotics, cooperative, choices, tail):
    """Arbitrary inputs (violating ones included): every step keeps rho_s when some move can, picks by
    the recovery rules, and never gets stuck (a move or the explicit UNSAFE report). Once the
    position is winning and the inputs admissible again, it moves exactly as the normal strategy."""
    spec, strategy, reference = solved(seed, robotics, cooperative)
    assume(strategy is not None)
    strategy.recovery = False
    state = strategy.initial_state()
    inputs = valuations(spec.inputs)
    for choice in choices:
        result = check_recovery_step(spec, strategy, reference, state, inputs[choice % len(inputs)])
        if result.state is not None:  # UNSAFE: the caller holds the last state
            state = result.state
    # the violations stop: admissible inputs only, compared with the normal strategy
    normal_state = state
    for choice in tail:
        current = state.valuation
        allowed = [x for x in inputs if all(evaluate(c.formula, current, x) for c in spec.env_safety)]
        if not allowed:
            break
        x = allowed[choice % len(allowed)]
        winning = reference.winning[reference.index(spec, current)]
        result = check_recovery_step(spec, strategy, reference, state, x)
        if winning:
            expected = strategy.step(normal_state, x)  # recovery is off: the ordinary strategy
            assert result.kind is StepKind.NORMAL and result.state == expected
        if result.state is None:
            break
        state = normal_state = result.state
