"""Conformance of a recorded run to its spec (``runtime.runs.conformance``, what check_run reports): a run read
as a play of the GR(1) game (ROS-free)."""
from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.runs.conformance import check_run, distinct_steps
from ltl_stack.runtime.runs.trace import TraceStep
from ltl_stack.spec import load_spec

SPEC_TEXT = """[INPUT]
a
[OUTPUT]
x
[ENV_INIT]
!a
[SYS_INIT]
!x
[ENV_TRANS]
a -> a'
[SYS_TRANS]
x' <-> a'
[SYS_LIVENESS]
x
"""


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    path = tmp_path_factory.mktemp("run_check") / "latch.structuredslugs"
    path.write_text(SPEC_TEXT)
    return load_spec(path)


def run(*values: tuple[bool, bool], running: bool = True) -> list[TraceStep]:
    return [TraceStep(time=float(i), state_id=i, goal=0, inputs={"a": a}, outputs={"x": x}, running=running)
            for i, (a, x) in enumerate(values)]


def test_a_good_run_holds_everything_and_counts_the_goal(spec):
    report = check_run(spec, run((False, False), (True, True), (True, True)), from_start=True)
    assert report.ok and report.transitions == 2 and report.initial_checked
    assert [count for _, count in report.goals] == [2]
    assert report.goals[0][0].endswith("latch.structuredslugs:14: x")


def test_broken_assumption_and_guarantee_name_the_step_and_clause(spec):
    report = check_run(spec, run((False, False), (True, True), (False, True)))
    assert [(v.kind, v.step, v.clause.split(": ", 1)[1]) for v in report.violations] == [
        ("assumption", 1, "a -> a'"), ("guarantee", 1, "x' <-> a'")]
    assert report.violations[0].describe().startswith("step 1 -> 2 (t=2.00s): assumption broken: ")
    assert report.violations[0].clause.split(": ")[0].endswith("latch.structuredslugs:10")


def test_initial_conditions_only_from_the_start(spec):
    late = run((True, True), (True, True))
    assert check_run(spec, late).ok
    report = check_run(spec, late, from_start=True)
    assert [(v.section, v.step) for v in report.violations] == [("env_init", 0), ("sys_init", 0)]


def test_paused_states_take_no_part_in_transitions(spec):
    paused = run((True, False), running=False)
    steps = [*run((False, False)), *[TraceStep(1.0, 9, 0, p.inputs, p.outputs, False) for p in paused]]
    report = check_run(spec, steps)
    assert report.ok and report.transitions == 0


def test_a_run_of_another_spec_is_refused(spec):
    with pytest.raises(ValueError, match="state 0 of the run has no value for x"):
        check_run(spec, [TraceStep(0.0, 1, 0, {"a": False}, {"y": True})])


@given(st.integers(1, 8), st.integers(1, 8), st.data())
def test_one_flipped_output_is_reported_at_exactly_its_step(spec, before, after, data):
    """A run that keeps every clause, with x flipped in one later state: the guarantee breaks on the
    transitions into (and, unless it is the last, out of) that state, nothing else does."""
    values = [(False, False)] * before + [(True, True)] * after
    k = data.draw(st.integers(1, len(values) - 1))
    flipped = [(a, (not x) if i == k else x) for i, (a, x) in enumerate(values)]
    steps = distinct_steps(run(*flipped))
    assert len(steps) == len(flipped)  # state ids differ: nothing merged
    report = check_run(spec, steps)
    assert {(v.kind, v.step) for v in report.violations} == {("guarantee", k - 1)}
