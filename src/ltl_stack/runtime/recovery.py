"""Recovery after an environment-assumption violation for a running controller (thesis §4.6).

Without recovery the ``Controller`` holds its last state after a violation and retries every later
input change from it, which stays inadmissible forever when the violation changed the world (the
robot drifted into a region after leaving it). ``RecoveringStrategy`` wraps the strategy the
executor runs (``primary``: the explicit ``AutomatonStrategy`` or the ``SymbolicStrategy``) and
gives the Controller a ``recovery`` hook: on a violation it takes one recovery-mode step of the
symbolic strategy (``SymbolicStrategy.step_result``: into W, towards W, or only safe; thesis §4.6.1,
§4.6.2, Alg. 1 lines 19-25) from the current state with the current readings.

States: a recovered state is mapped back to the explicit state with the same goal and valuation
when the automaton has one (the explicit extraction numbers goals as the symbolic strategy does,
``synthesis.explicit``), so ``~state`` keeps the ids of ``synthesize --strategy-json``. Otherwise the
symbolic ``State`` is used, and its ``id`` is the symbolic one (valuation bits and goal), not an
export's; stepping from it uses the symbolic strategy until a step lands on an explicit state again.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ltl_stack.runtime.explicit import AutomatonStrategy, ExplicitState
from ltl_stack.synthesis.errors import AssumptionViolation, SynthesisError
from ltl_stack.synthesis.recovery import StepResult
from ltl_stack.synthesis.state import State
from ltl_stack.synthesis.strategy import SymbolicStrategy


class RecoveringStrategy:
    """``primary`` stepped as usual; ``recover`` is the Controller's ``recovery=`` hook."""

    def __init__(self, primary: Any, symbolic: SymbolicStrategy) -> None:
        self.primary = primary
        self.symbolic = symbolic
        self.inputs = list(primary.inputs)
        self.outputs = list(primary.outputs)
        #: the StepResult of the last recovery (kind, broken env clauses, unkeepable sys clauses)
        self.last: StepResult | None = None
        self._index: dict[tuple, ExplicitState] | None = None

    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> Any:
        return self.primary.initial_state(inputs=inputs, outputs=outputs)

    def step(self, state: Any, inputs: Mapping[str, bool]) -> Any:
        """The primary's step from its own states; from a symbolic state reached by recovery the
        symbolic strategy's normal step (``AssumptionViolation`` also when that state has no normal
        move, i.e. it is outside W: the Controller then recovers again)."""
        if isinstance(state, State):
            try:
                return self._map_back(self.symbolic.step(state, inputs))
            except AssumptionViolation:
                raise
            except SynthesisError:
                raise AssumptionViolation([], dict(inputs)) from None
        return self.primary.step(state, inputs)

    def recover(self, controller: Any, violation: AssumptionViolation) -> Any:
        """One recovery-mode step from ``controller.state`` with ``controller.readings``; None when
        no move keeps the system safety (UNSAFE: the Controller applies its violation policy)."""
        cur = controller.state
        here = State(dict(cur.inputs), dict(cur.outputs), cur.goal)
        self.last = self.symbolic.step_result(here, controller.readings)
        if self.last.state is None:
            return None
        return self._map_back(self.last.state)

    def _map_back(self, state: State) -> Any:
        if not isinstance(self.primary, AutomatonStrategy):
            return state
        if self._index is None:
            self._index = {self._key(s.goal, s.inputs, s.outputs): s for s in self.primary._states.values()}
        return self._index.get(self._key(state.goal, state.inputs, state.outputs), state)

    def _key(self, goal: int, inputs: Mapping[str, bool], outputs: Mapping[str, bool]) -> tuple:
        return (goal, tuple(bool(inputs[p]) for p in self.inputs), tuple(bool(outputs[p]) for p in self.outputs))


__all__ = ["RecoveringStrategy"]
