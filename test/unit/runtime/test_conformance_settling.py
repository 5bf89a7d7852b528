"""check_run is right on real runs: the states the controller settles through are in the record
(``Update.passed``, which the executor publishes on ``~state`` before the state it reaches), so every
goal the strategy met is counted, and any stretch of a correct recording checks clean (ROS-free, with
the real synthesizer)."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.runs.conformance import check_run
from ltl_stack.runtime.runs.trace import TraceStep
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize

#: a patrol whose moves need no input change: every goal is met while the controller settles
SPEC_TEXT = """[INPUT]
door
[OUTPUT]
a
b
c
[SYS_INIT]
!a & !b & !c
[SYS_TRANS]
!(a' & b') & !(a' & c') & !(b' & c')
[SYS_LIVENESS]
a
b
c
"""


@pytest.fixture(scope="module")
def patrol(tmp_path_factory):
    path = tmp_path_factory.mktemp("settling") / "patrol.structuredslugs"
    path.write_text(SPEC_TEXT)
    spec = load_spec(path)
    return spec, synthesize(spec).strategy


def record(strategy, doors: list[bool], settle_steps: int) -> tuple[list[TraceStep], list[dict]]:
    """What the executor publishes on ~state for the readings ``doors``: each update's passed states,
    then the state reached; and, beside it, every state the strategy returned (the ground truth)."""
    taken: list[dict] = []

    class Watched:
        inputs, outputs = strategy.inputs, strategy.outputs

        def initial_state(self, **kwargs):
            state = strategy.initial_state(**kwargs)
            taken.append({**state.inputs, **state.outputs})
            return state

        def step(self, state, inputs):
            following = strategy.step(state, inputs)
            if following.id != state.id:
                taken.append({**following.inputs, **following.outputs})
            return following

    controller = Controller(Watched(), settle_steps=settle_steps)
    steps: list[TraceStep] = []
    for tick, door in enumerate(doors):
        update = controller.report("door", door)
        for state in [*update.passed, update.state] if update.stepped else []:
            steps.append(TraceStep(float(tick), state.id, state.goal, {"door": bool(state.inputs["door"])},
                                   {p: bool(state.outputs[p]) for p in ("a", "b", "c")}))
    return steps, taken


def met(spec, states: list[dict]) -> list[int]:
    from ltl_stack.spec.formula import evaluate
    return [sum(bool(evaluate(goal.formula, s, None)) for s in states) for goal in spec.sys_liveness]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.booleans(), min_size=1, max_size=12), st.integers(1, 6), st.data())
def test_every_goal_the_strategy_met_is_counted_and_every_cut_checks_clean(patrol, doors, settle_steps, data):
    spec, strategy = patrol
    steps, taken = record(strategy, doors, settle_steps)
    report = check_run(spec, steps, from_start=True)
    assert report.ok, [v.describe() for v in report.violations]
    assert [count for _, count in report.goals] == met(spec, taken), (report.goals, taken)
    if settle_steps >= 3:  # settling alone goes round a, b, c
        assert all(count >= 1 for _, count in report.goals), report.goals
    cut = data.draw(st.integers(0, len(steps) - 1), label="cut")
    later = check_run(spec, steps[cut:])  # a recording started by hand later
    assert later.ok and later.steps == len(steps) - cut, [v.describe() for v in later.violations]
