"""Resilient execution without ROS: runtime monitor, environment characterization and the user in the
loop (thesis §4.7, Alg. 2, Alg. 3 for a robot alone, §4.10.2's threshold).

``Characterizer`` holds the rewritten specification phi' (Alg. 2):

- the original env-safety clauses psi (kept as they are) and two disjunction sets, EC1 (Eq. 4.3: the
  incoming inputs x_(i+1) as a simple LTL conjunction over next inputs) and EC2 (Eq. 4.4: the
  current inputs gamma^e(s_i) and the incoming ones). Every violation appends to both (lines 4, 5;
  a conjunction already in a set is not added twice), so both sets only grow and are bounded by
  2^|X| and 2^(2|X|): they converge (Lemma 1(b)); with every EC1 conjunction present phi'^t_e is
  valid;
- ``characterize(current, incoming)``: env and sys init from the observation (lines 2, 3: the
  incoming inputs and the current outputs), phi'^t_e = G((/\\ psi) | EC1) and resynthesize (lines 6,
  7); if unrealizable, G((/\\ psi) | EC2) (lines 8-10);
- ``add_env_liveness(text)`` (Alg. 3 line 6): user liveness assumptions in the structured syntax,
  checked against the spec's propositions (``SpecError`` naming column and problem).

Every candidate phi' is produced as spec *text* (structured format, or slugsin for a ``.slugsin``
path) with each added disjunct commented with when and what was observed, parsed back, and
synthesized; so the written file (``write_atomic``, after each successful resynthesis) is exactly
what runs, and ``synthesize`` and the executor load it.

``ResilientStrategy`` puts it together behind the strategy interface the ``Controller`` steps
(``inputs``, ``outputs``, ``initial_state``, ``step``): it monitors phi'^t_e on every step (the
running strategy's env safety, current state and incoming inputs), takes recovery moves (thesis
§4.6) while a violation lasts no longer than the ``Threshold`` (§4.10.2), characterizes (Alg. 2)
when it does (at once without recovery), and when EC1 and EC2 both leave phi' unrealizable follows
Alg. 3: S.1 explains (``ltl_stack.synthesis.explain``) and waits for the user's env liveness
(``add_env_liveness``; ``abort``); S.2 — a collaborative robot in the workspace — calls ``negotiate``,
the extension point of integrative negotiation (§4.8). ``mode`` (``Mode``) and ``counters`` are
what an executor publishes.
"""
from __future__ import annotations

import re
import threading
import time
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional

from ltl_stack.fileio import write_atomic
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.spec import (
    SpecError,
    formula_to_infix,
    formula_to_slugsin,
    parse_slugsin,
    parse_structured,
    write_slugsin,
)
from ltl_stack.spec.formula import And, Formula, Not, Or, Var, variables
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.spec.writer import write_spec_text
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.errors import AssumptionViolation, SynthesisError
from ltl_stack.synthesis.explain import Explanation, explain
from ltl_stack.synthesis.recovery import StepKind, StepResult, UnsafeStep
from ltl_stack.synthesis.strategy import State, SymbolicStrategy

EC1, EC2 = "EC1", "EC2"
#: attempts and events a resilient strategy keeps (memory stays bounded under a flood of violations)
HISTORY_KEPT = 1
EVENTS_KEPT = 1000
#: the characters ``str.splitlines`` breaks a line at
LINE_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"


class ExecutionAborted(AssumptionViolation):
    """The execution was aborted (Alg. 3 line 11, or by the user): every output must be false.

    An ``AssumptionViolation`` so that a controller's violation handling catches it."""

    def __init__(self, reason: str) -> None:
        super().__init__([], {})
        self.reason = reason
        self.args = (f"execution aborted: {reason}",)


@dataclass(frozen=True)
class Observation:
    """One observed transition: the current state's valuation and the incoming inputs."""

    step: int
    wall_time: float
    current_inputs: dict[str, bool]
    current_outputs: dict[str, bool]
    incoming: dict[str, bool]


@dataclass(frozen=True)
class Disjunct:
    """A simple LTL conjunction added to phi'^t_e (Eq. 4.3 or 4.4) and what it came from."""

    kind: str
    formula: Formula
    observation: Observation

    def comment(self) -> str:
        when = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(self.observation.wall_time))
        eq = "Eq. 4.3" if self.kind == EC1 else "Eq. 4.4"
        now = _true(self.observation.current_inputs)
        return (f"{self.kind} ({eq}) observed {when} at step {self.observation.step}: "
                f"inputs {now} -> {_true(self.observation.incoming)} "
                f"(outputs {_true(self.observation.current_outputs)})")


@dataclass
class Attempt:
    """The outcome of one resynthesis."""

    realizable: bool
    variant: str  # EC1, EC2, "user" (with user liveness), "negotiation"
    spec: Spec
    text: str
    strategy: SymbolicStrategy | None
    seconds: float


def _true(valuation: Mapping[str, bool]) -> str:
    return "{" + ", ".join(k for k, v in valuation.items() if v) + "}"


def _literals(valuation: Mapping[str, bool], names: list[str], primed: bool) -> list[Formula]:
    return [Var(n, primed) if valuation[n] else Not(Var(n, primed)) for n in names]


def _conjunction(parts: list[Formula]) -> Formula:
    return parts[0] if len(parts) == 1 else And(tuple(parts))


class Characterizer:
    """The specification phi' of Alg. 2 and its rewriting (see the module docstring)."""

    def __init__(self, spec: Spec, *, path: str | Path | None = None,
                 synthesis_options: Mapping[str, Any] | None = None) -> None:
        self.original = spec
        self.path = Path(path) if path is not None else None
        self.synthesis_options = dict(synthesis_options or {})
        self.ec1: list[Disjunct] = []
        self.ec2: list[Disjunct] = []
        self.user_liveness: list[tuple[str, float]] = []  # (text, when added)
        self.variant: str | None = None  # the EC variant of the running spec (None: original)
        self.observation: Observation | None = None  # the one the running spec's init comes from
        #: the latest attempts (each holds a strategy and its BDD manager, megabytes: only the last
        #: ``HISTORY_KEPT`` are kept, so memory stays flat over hundreds of resyntheses)
        self.history: deque[Attempt] = deque(maxlen=HISTORY_KEPT)
        #: each input literal once (name, primed, value): the EC conjunctions share them, so a disjunct
        #: holds one And and its tuple instead of 2-3 objects per input (bounded memory under a flood of violations)
        self._literals: dict[tuple[str, bool, bool], Formula] = {}

    # --- Alg. 2 -----------------------------------------------------------------------------------
    def _shared(self, valuation: Mapping[str, bool], primed: bool) -> list[Formula]:
        """``_literals`` over the inputs, each literal the same object every time."""
        out = []
        for name in self.original.inputs:
            key = (name, primed, bool(valuation[name]))
            literal = self._literals.get(key)
            if literal is None:
                literal = self._literals[key] = _literals({name: key[2]}, [name], primed)[0]
            out.append(literal)
        return out

    def record(self, observation: Observation) -> tuple[bool, bool]:
        """Append the observation's EC1 and EC2 conjunctions (lines 4, 5); returns which were new."""
        incoming = self._shared(observation.incoming, True)
        one = _conjunction(incoming)
        two = _conjunction(self._shared(observation.current_inputs, False) + incoming)
        new1 = all(d.formula != one for d in self.ec1)
        new2 = all(d.formula != two for d in self.ec2)
        if new1:
            self.ec1.append(Disjunct(EC1, one, observation))
        if new2:
            self.ec2.append(Disjunct(EC2, two, observation))
        return new1, new2

    def characterize(self, observation: Observation) -> Attempt:
        """Alg. 2: init from the observation, then the EC1 variant, else the EC2 variant."""
        self.record(observation)
        attempt = self.attempt(EC1, observation)
        if not attempt.realizable:
            attempt = self.attempt(EC2, observation)
        return attempt

    def attempt(self, variant: str, observation: Observation, extra_liveness: list[str] = ()) -> Attempt:
        """Synthesize phi' with the ``variant`` disjunction set and init from ``observation``."""
        text = self.text(variant, observation, list(extra_liveness))
        spec = self.parse(text)
        start = time.perf_counter()
        result = synthesize(spec, **self.synthesis_options)
        attempt = Attempt(result.realizable, variant, spec, text, result.strategy, time.perf_counter() - start)
        self.history.append(attempt)
        return attempt

    def accept(self, attempt: Attempt, observation: Observation, liveness: list[str] = ()) -> None:
        """Make ``attempt`` the running spec and write it (atomically) when a path was given."""
        self.variant = attempt.variant if attempt.variant in (EC1, EC2) else self.variant
        self.observation = observation
        for text in liveness:
            self.user_liveness.append((text, time.time()))
        if self.path is not None:
            write_atomic(self.path, attempt.text)

    # --- Alg. 3 line 6 ----------------------------------------------------------------------------
    def check_liveness(self, text: str) -> Formula:
        """Parse one env-liveness formula (structured syntax) against the spec's propositions."""
        where = "env liveness"
        if not isinstance(text, str) or not text.strip():
            raise SpecError(where, 1, 1, "empty formula; write one like: doorOpen | doorBroken")
        breaks = [c for c in text.strip() if c in LINE_BREAKS]
        if breaks:  # str.splitlines splits there too: two formulas would be taken as one text
            raise SpecError(where, 1, text.strip().index(breaks[0]) + 1,
                            f"one formula on one line (it contains the line break U+{ord(breaks[0]):04X})")
        if re.fullmatch(r"\[[^\]]*\]", text.strip()):
            raise SpecError(where, 1, 1, f"{text.strip()} is a section header, not a formula; write one like: "
                            "doorOpen | doorBroken")
        spec = self.original
        bits = {b for var in spec.integers for b in var.bits}
        decl = ["[INPUT]"]
        decl += [n for n in spec.inputs if n not in bits]
        decl += [f"{v.name}:{v.low}...{v.high}" for v in spec.integers if v.bits and v.bits[0] in spec.inputs]
        decl.append("[OUTPUT]")
        decl += [n for n in spec.outputs if n not in bits]
        decl += [f"{v.name}:{v.low}...{v.high}" for v in spec.integers if v.bits and v.bits[0] in spec.outputs]
        source = "[ENV_LIVENESS]\n" + text.strip() + "\n" + "\n".join(decl) + "\n"
        try:
            parsed = parse_structured(source, where)
        except SpecError as err:
            if err.line == 2:
                raise SpecError(where, 1, err.column, err.message) from None
            raise SpecError(where, 1, 1, err.message) from None
        if len(parsed.env_liveness) != 1:
            raise SpecError(where, 1, 1, "not one formula; write one like: doorOpen | doorBroken")
        formula = parsed.env_liveness[0].formula
        primed = sorted({v.name for v in _variables(formula) if v.primed and v.name in spec.outputs})
        if primed:
            raise SpecError(where, 1, 1, f"next-state output(s) {', '.join(p + chr(39) for p in primed)} in an "
                            "environment assumption (the environment cannot see the robot's next move)")
        return formula

    # --- spec text --------------------------------------------------------------------------------
    def text(self, variant: str | None, observation: Observation | None, extra_liveness: list[str] = ()) -> str:
        """phi' as spec text (slugsin when ``path`` ends in .slugsin, else structured)."""
        spec = self.original
        slugsin = self.path is not None and self.path.suffix == ".slugsin"
        render = formula_to_slugsin if slugsin else formula_to_infix
        header = ["# Specification rewritten at runtime by ltl_stack's environment characterization",
                  "# (thesis §4.7, Alg. 2" + (f"; variant {variant}" if variant else "") + f") from {spec.source}.",
                  "# It loads like any spec: synthesize FILE, controller_executor FILE.", ""]
        if any(var.bits for var in spec.integers):
            header.append("# integers appear as their bits: " + ", ".join(
                f"{v.name}:{v.low}...{v.high} = {' '.join(v.bits)}" for v in spec.integers if v.bits))
        sections: dict[str, list[Any]] = {}
        for section in SECTIONS:
            out: list[Any] = sections.setdefault(section, [])
            if section in ("env_init", "sys_init") and observation is not None:
                names = spec.inputs if section == "env_init" else spec.outputs
                values = observation.incoming if section == "env_init" else observation.current_outputs
                what = "incoming inputs" if section == "env_init" else "current outputs"
                out.append(f"# Alg. 2 line {2 if section == 'env_init' else 3}: the {what} observed at step "
                           f"{observation.step}")
                out.append(_conjunction(_literals(values, names, False)))
            elif section == "env_safety" and variant is not None:
                disjuncts = self.ec1 if variant == EC1 else self.ec2
                original = [c.formula for c in spec.env_safety]
                out.append(f"# G((original assumptions) | {variant} disjuncts), Alg. 2 line "
                           f"{6 if variant == EC1 else 9}. The original assumptions:")
                out += [f"#   {c.location}: {c.text}" for c in spec.env_safety]
                for k, d in enumerate(disjuncts, 1):
                    out.append(f"# disjunct {k}: {d.comment()}")
                    out.append(f"#   {formula_to_infix(d.formula)}")
                other = self.ec2 if variant == EC1 else self.ec1
                if other:
                    out.append(f"# The {EC2 if variant == EC1 else EC1} set, kept for later resyntheses "
                               "(not part of this formula):")
                    out += [f"#   {d.comment()}: {formula_to_infix(d.formula)}" for d in other]
                base = _conjunction(original) if original else None
                parts = ([base] if base is not None else []) + [d.formula for d in disjuncts]
                out.append(parts[0] if len(parts) == 1 else Or(tuple(parts)))
            else:
                for c in spec.section(section):
                    out.append(f"# {c.location}: {c.text}")
                    out.append(c.formula)
                if section == "env_liveness":
                    for text, when in self.user_liveness:
                        out.append(f"# added by the user {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(when))}"
                                   " (Alg. 3 line 6)")
                        out.append(self.check_liveness(text))
                    for text in extra_liveness:
                        out.append("# added by the user now (Alg. 3 line 6)")
                        out.append(self.check_liveness(text))
        return write_spec_text(sections, header=header, inputs=spec.inputs, outputs=spec.outputs, render=render)

    def parse(self, text: str) -> Spec:
        name = str(self.path) if self.path is not None else "<characterized spec>"
        if self.path is not None and self.path.suffix == ".slugsin":
            return parse_slugsin(text, name)
        return parse_structured(text, name)


def _variables(formula: Formula) -> list[Var]:
    return list(variables(formula))  # each shared subformula once: work linear in the DAG, not the tree


def characterizing_message(count: int, violated: list[Clause]) -> str:
    """The event that starts a characterization: the violated clauses, and how long the violation
    lasted when the threshold counted it (a violation left standing after a handover was not counted)."""
    where = "; ".join(f"{c.location}" for c in violated)
    after = f" after {count} violating transition(s)" if count else ""
    return f"characterizing{after} ({where})"


class Threshold:
    """§4.10.2: with recovery on, characterize only once a violation has lasted more than
    ``transitions`` consecutive violating transitions or ``seconds`` (either; None = not used;
    neither = at once)."""

    def __init__(self, transitions: int | None = None, seconds: float | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if transitions is not None and transitions < 0:
            raise ValueError(f"transitions must be >= 0, got {transitions}")
        if seconds is not None and seconds < 0:
            raise ValueError(f"seconds must be >= 0, got {seconds}")
        self.transitions = transitions
        self.seconds = seconds
        self.clock = clock
        self.count = 0
        self.since: float | None = None

    def observe(self, violated: bool) -> bool:
        """Record one transition; True when characterization is due."""
        if not violated:
            self.reset()
            return False
        self.count += 1
        now = self.clock()
        if self.since is None:
            self.since = now
        if self.transitions is None and self.seconds is None:
            return True
        return bool((self.transitions is not None and self.count > self.transitions)
                    or (self.seconds is not None and now - self.since > self.seconds))

    def reset(self) -> None:
        self.count = 0
        self.since = None


@dataclass
class Counters:
    """What happened so far (published by an executor)."""

    violations: int = 0             # violating transitions observed
    recovery_steps: int = 0         # steps taken with a recovery move
    resyntheses: int = 0            # new strategies put in place
    ec1: int = 0                    # ... of them from the EC1 variant
    ec2: int = 0                    # ... from the EC2 variant
    user: int = 0                   # ... after user liveness
    unrealizable: int = 0           # characterizations where EC1 and EC2 both failed
    negotiations: int = 0           # negotiations held with a collaborative robot (§4.8)
    negotiated: int = 0             # new strategies adopted from a negotiation (also in resyntheses)
    unsafe: int = 0                 # steps where no move kept sys safety

    def new_strategy(self, source: str | None) -> None:
        """One more new strategy in place, from ``source``: EC1, EC2, "user" (the user's liveness) or
        "negotiation"; it counts in ``resyntheses`` and in that source's counter."""
        self.resyntheses += 1
        name = {EC1: "ec1", EC2: "ec2", "user": "user", "negotiation": "negotiated"}.get(source)
        if name is not None:
            setattr(self, name, getattr(self, name) + 1)


@dataclass(frozen=True)
class Event:
    step: int
    mode: Mode
    message: str


#: The negotiation hook (Alg. 3 line 9): the agreed spec to run; None when negotiation does not apply —
#: no collaborative robot is involved, the peer is absent or silent, or the pair already negotated —
#: and the robot goes to S.1 (explanation and the user, §4.4: the peer is then uncontrollable
#: environment); ``NegotiationAbort`` when the robots negotiated and cannot agree (4.8.3, line 20).
Negotiate = Callable[["ResilientStrategy", Observation], Optional[Spec]]


class NegotiationAbort(Exception):
    """The negotiation hook's answer when Alg. 4 ended in 4.8.3 or line 20: the robot aborts."""


@dataclass
class _Pending:
    observation: Observation
    explanation: Explanation | None = None
    extra: list[str] = field(default_factory=list)


class ResilientStrategy:
    """A strategy with recovery, environment characterization and the user in the loop."""

    #: The longest handover after a negotiation this robot initiated (see ``_handover``), in seconds:
    #: a peer whose promised output has not arrived by then is taken to break its promise.
    HANDOVER_SECONDS = 5.0

    def __init__(self, spec: Spec, *, recovery: bool = True, characterize: bool = True,
                 threshold: Threshold | None = None, path: str | Path | None = None,
                 synthesis_options: Mapping[str, Any] | None = None, negotiate: Negotiate | None = None,
                 on_event: Callable[[Event], None] | None = None,
                 wall_clock: Callable[[], float] = time.time) -> None:
        self.characterizer = Characterizer(spec, path=path, synthesis_options=synthesis_options)
        result = synthesize(spec, **self.characterizer.synthesis_options)
        if not result.realizable:
            raise SynthesisError(f"{spec.source}: the specification is unrealizable")
        self.strategy: SymbolicStrategy = result.strategy
        self.strategy.recovery = recovery
        self.recovery = recovery
        self.characterize_enabled = characterize
        self.threshold = threshold if threshold is not None else Threshold()
        if not recovery:
            self.threshold = Threshold()  # without recovery there is nothing to wait with
        self.negotiate = negotiate
        self.on_event = on_event
        self.wall_clock = wall_clock
        self.inputs = list(spec.inputs)
        self.outputs = list(spec.outputs)
        self.mode = Mode.NORMAL
        #: After this robot, as the initiator, adopts a negotiated spec (Alg. 4): the inputs it read then.
        #: Until an input changes (or HANDOVER_SECONDS pass), a violation is recovered but not
        #: characterized: the steps still read the peer's outputs from before the peer adopted (its first
        #: step with the agreed spec, and the message, are on their way), and characterizing that
        #: handover would drop the promise just agreed.
        self._handover: dict[str, bool] | None = None
        self._handover_until = 0.0
        self.counters = Counters()
        self.events: deque[Event] = deque(maxlen=EVENTS_KEPT)  # the latest (``on_event`` sees every one)
        self.last: StepResult | None = None
        self.explanation: Explanation | None = None
        self.steps = 0
        self._pending: _Pending | None = None
        #: held while negotiation reads or replaces the base spec (the executor's own lock replaces it)
        self.lock: Any = threading.RLock()
        self._state: State | None = None

    # --- strategy interface ---------------------------------------------------------------------
    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> State:
        self._state = self.strategy.initial_state(inputs=inputs, outputs=outputs)
        return self._state

    def step(self, state: State, inputs: Mapping[str, bool]) -> State:
        """Monitor, recover, characterize (see the class docstring); raises ``AssumptionViolation``
        when the violation is not handled (recovery off and characterization failed),
        ``UnsafeStep`` when no move keeps sys safety, ``ExecutionAborted`` once aborted."""
        if self.mode is Mode.ABORTED:
            raise ExecutionAborted(self._abort_reason)
        self.steps += 1
        incoming = {n: bool(inputs[n]) for n in self.inputs}
        game = self.strategy.game
        violated = game.violated("env_safety", state.valuation, incoming)
        if violated:
            self.counters.violations += 1
        observation = Observation(self.steps, self.wall_clock(), dict(state.inputs), dict(state.outputs), incoming)
        if self._handover is not None and (incoming != self._handover or self._handover_over()):
            self._handover = None  # news from the environment, or the peer is late: the handover is over
        if violated and self._handover is not None:
            self._event("a violation during the handover after a negotiated adoption: recovered, not characterized")
        elif violated and self.mode is not Mode.WAITING_FOR_USER and self.characterize_enabled:
            due = self.threshold.observe(True)
            if due:
                new_state = self._characterize(observation, violated)
                if new_state is not None:
                    return new_state
            else:
                self.characterizer.record(observation)  # §4.10.2: learned now, resynthesized later
        elif not violated:
            self.threshold.observe(False)
        return self._move(state, incoming, violated)

    # --- Alg. 3 user input ----------------------------------------------------------------------
    def add_env_liveness(self, texts: list[str] | str) -> Attempt:
        """Alg. 3 lines 6-7: resynthesize with the user's env liveness (EC1 variant first, then EC2);
        on success the controller continues from the current state, otherwise it aborts.
        Raises ``SpecError`` for a formula that does not parse against the spec (nothing changes)."""
        texts = [texts] if isinstance(texts, str) else list(texts)
        for text in texts:
            self.characterizer.check_liveness(text)
        if self.mode is Mode.ABORTED:
            raise ExecutionAborted(self._abort_reason)
        state = self._state
        observation = Observation(self.steps, self.wall_clock(), dict(state.inputs) if state else {},
                                  dict(state.outputs) if state else {}, dict(state.inputs) if state else {})
        previous = self.mode
        self.mode = Mode.CHARACTERIZING
        attempt = None
        for variant in (EC1, EC2) if self.characterizer.ec1 else (None,):
            attempt = self._attempt_user(variant, observation, texts)
            if attempt.realizable:
                break
        if attempt.realizable:
            self.characterizer.accept(attempt, observation, texts)
            self._install(attempt, observation)
            self.counters.new_strategy("user")
            self._event(f"user env liveness {'; '.join(texts)}: realizable ({attempt.variant}); continuing")
        else:
            self.mode = previous
            self.abort(f"still unrealizable with the user's env liveness {'; '.join(texts)}")
        return attempt

    def _attempt_user(self, variant: str | None, observation: Observation, texts: list[str]) -> Attempt:
        ch = self.characterizer
        if variant is None:  # nothing characterized yet: the original safety, init from now
            text = ch.text(None, observation, texts)
            spec = ch.parse(text)
            start = time.perf_counter()
            result = synthesize(spec, **ch.synthesis_options)
            return Attempt(result.realizable, "user", spec, text, result.strategy, time.perf_counter() - start)
        return ch.attempt(variant, observation, texts)

    def abort(self, reason: str = "aborted by the user") -> None:
        """Abort (Alg. 3 line 11): every later step raises ``ExecutionAborted``; outputs must be false."""
        self._abort_reason = reason
        self.mode = Mode.ABORTED
        self._event(f"aborted: {reason}")

    def adopt(self, spec: Spec, text: str, strategy: SymbolicStrategy, inputs: Mapping[str, bool],
              outputs: Mapping[str, bool], write: bool = True) -> State:
        """Run ``spec`` (with its ``strategy``) from the position (``inputs``, ``outputs``) on: a
        specification adopted by integrative negotiation (§4.8, Alg. 4 lines 12/15). It becomes the
        base of later characterizations, whose disjunction sets start empty (Alg. 4 line 2), and is
        written atomically to ``path`` (slugsin for a ``.slugsin`` path). Returns the new state."""
        path = self.characterizer.path
        self.characterizer = Characterizer(spec, path=path, synthesis_options=self.characterizer.synthesis_options)
        if path is not None and write:  # (negotiation writes it itself before agreeing: two-phase)
            write_atomic(path, write_slugsin(spec, comments=True) if path.suffix == ".slugsin" else text)
        observation = Observation(self.steps, self.wall_clock(), dict(inputs), dict(outputs), dict(inputs))
        self.counters.new_strategy("negotiation")
        self.threshold.reset()
        state = self._install(Attempt(True, "negotiation", spec, text, strategy, 0.0), observation)
        self._event("adopted the specification negotiated with a collaborative robot (Alg. 4)")
        return state

    # --- integrative negotiation (the interface ``runtime.resilience.negotiation.sessions.NegotiationHost``) ----
    def negotiation_base(self) -> Spec:
        """phi*_r (Alg. 4): the spec a negotiation starts from — the original, or the one adopted last."""
        return self.characterizer.original

    def rebase(self, spec: Spec) -> None:
        """The initiator adopted ``spec`` (the negotiation hook returns it to run): it becomes the base
        of later characterizations (EC sets start empty, Alg. 4 line 2)."""
        old = self.characterizer
        self.characterizer = Characterizer(spec, path=old.path, synthesis_options=old.synthesis_options)

    @property
    def spec_path(self) -> Path | None:
        """Where the spec this robot runs is written (``--characterized-spec``), or None."""
        return self.characterizer.path

    def negotiation_held(self) -> None:
        """One more negotiation held by this robot, whatever its outcome (``Counters.negotiations``)."""
        with self.lock:
            self.counters.negotiations += 1

    @property
    def aborted(self) -> bool:
        return self.mode is Mode.ABORTED

    def install_negotiated(self, spec: Spec, text: str, strategy: SymbolicStrategy, inputs: Mapping[str, bool],
                           outputs: Mapping[str, bool], write: bool = True) -> State | None:
        """The responder adopted ``spec`` (``adopt``, from the position the negotiation started at):
        the state its controller continues from (None: handed to the controller already)."""
        return self.adopt(spec, text, strategy, inputs, outputs, write=write)

    def safe_outputs(self) -> dict[str, bool]:
        """The outputs an aborted controller publishes: all false."""
        return dict.fromkeys(self.outputs, False)

    # --- internals --------------------------------------------------------------------------------
    def _begin_handover(self, readings: Mapping[str, bool]) -> None:
        self._handover = {n: bool(readings.get(n, False)) for n in self.inputs}
        self._handover_until = self.threshold.clock() + self.HANDOVER_SECONDS

    def _handover_over(self) -> bool:
        return self.threshold.clock() >= self._handover_until

    def _characterize(self, observation: Observation, violated: list[Clause]) -> State | None:
        self.mode = Mode.CHARACTERIZING
        self._event(characterizing_message(self.threshold.count, violated))
        attempt = self.characterizer.characterize(observation)
        if attempt.realizable:
            self.characterizer.accept(attempt, observation)
            self.counters.new_strategy(attempt.variant)  # EC1 or EC2
            self.threshold.reset()
            self._event(f"resynthesized with {attempt.variant} in {attempt.seconds * 1000:.1f} ms")
            return self._install(attempt, observation)
        self.counters.unrealizable += 1
        if self.negotiate is not None:  # S.2: a collaborative robot caused it (Alg. 3 line 9, §4.8)
            try:
                spec = self.negotiate(self, observation)
            except NegotiationAbort as ended:
                self.abort(f"unrealizable after environment characterization and negotiation: {ended}")
                raise ExecutionAborted(self._abort_reason) from None
            result = synthesize(spec, **self.characterizer.synthesis_options) if spec is not None else None
            if result is not None and result.realizable:
                text = self.characterizer.text(None, observation)
                attempt = Attempt(True, "negotiation", spec, text, result.strategy, 0.0)
                self.counters.new_strategy("negotiation")
                self._event("negotiation gave a realizable specification")
                self._begin_handover(observation.incoming)
                return self._install(attempt, observation)
            if spec is not None:
                self.abort("the negotiated specification is unrealizable")
                raise ExecutionAborted(self._abort_reason)
            self._event("no collaborative robot to negotiate with (none involved, absent or silent, or "
                        "already negotiated): S.1")
        # S.1 (Alg. 3 lines 4-5): explain and wait for the user
        self.explanation = explain(attempt.spec, robotics_semantics=self.characterizer.synthesis_options.get(
            "robotics_semantics", True))
        self._pending = _Pending(observation, self.explanation)
        self.mode = Mode.WAITING_FOR_USER
        self._event("unrealizable with EC1 and EC2; waiting for the user's env liveness "
                    "(add_env_liveness) or abort")
        return None

    def _switch_to(self, attempt: Attempt) -> SymbolicStrategy:
        """Make ``attempt``'s strategy the running one (mode normal, nothing pending)."""
        strategy = attempt.strategy
        strategy.recovery = self.recovery
        self.strategy = strategy
        self.inputs, self.outputs = list(attempt.spec.inputs), list(attempt.spec.outputs)
        self._pending = None
        self.explanation = None
        self.mode = Mode.NORMAL
        return strategy

    def _install(self, attempt: Attempt, observation: Observation) -> State:
        strategy = self._switch_to(attempt)
        state = self._state if self._state is not None else None
        inputs = observation.incoming if observation.incoming else (state.inputs if state else {})
        outputs = observation.current_outputs if observation.current_outputs else (state.outputs if state else {})
        self._state = strategy.initial_state(inputs=inputs, outputs=outputs)
        return self._state

    def _move(self, state: State, incoming: dict[str, bool], violated: list[Clause]) -> State:
        if not self.recovery and violated:
            if self.mode is not Mode.WAITING_FOR_USER:
                self.mode = Mode.NORMAL
            raise AssumptionViolation(violated, incoming)
        result = self.strategy.step_result(state, incoming)
        self.last = result
        if result.kind is StepKind.UNSAFE:
            self.counters.unsafe += 1
            self._event("no move keeps the system safety: " + "; ".join(c.location for c in result.unsafe))
            raise UnsafeStep(result.violated, incoming, result.unsafe)
        if result.kind is not StepKind.NORMAL:
            self.counters.recovery_steps += 1
        if self.mode is not Mode.WAITING_FOR_USER:
            self.mode = Mode.NORMAL if result.kind is StepKind.NORMAL else Mode.RECOVERING
        self._state = result.state
        return result.state

    def _event(self, message: str) -> None:
        event = Event(self.steps, self.mode, message)
        self.events.append(event)
        if self.on_event is not None:
            self.on_event(event)
