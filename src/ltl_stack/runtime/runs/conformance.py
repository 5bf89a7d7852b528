"""Conformance: whether a recorded run kept its specification, ROS-free (the post-mortem of a field
test; the ``check_run`` tool, ``ros.check_run``, reads the bag and prints this report).

A run is the controller's sequence of states (``TraceStep``: inputs and outputs, as the executor
published them on ``~state``). Read as a play of the GR(1) game (thesis §3.2), each state ``v_i`` and
its successor ``v_{i+1}`` must satisfy the environment's safety assumptions (ENV_TRANS, evaluated on
``v_i`` and ``v_{i+1}``) and the system's safety guarantees (SYS_TRANS); the first state the initial
conditions (only when the recording holds the controller's first state: a bag started by hand
usually begins later); and each system goal (SYS_LIVENESS) is counted at every step where it holds. A broken
assumption excuses the controller (the guarantee is an implication), so both are reported with the
step, the time and the clause (``file:line: text``). Paused states (every output forced false) are
left out of the transitions they take part in.
"""
from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from ltl_stack.runtime.runs.trace import TraceStep
from ltl_stack.spec.formula import evaluate
from ltl_stack.spec.model import Clause, Spec


@dataclass(frozen=True)
class Violation:
    """A clause that did not hold at step ``step`` (the transition from ``step`` to ``step + 1``, or the
    first state for an initial condition)."""

    kind: str  # "assumption" or "guarantee"
    section: str  # env_init, env_safety, sys_init, sys_safety
    step: int
    time: float
    clause: str  # file:line: text

    def to_dict(self) -> dict:
        return {"kind": self.kind, "section": self.section, "step": self.step, "time": round(self.time, 3),
                "clause": self.clause}

    def describe(self) -> str:
        what = "assumption" if self.kind == "assumption" else "guarantee"
        where = "initially" if self.section.endswith("init") else f"step {self.step} -> {self.step + 1}"
        return f"{where} (t={self.time:.2f}s): {what} broken: {self.clause}"


@dataclass
class RunReport:
    """What ``check_run`` found: violations in order, how often each goal held, steps checked."""

    steps: int
    transitions: int
    initial_checked: bool = False
    violations: list[Violation] = field(default_factory=list)
    goals: list[tuple[str, int]] = field(default_factory=list)

    @property
    def assumptions_held(self) -> bool:
        return not any(v.kind == "assumption" for v in self.violations)

    @property
    def guarantees_held(self) -> bool:
        return not any(v.kind == "guarantee" for v in self.violations)

    @property
    def ok(self) -> bool:
        return not self.violations

    def to_dict(self) -> dict:
        return {"steps": self.steps, "transitions": self.transitions, "initial_checked": self.initial_checked,
                "ok": self.ok,
                "assumptions_held": self.assumptions_held, "guarantees_held": self.guarantees_held,
                "violations": [v.to_dict() for v in self.violations],
                "goals": [{"goal": text, "reached": count} for text, count in self.goals]}

    def lines(self) -> list[str]:
        """The readable report, one line each."""
        out = [f"{self.steps} states, {self.transitions} transitions checked; initial conditions "
               + ("checked" if self.initial_checked else "not checked (--from-start checks them)")]
        out += [v.describe() for v in self.violations]
        out.append("environment assumptions: " + ("held" if self.assumptions_held else "broken"))
        out.append("system guarantees: " + ("held" if self.guarantees_held else "broken"))
        out += [f"goal {i + 1} reached {count} time(s): {text}" for i, (text, count) in enumerate(self.goals)]
        return out


def clause_name(clause: Clause) -> str:
    return f"{clause.location}: {clause.text}" if clause.text else clause.location


def distinct_steps(steps: Iterable[TraceStep]) -> list[TraceStep]:
    """The steps with a new state: ``~state`` is also republished unchanged."""
    return list(iter_distinct(steps))


def iter_distinct(steps: Iterable[TraceStep]) -> Iterator[TraceStep]:
    """``distinct_steps`` one at a time (a long recording is never held in memory)."""
    last = None
    for step in steps:
        key = _key(step)
        if key != last:
            last = key
            yield step


def _key(step: TraceStep) -> tuple:
    return (step.state_id, step.running, tuple(sorted(step.inputs.items())), tuple(sorted(step.outputs.items())))


def _holds(clause: Clause, current: dict[str, bool], nxt: dict[str, bool] | None) -> bool | None:
    try:
        return evaluate(clause.formula, current, nxt)
    except KeyError:
        return None  # mentions a proposition the run does not carry (or a next value at the last step)


def check_run(spec: Spec, steps: Iterable[TraceStep], from_start: bool = False) -> RunReport:
    """Check the run ``steps`` against ``spec`` (see the module doc); the initial conditions only with
    ``from_start``. One pass over the steps, holding two at a time. ValueError when a step lacks a
    proposition of the spec (the recording belongs to another controller)."""
    names = set(spec.propositions)
    report = RunReport(steps=0, transitions=0)
    counts = [0] * len(spec.sys_liveness)
    previous: TraceStep | None = None
    for step in iter_distinct(steps):
        missing = names - set(step.inputs) - set(step.outputs)
        if missing:
            raise ValueError(f"state {report.steps} of the run has no value for {', '.join(sorted(missing))}: "
                             "is it a run of this spec?")
        if previous is None and from_start:
            report.initial_checked = True
            first = {**step.inputs, **step.outputs}
            for section, kind in (("env_init", "assumption"), ("sys_init", "guarantee")):
                for clause in spec.section(section):
                    if _holds(clause, first, first) is False:
                        report.violations.append(Violation(kind, section, 0, step.time, clause_name(clause)))
        if previous is not None:
            _check_step(spec, report, counts, report.steps - 1, previous, step)
        previous = step
        report.steps += 1
    if previous is not None:
        _check_step(spec, report, counts, report.steps - 1, previous, None)
    report.goals = [(clause_name(c), counts[i]) for i, c in enumerate(spec.sys_liveness)]
    return report


def _check_step(spec: Spec, report: RunReport, counts: list[int], index: int, step: TraceStep,
                following: TraceStep | None) -> None:
    """The transition from ``step`` (number ``index``) to ``following`` (both running), and the goals
    that hold at ``step``."""
    current = {**step.inputs, **step.outputs}
    nxt = None
    if following is not None and step.running and following.running:
        nxt = {**following.inputs, **following.outputs}
        report.transitions += 1
        for section, kind in (("env_safety", "assumption"), ("sys_safety", "guarantee")):
            for clause in spec.section(section):
                if _holds(clause, current, nxt) is False:
                    report.violations.append(Violation(kind, section, index, following.time, clause_name(clause)))
    for goal, clause in enumerate(spec.sys_liveness):
        if step.running and _holds(clause, current, nxt):
            counts[goal] += 1
