"""Recovery of the running controller (thesis §4.6) over the explicit automaton, without ROS.

The probe: the environment promises the door stays open (``door'``) and the robot must stop when it
sees a person (``person' -> stop'``). The readings person=1 door=0 break the promise. Without
recovery the controller holds its last outputs (stop=false while a person is there) and every later
reading is tried from that state again; with recovery it takes a recovery-mode step that keeps
``person' -> stop'``.
"""
from __future__ import annotations

import pytest

from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.executor.explicit import AutomatonStrategy, ExplicitState
from ltl_stack.runtime.executor.recovery import RecoveringStrategy
from ltl_stack.spec.structured import parse_structured
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.recovery import StepKind
from ltl_stack.synthesis.state import State

PROBE = """\
[INPUT]
person
door

[OUTPUT]
stop

[ENV_INIT]
door

[ENV_TRANS]
door'

[SYS_TRANS]
person' -> stop'
"""


@pytest.fixture(scope="module")
def probe():
    spec = parse_structured(PROBE, "probe.structuredslugs")
    result = synthesize(spec)
    assert result.realizable
    symbolic = result.strategy
    return spec, symbolic, AutomatonStrategy(symbolic.explicit(), spec)


def started(strategy, **kwargs) -> Controller:
    ctl = Controller(strategy, **kwargs)
    update = ctl.report_many({"person": False, "door": True})
    assert update.started and update.outputs == {"stop": False}, update
    return ctl


def test_without_recovery_the_controller_holds_stop_false(probe):
    _, _, explicit = probe
    ctl = started(explicit)
    update = ctl.report_many({"person": True, "door": False})
    assert update.violation is not None and not update.stepped and not update.recovered, update
    assert [c.line for c in update.violation.clauses] == [12], update.violation.clauses
    assert update.outputs == {"stop": False} and ctl.violation is not None


def test_with_recovery_the_controller_steps_and_stops(probe):
    _, symbolic, explicit = probe
    wrapper = RecoveringStrategy(explicit, symbolic)
    ctl = started(wrapper, recovery=wrapper.recover)
    assert isinstance(ctl.state, ExplicitState)
    update = ctl.report_many({"person": True, "door": False})
    assert update.stepped and update.recovered and update.violation is not None, update
    assert [c.line for c in update.violation.clauses] == [12], update.violation.clauses
    assert update.outputs == {"stop": True}, update
    assert ctl.violation is None and ctl.current_outputs() == {"stop": True}
    assert wrapper.last.kind is StepKind.RECOVER_TO_W and [c.line for c in wrapper.last.violated] == [12]
    # door=0 never happens after the start (ENV_INIT door, ENV_TRANS door'): no explicit state has it,
    # so the controller is in a symbolic state, with the symbolic strategy's id.
    assert isinstance(ctl.state, State) and ctl.state.inputs == {"person": True, "door": False}
    # Admissible readings again: the step goes on from the symbolic state and lands on explicit ids.
    update = ctl.report_many({"person": False, "door": True})
    assert update.stepped and not update.recovered and update.violation is None, update
    assert isinstance(ctl.state, ExplicitState) and ctl.state.inputs == {"person": False, "door": True}
    update = ctl.report_many({"person": True, "door": True})
    assert isinstance(ctl.state, ExplicitState) and update.outputs == {"stop": True}, update


def test_recovered_state_maps_to_the_explicit_state_with_the_same_goal_and_valuation(probe):
    _, symbolic, explicit = probe
    wrapper = RecoveringStrategy(explicit, symbolic)
    for state in explicit._states.values():
        twin = State(dict(state.inputs), dict(state.outputs), state.goal)
        assert wrapper._map_back(twin, twin.inputs, twin) is state


def test_recovery_over_the_symbolic_strategy_keeps_symbolic_states(probe):
    _, symbolic, _ = probe
    wrapper = RecoveringStrategy(symbolic, symbolic)
    ctl = started(wrapper, recovery=wrapper.recover)
    update = ctl.report_many({"person": True, "door": False})
    assert update.recovered and update.outputs == {"stop": True} and isinstance(ctl.state, State), update


def test_after_a_recovery_steps_land_on_the_exported_automaton(tmp_path):
    """Example 8's export re-uses states, so the symbolic strategy's own pick from a state is often
    not in it; from a symbolic state the wrapper takes a move into the automaton instead. For every
    state and admissible input the move it returns keeps the system safety, and it is an automaton
    state whenever the automaton has an edge there."""
    from pathlib import Path

    from ltl_stack.spec import load_spec

    spec = load_spec(Path(__file__).resolve().parents[3] / "config" / "clean_and_patrol" / "clean_and_patrol.structuredslugs")
    symbolic = synthesize(spec).strategy
    explicit = AutomatonStrategy(symbolic.explicit(), spec)
    wrapper = RecoveringStrategy(explicit, symbolic)
    game = symbolic.game
    picked_elsewhere = 0
    for state in sorted(explicit._states.values(), key=lambda s: s.id)[:40]:
        twin = State(dict(state.inputs), dict(state.outputs), state.goal)
        for inputs in symbolic.admissible_inputs(twin):
            try:
                own = explicit.step(state, inputs)
            except Exception:
                own = None
            picked = symbolic.step(twin, inputs)
            moved = wrapper.step(twin, inputs)
            assert game.bdd.let(game.assignment(twin.valuation, {**inputs, **moved.outputs}),
                                game.sys_trans) == game.bdd.true
            if own is not None:
                assert isinstance(moved, ExplicitState), (state.id, inputs)
                picked_elsewhere += (picked.goal, picked.outputs) != (moved.goal, moved.outputs)
    assert picked_elsewhere > 0  # the case this guards: the symbolic pick is not the exported one
