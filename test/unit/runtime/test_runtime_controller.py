"""The ROS-free controller wrapper: ready handshake, event-driven stepping, pause, violation policy.

``ToyStrategy`` is a test double with the SymbolicStrategy interface (it is not a synthesizer): it
serves the spec ``out' <-> a'`` with the env assumption ``lock -> lock'`` so the wrapper's own
logic can be checked in isolation. The executor's integration tests use the real synthesizer.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.executor.controller import ALL_FALSE, HOLD, Controller
from ltl_stack.runtime.executor.explicit import AutomatonStrategy, violated_env_safety
from ltl_stack.spec.formula import Implies, Var
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.synthesis.errors import AssumptionViolation, NoInitialState

LOCK_CLAUSE = Clause(Implies(Var("lock"), Var("lock", True)), "lock -> lock'", "toy.slugsin", 7)


@dataclass(frozen=True)
class ToyState:
    inputs: dict = field(hash=False)
    outputs: dict = field(hash=False)
    goal: int = 0

    @property
    def id(self) -> int:
        return (self.inputs["a"] << 2) | (self.inputs["lock"] << 1) | self.goal


class ToyStrategy:
    inputs = ["a", "lock"]
    outputs = ["out", "busy"]

    def __init__(self):
        self.steps: list[dict] = []
        self.forbid_initial_out = None

    def _state(self, inputs, goal):
        return ToyState(dict(inputs), {"out": inputs["a"], "busy": inputs["lock"]}, goal)

    def initial_state(self, inputs=None, outputs=None):
        inputs = dict(inputs or {})
        if outputs and outputs.get("out") is not None and outputs["out"] != inputs.get("a", outputs["out"]):
            raise NoInitialState(f"no winning initial state with out={outputs['out']} and a={inputs.get('a')}")
        return self._state(inputs, 0)

    def step(self, state, inputs):
        self.steps.append(dict(inputs))
        if state.inputs["lock"] and not inputs["lock"]:
            raise AssumptionViolation([LOCK_CLAUSE], dict(inputs))
        return self._state(inputs, 1 - state.goal)


def make(**kwargs):
    # The toy strategy changes its goal on every step, so settling would always take settle_steps
    # steps; these tests are about one step per input change.
    kwargs.setdefault("settle_steps", 0)
    strategy = ToyStrategy()
    return strategy, Controller(strategy, **kwargs)


def test_nothing_steps_before_every_input_reported():
    strategy, ctl = make()
    assert ctl.missing_inputs() == ["a", "lock"]
    update = ctl.report("a", True)
    assert not update.stepped and update.state is None, update
    assert update.outputs == {"out": False, "busy": False}, update.outputs
    assert ctl.missing_inputs() == ["lock"]
    update = ctl.report("lock", False)
    assert update.started and update.stepped, update
    assert update.outputs == {"out": True, "busy": False}, update.outputs
    assert update.changed_outputs == {"out": True}, update.changed_outputs
    assert strategy.steps == []


def test_steps_only_when_the_input_valuation_changes():
    strategy, ctl = make()
    ctl.report_many({"a": False, "lock": False})
    for _ in range(3):
        assert not ctl.report("a", False).stepped
    update = ctl.report("a", True)
    assert update.stepped and update.changed_outputs == {"out": True}, update
    assert not ctl.report("a", True).stepped
    assert strategy.steps == [{"a": True, "lock": False}], strategy.steps
    assert ctl.state.goal == 1


def test_tick_steps_with_unchanged_readings():
    strategy, ctl = make()
    ctl.report_many({"a": False, "lock": False})
    assert ctl.tick().stepped
    assert strategy.steps == [{"a": False, "lock": False}], strategy.steps


def test_pause_drives_outputs_false_and_resume_steps_from_the_last_state():
    strategy, ctl = make()
    ctl.report_many({"a": True, "lock": False})
    update = ctl.set_running(False)
    assert update.outputs == {"out": False, "busy": False} and update.changed_outputs == {"out": False}, update
    assert not ctl.report("lock", True).stepped
    assert ctl.current_outputs() == {"out": False, "busy": False}
    update = ctl.set_running(True)
    assert update.stepped, update
    assert update.outputs == {"out": True, "busy": True}, update.outputs
    assert strategy.steps == [{"a": True, "lock": True}], strategy.steps


def test_started_paused_picks_the_initial_state_on_resume():
    _, ctl = make(running=False)
    assert not ctl.report_many({"a": True, "lock": False}).stepped
    update = ctl.set_running(True)
    assert update.started and update.outputs["out"] is True, update


@pytest.mark.parametrize("policy, held", [(HOLD, {"out": True, "busy": True}), (ALL_FALSE, {"out": False, "busy": False})])
def test_violation_keeps_the_state_applies_the_policy_and_recovers(policy, held):
    strategy, ctl = make(on_violation=policy)
    ctl.report_many({"a": True, "lock": True})
    before = ctl.state
    update = ctl.report("lock", False)
    assert update.violation is not None and update.violation.clauses == [LOCK_CLAUSE], update
    assert "toy.slugsin:7" in str(update.violation), str(update.violation)
    assert ctl.state is before and update.outputs == held, update
    # Still broken from the last safe state: tried again, still held.
    update = ctl.report("a", False)
    assert update.violation is not None and update.outputs == held, update
    # Admissible again: the controller continues by itself.
    update = ctl.report("lock", True)
    assert update.violation is None and update.stepped, update
    assert ctl.violation is None and update.outputs == {"out": False, "busy": True}, update.outputs


def test_recovery_hook_supplies_the_state_to_continue_from():
    calls = []

    def recover(controller, violation):
        calls.append(violation.clauses)
        return controller.strategy.initial_state(inputs=controller.readings)

    _, ctl = make(recovery=recover)
    ctl.report_many({"a": False, "lock": True})
    update = ctl.report("lock", False)
    assert calls == [[LOCK_CLAUSE]], calls
    assert update.stepped and ctl.violation is None and ctl.state.inputs == {"a": False, "lock": False}, update


def test_init_props_constrain_outputs_and_seed_inputs_true_and_false():
    _, ctl = make(init_props={"lock": False, "out": False})
    assert ctl.missing_inputs() == ["a"]
    update = ctl.report("a", True)
    assert update.state is None and "out=False and a=True" in update.error, update
    update = ctl.report("a", False)
    assert update.started and update.state.inputs == {"a": False, "lock": False}, update
    update = ctl.report("lock", True)  # a real reading replaces the seeded one
    assert update.stepped and update.outputs["busy"] is True, update


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="unknown proposition.*nope"):
        make(init_props={"nope": True})
    with pytest.raises(ValueError, match="on_violation"):
        make(on_violation="explode")
    _, ctl = make()
    with pytest.raises(ValueError, match="'out' is not an input"):
        ctl.report("out", True)


EVENTS = st.one_of(
    st.tuples(st.just("a"), st.booleans()),
    st.tuples(st.just("lock"), st.booleans()),
    st.tuples(st.just("run"), st.booleans()),
    st.tuples(st.just("tick"), st.just(True)),
)


@given(st.lists(EVENTS, max_size=40), st.sampled_from([HOLD, ALL_FALSE]))
def test_outputs_always_follow_the_policy(events, policy):
    strategy, ctl = make(on_violation=policy)
    for kind, value in events:
        steps_before = len(strategy.steps)
        readings_before = ctl.readings
        if kind == "run":
            update = ctl.set_running(value)
        elif kind == "tick":
            update = ctl.tick()
        else:
            update = ctl.report(kind, value)
        if not ctl.running or ctl.state is None:
            assert update.outputs == {"out": False, "busy": False}, update
        elif ctl.violation is not None:
            expect = {"out": False, "busy": False} if policy == ALL_FALSE else ctl.state.outputs
            assert update.outputs == expect, update
        else:
            assert update.outputs == ctl.state.outputs, update
        # A reading that changes nothing never reaches the strategy.
        if kind in ("a", "lock") and ctl.readings == readings_before:
            assert len(strategy.steps) == steps_before, (events, strategy.steps)
        assert ctl.outputs_published() == update.outputs


# --- AutomatonStrategy: a saved explicit automaton behind the same interface ---------------------

@dataclass
class S:
    id: int
    inputs: dict
    outputs: dict
    goal: int
    successors: list


@dataclass
class Auto:
    states: list
    initial: list


def lock_automaton():
    states = [S(0, {"lock": False}, {"busy": False}, 0, [0, 1]), S(1, {"lock": True}, {"busy": True}, 0, [1])]
    return Auto(states, [0, 1])


def test_automaton_strategy_steps_along_successors_and_names_violated_clauses():
    spec = Spec(inputs=["lock"], outputs=["busy"], env_safety=[LOCK_CLAUSE], source="toy.slugsin")
    strategy = AutomatonStrategy(lock_automaton(), spec)
    state = strategy.initial_state(inputs={"lock": True})
    assert state.id == 1, state
    assert strategy.initial_state(inputs={"lock": False}, outputs={"busy": False}).id == 0
    with pytest.raises(NoInitialState, match="lock !busy"):
        strategy.initial_state(inputs={"lock": True}, outputs={"busy": False})
    assert strategy.step(strategy.initial_state(inputs={"lock": False}), {"lock": True}).id == 1
    with pytest.raises(AssumptionViolation) as info:
        strategy.step(state, {"lock": False})
    assert info.value.clauses == [LOCK_CLAUSE], info.value.clauses
    ctl = Controller(strategy)
    assert ctl.report("lock", False).outputs == {"busy": False}


def test_violated_env_safety_evaluates_each_clause():
    spec = Spec(inputs=["lock"], outputs=[], env_safety=[LOCK_CLAUSE,
                                                         Clause(Var("busy", True), "busy'", "x", 1)])
    assert violated_env_safety(spec, {"lock": True}, {"lock": False}) == [LOCK_CLAUSE]
    assert violated_env_safety(spec, {"lock": True}, {"lock": True}) == []


# --- settling: stepping with unchanged readings until the state stops changing ------------------

def chain_automaton():
    """go=1 leads through states 1 -> 2 -> 3 with the same input; 3 loops. Outputs say where."""
    where = lambda k: {"at1": k == 1, "at2": k == 2, "at3": k == 3}  # noqa: E731
    states = [S(0, {"go": False}, where(0), 0, [0, 1]), S(1, {"go": True}, where(1), 0, [2]),
              S(2, {"go": True}, where(2), 0, [3]), S(3, {"go": True}, where(3), 0, [3])]
    return Auto(states, [0])


@pytest.mark.parametrize("settle_steps,expected", [(0, 1), (1, 2), (2, 3), (16, 3)])
def test_settling_steps_with_unchanged_readings_until_the_state_repeats(settle_steps, expected):
    ctl = Controller(AutomatonStrategy(chain_automaton()), settle_steps=settle_steps)
    ctl.report("go", False)
    update = ctl.report("go", True)
    assert update.state.id == expected, update.state
    assert update.outputs == {"at1": expected == 1, "at2": expected == 2, "at3": expected == 3}, update.outputs


def test_settling_stops_where_the_environment_may_not_stay_still():
    # From state 1 the only successor needs go=False: staying with go=True is not an allowed move.
    states = [S(0, {"go": False}, {"busy": False}, 0, [1]), S(1, {"go": True}, {"busy": True}, 0, [0])]
    ctl = Controller(AutomatonStrategy(Auto(states, [0])), settle_steps=16)
    ctl.report("go", False)
    update = ctl.report("go", True)
    assert update.state.id == 1 and update.violation is None, update


def test_settling_also_follows_the_initial_state():
    ctl = Controller(AutomatonStrategy(Auto(chain_automaton().states, [1])), settle_steps=16)
    update = ctl.report("go", True)
    assert update.started and update.state.id == 3, update.state


def test_record_gathers_readings_and_advance_steps_once_with_all_of_them():
    """The executor's ``--input-window``: readings that arrive together (leaving one region, entering
    the next) are recorded without stepping, then one step sees them all."""
    strategy, controller = make()
    controller.report_many({"a": False, "lock": True})
    strategy.steps.clear()
    assert controller.record({"a": True}) is True and controller.record({"lock": False}) is True
    assert strategy.steps == [], "recording never steps"
    assert controller.record({"a": True}) is False, "an unchanged reading is no change"
    update = controller.advance()
    assert strategy.steps == [{"a": True, "lock": False}] and update.violation is not None
    with pytest.raises(ValueError, match="'nope' is not an input"):
        controller.record({"nope": True})
