"""Check a recorded run against its specification, ROS-free: the post-mortem of a field test.

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

from collections.abc import Sequence
from dataclasses import dataclass, field

from ltl_stack.runtime.trace import TraceStep
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


def distinct_steps(steps: Sequence[TraceStep]) -> list[TraceStep]:
    """The steps with a new state: ``~state`` is also republished unchanged."""
    out: list[TraceStep] = []
    for step in steps:
        if out and _key(out[-1]) == _key(step):
            continue
        out.append(step)
    return out


def _key(step: TraceStep) -> tuple:
    return (step.state_id, step.running, tuple(sorted(step.inputs.items())), tuple(sorted(step.outputs.items())))


def _holds(clause: Clause, current: dict[str, bool], nxt: dict[str, bool] | None) -> bool | None:
    try:
        return evaluate(clause.formula, current, nxt)
    except KeyError:
        return None  # mentions a proposition the run does not carry (or a next value at the last step)


def check_run(spec: Spec, steps: Sequence[TraceStep], from_start: bool = False) -> RunReport:
    """Check the run ``steps`` against ``spec`` (see the module doc); the initial conditions only with
    ``from_start``. ValueError when a step lacks a proposition of the spec (the recording belongs to
    another controller)."""
    run = distinct_steps(steps)
    names = set(spec.propositions)
    for index, step in enumerate(run):
        missing = names - set(step.inputs) - set(step.outputs)
        if missing:
            raise ValueError(f"state {index} of the run has no value for {', '.join(sorted(missing))}: "
                             "is it a run of this spec?")
    report = RunReport(steps=len(run), transitions=0, initial_checked=from_start and bool(run))
    if not run:
        return report
    first = {**run[0].inputs, **run[0].outputs}
    for section, kind in (("env_init", "assumption"), ("sys_init", "guarantee")) if from_start else ():
        for clause in spec.section(section):
            if _holds(clause, first, first) is False:
                report.violations.append(Violation(kind, section, 0, run[0].time, clause_name(clause)))
    counts = [0] * len(spec.sys_liveness)
    for index, step in enumerate(run):
        current = {**step.inputs, **step.outputs}
        nxt = None
        if index + 1 < len(run) and step.running and run[index + 1].running:
            nxt = {**run[index + 1].inputs, **run[index + 1].outputs}
            report.transitions += 1
            for section, kind in (("env_safety", "assumption"), ("sys_safety", "guarantee")):
                for clause in spec.section(section):
                    if _holds(clause, current, nxt) is False:
                        report.violations.append(Violation(kind, section, index, run[index + 1].time,
                                                           clause_name(clause)))
        for goal, clause in enumerate(spec.sys_liveness):
            if step.running and _holds(clause, current, nxt):
                counts[goal] += 1
    report.goals = [(clause_name(c), n) for c, n in zip(spec.sys_liveness, counts)]
    return report
