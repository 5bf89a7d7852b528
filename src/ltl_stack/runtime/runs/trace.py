"""Readable traces of a running controller: what it senses, what it does, and what changed.

ROS-free: the executor's ``~state`` messages are turned into ``TraceStep`` values by the ROS
adapter (``ltl_stack.ros.controller_trace``); this module formats them and counts goal cycles.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ltl_stack.synthesis.automaton import goal_text


@dataclass(frozen=True)
class TraceStep:
    """One controller state as published on ``~state``."""

    time: float
    state_id: int
    goal: int
    inputs: Mapping[str, bool]
    outputs: Mapping[str, bool]
    running: bool = True
    #: passed through while settling: its outputs were never published (``ControllerState.settling``)
    settling: bool = False

    def true_inputs(self) -> list[str]:
        return [name for name, value in self.inputs.items() if value]

    def true_outputs(self) -> list[str]:
        return [name for name, value in self.outputs.items() if value]

    def to_dict(self) -> dict:
        """The step as JSON; ``settling`` only when true (older records lack it)."""
        data = {"time": round(self.time, 3), "state": self.state_id, "goal": self.goal,
                "inputs": dict(self.inputs), "outputs": dict(self.outputs), "running": self.running}
        if self.settling:
            data["settling"] = True
        return data


def changes(previous: TraceStep | None, current: TraceStep) -> list[str]:
    """``+name`` for each proposition that became true, ``-name`` for each that became false."""
    if previous is None:
        return []
    result = []
    for now, before in ((current.inputs, previous.inputs), (current.outputs, previous.outputs)):
        for name, value in now.items():
            if value != before.get(name, False):
                result.append(f"+{name}" if value else f"-{name}")
    return result


def describe(previous: TraceStep | None, current: TraceStep, goals: int | None = None) -> str:
    """One line: time, state, goal, what is sensed, what is done, what changed."""
    goal = goal_text(current.goal, goals)
    sensing = ", ".join(current.true_inputs()) or "-"
    doing = ", ".join(current.true_outputs()) or "-"
    line = f"[{current.time:7.2f}s] state {current.state_id:<8d} goal {goal:<5s} sensing: {sensing:<32s} doing: {doing}"
    if not current.running:
        line += "  (paused)"
    if current.settling:
        line += "  (settling: not published)"
    delta = changes(previous, current)
    if delta:
        line += f"   [{' '.join(delta)}]"
    return line


@dataclass
class GoalCycles:
    """Counts completed cycles through all ``goals`` system goals from a stream of goal indices.

    The strategy pursues goals in order and wraps to 0 after the last; a cycle is complete each
    time the index wraps around (an index lower than the previous one).
    """

    goals: int
    completed: int = 0
    _last: int | None = field(default=None, repr=False)

    def update(self, goal: int) -> bool:
        """Record the current goal index; True when this completed a cycle."""
        wrapped = self._last is not None and goal < self._last
        self._last = goal
        if wrapped:
            self.completed += 1
        return wrapped
