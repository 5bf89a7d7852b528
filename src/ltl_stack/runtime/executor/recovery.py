"""Recovery after an environment-assumption violation for a running controller (thesis §4.6).

Without recovery the ``Controller`` holds its last state after a violation and retries every later
input change from it, which stays inadmissible forever when the violation changed the world (the
robot drifted into a region after leaving it). ``RecoveringStrategy`` wraps the strategy the
executor runs (``primary``: the explicit ``AutomatonStrategy`` or the ``SymbolicStrategy``) and
gives the Controller a ``recovery`` hook: on a violation it takes one recovery-mode step of the
symbolic strategy (``SymbolicStrategy.step_result``: into W, towards W, or only safe; thesis §4.6.1,
§4.6.2, Alg. 1 lines 19-25) from the current state with the current readings.

States: ``~state`` keeps the ids of ``synthesize --strategy-json`` wherever it can. A move taken
by the symbolic strategy (the recovery step, and every step from a symbolic state) lands, when it
can, on an automaton state with the new inputs: the symbolic pick itself, else one the strategy's
relation allows, else one the move reaches keeping the system safety (``_map_back``). The export
re-uses states, so the symbolic pick itself is often not one of them. Only when no such move
exists the symbolic ``State`` is kept, with its symbolic ``id`` (valuation bits and goal), and the
next step tries again.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ltl_stack.runtime.executor.explicit import AutomatonStrategy, ExplicitState
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
        self._index: dict[tuple, list[ExplicitState]] | None = None

    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> Any:
        return self.primary.initial_state(inputs=inputs, outputs=outputs)

    def step(self, state: Any, inputs: Mapping[str, bool]) -> Any:
        """The primary's step from its own states; from a symbolic state reached by recovery the
        symbolic strategy's normal step (``AssumptionViolation`` also when that state has no normal
        move, i.e. it is outside W: the Controller then recovers again)."""
        if isinstance(state, State):
            try:
                return self._map_back(state, inputs, self.symbolic.step(state, inputs))
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
        return self._map_back(here, controller.readings, self.last.state)

    def _map_back(self, source: State, inputs: Mapping[str, bool], picked: State) -> Any:
        """The automaton's state for the symbolic move ``source`` -> ``picked``: ``picked`` itself
        when the automaton has it; else, among the automaton's states with the same inputs (lowest
        id first), one the strategy's relation allows, else one the move reaches keeping the system
        safety (every automaton state is winning, and the automaton is a strategy from each of its
        states, whatever its goal number); else ``picked`` (symbolic)."""
        if not isinstance(self.primary, AutomatonStrategy):
            return picked
        if self._index is None:
            self._index = {}
            for s in sorted(self.primary._states.values(), key=lambda s: s.id):
                self._index.setdefault(self._bits(s.inputs), []).append(s)
        candidates = self._index.get(self._bits(picked.inputs), [])
        for s in candidates:
            if s.goal == picked.goal and s.outputs == picked.outputs:
                return s
        for check in (self.symbolic.allows, self.symbolic.keeps_safety):
            for s in candidates:
                if check(source, picked.inputs, s.outputs):
                    return s
        return picked

    def _bits(self, inputs: Mapping[str, bool]) -> tuple:
        return tuple(bool(inputs[p]) for p in self.inputs)


__all__ = ["RecoveringStrategy"]
