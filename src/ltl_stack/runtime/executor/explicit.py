"""Stepping a saved explicit automaton through the same interface as the symbolic strategy.

``controller_executor --strategy FILE`` loads an ``ltl_stack.synthesis.Automaton`` (JSON), which
``AutomatonStrategy`` checks against the spec (``synthesis.automaton_check``), and runs it:
``initial_state`` picks the first initial state that matches the given partial valuation, ``step`` the first successor whose inputs equal the new readings. When no successor
matches, the readings broke the environment assumptions; with the spec at hand ``violated_env_safety``
names the env-safety clauses they break.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ltl_stack.spec.formula import evaluate
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.synthesis.automaton import Automaton
from ltl_stack.synthesis.automaton_check import check_automaton
from ltl_stack.synthesis.errors import AssumptionViolation, NoInitialState


@dataclass(frozen=True)
class ExplicitState:
    """A state of an explicit automaton: its id, goal index and valuation."""

    id: int
    goal: int
    inputs: dict[str, bool] = field(hash=False)
    outputs: dict[str, bool] = field(hash=False)


def violated_env_safety(spec: Spec, current: Mapping[str, bool], next_inputs: Mapping[str, bool]) -> list[Clause]:
    """The env-safety clauses of ``spec`` that the move from ``current`` (inputs and outputs) to
    ``next_inputs`` breaks. A clause that cannot be evaluated (it mentions a next output) is skipped."""
    broken = []
    for clause in spec.env_safety:
        try:
            holds = evaluate(clause.formula, dict(current), dict(next_inputs))
        except KeyError:
            continue
        if not holds:
            broken.append(clause)
    return broken


class AutomatonStrategy:
    """An explicit automaton (``Automaton.states``, ``Automaton.initial``) as a steppable strategy."""

    def __init__(self, automaton: Any, spec: Spec | None = None) -> None:
        """With ``spec``, an automaton loaded from a file (``Automaton.path``) is first checked against
        it (``check_automaton``: names, ids, init, safety on every edge; ``StrategyFileError``)."""
        if spec is not None and isinstance(automaton, Automaton) and automaton.path:
            check_automaton(automaton, spec)
        states = automaton.states.values() if isinstance(automaton.states, Mapping) else automaton.states
        self._states = {int(s.id): ExplicitState(int(s.id), int(getattr(s, "goal", 0)), dict(s.inputs), dict(s.outputs))
                        for s in states}
        self._successors = {int(s.id): [int(t) for t in s.successors] for s in states}
        initial = automaton.initial
        self._initial = [int(initial)] if isinstance(initial, int) else [int(i) for i in _iterable(initial)]
        self.spec = spec
        first = next(iter(self._states.values()), None)
        self.inputs = list(spec.inputs if spec else getattr(automaton, "inputs", None) or (first.inputs if first else []))
        self.outputs = list(spec.outputs if spec else getattr(automaton, "outputs", None) or (first.outputs if first else []))

    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> ExplicitState:
        for sid in self._initial:
            state = self._states[sid]
            if _matches(state.inputs, inputs) and _matches(state.outputs, outputs):
                return state
        want = {**(inputs or {}), **(outputs or {})}
        shown = " ".join(p if v else f"!{p}" for p, v in want.items()) or "(anything)"
        raise NoInitialState(f"no initial state of the automaton ({len(self._initial)} of them) matches {shown}")

    def step(self, state: ExplicitState, inputs: Mapping[str, bool]) -> ExplicitState:
        for sid in self._successors.get(state.id, []):
            successor = self._states[sid]
            if _matches(successor.inputs, inputs):
                return successor
        clauses = []
        if self.spec is not None:
            clauses = violated_env_safety(self.spec, {**state.inputs, **state.outputs}, inputs)
        raise AssumptionViolation(clauses, dict(inputs))


def _matches(values: Mapping[str, bool], wanted: Mapping[str, bool] | None) -> bool:
    return all(bool(values.get(p)) == bool(v) for p, v in (wanted or {}).items())


def _iterable(value: Any) -> Iterable[Any]:
    return value if isinstance(value, Iterable) else [value]
