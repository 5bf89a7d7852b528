"""What the executor node reports, free of ROS: the mode of the node and its words and levels on
/diagnostics, what one controller update publishes, the violation report, the counters, the answers of
its services and the ``--json`` events (thesis ch. 4).

``NodeReports`` holds the node's decisions: what one controller update publishes, how violations,
recovery moves and unsafe steps are counted, the mode and health statuses of /diagnostics (texts and
levels), the violation report and the ``--json`` events. The outputs published while the node takes
no strategy move are the output guard's (``output_guard``, Lemma 1(a)). The node
(``ltl_stack.ros.executor``) only wires these decisions to topics, timers, logs and /diagnostics.
"""
from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from ltl_stack.errors import Exit
from ltl_stack.runtime.executor.controller import Controller, Update
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.executor.recovery import RecoveringStrategy
from ltl_stack.runtime.resilience.characterize import Counters, ExecutionAborted
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience, Busy
from ltl_stack.spec import SpecError
from ltl_stack.spec.formula_text import clause_in_words
from ltl_stack.spec.model import Clause
from ltl_stack.spec.valuation import format_valuation
from ltl_stack.synthesis.automaton import goal_text
from ltl_stack.synthesis.errors import AssumptionViolation
from ltl_stack.synthesis.explain_render import clause_line, explanation_text
from ltl_stack.synthesis.recovery import (
    StepKind,
    StepResult,
    UnsafeStep,
)

__all__ = ["ERROR", "INITIAL_STATUSES", "MODE_LEVELS", "OK", "USER_ABORT", "WARN", "Answer", "ModeReport",
           "NodeReports", "Publication", "Status", "ViolationReport", "aborted_report", "counters_event",
           "current_mode", "in_words", "liveness_refusal", "mode_text", "policy_text", "readings_key", "shown",
           "step_report", "strategy_source", "violation_report", "waiting_text"]

#: The levels of diagnostic_msgs/DiagnosticStatus.
OK, WARN, ERROR = 0, 1, 2
#: The diagnostic level of each mode (``~state``'s ``mode``).
MODE_LEVELS = {Mode.NORMAL.value: OK, Mode.RECOVERING.value: WARN, Mode.HOLDING.value: WARN,
               Mode.CHARACTERIZING.value: WARN, Mode.WAITING_FOR_USER.value: WARN, Mode.INPUTS_UNKNOWN.value: WARN,
               Mode.ABORTED.value: ERROR}


def current_mode(aborted: bool, violation: bool, resilient: str | None, recovered: bool,
                 unknown: bool = False) -> str:
    """``~state``'s mode: the value of a ``Mode``.

    ``violation``: the controller holds a violation (no recovery move was taken); ``resilient``: the
    resilient strategy's mode (None without characterization); ``recovered``: the latest update
    took a recovery move; ``unknown``: some input is stale (older than its freshness bound), the
    outputs keep rho_s for every value of it, nothing is stepped."""
    if aborted:
        return Mode.ABORTED.value
    if unknown:
        return Mode.INPUTS_UNKNOWN.value
    if resilient is not None:
        if resilient in (Mode.NORMAL.value, Mode.RECOVERING.value) and violation:
            return Mode.HOLDING.value
        if resilient == Mode.NORMAL.value and recovered:
            return Mode.RECOVERING.value
        return resilient
    if violation:
        return Mode.HOLDING.value
    return Mode.RECOVERING.value if recovered else Mode.NORMAL.value


def mode_text(mode: str, policy: str, recovery: bool, aborted: str | None) -> str:
    """The first words of the "mode" diagnostic status."""
    return {Mode.NORMAL: "normal", Mode.RECOVERING: "recovering: recovery moves keep the system safety",
            Mode.HOLDING: f"holding: no recovery move; outputs by --on-violation {policy}, kept safe (Lemma 1(a))",
            Mode.CHARACTERIZING: "characterizing: resynthesizing (recovery moves meanwhile)"
            if recovery else "characterizing: resynthesizing (holding meanwhile, kept safe)",
            Mode.WAITING_FOR_USER: "waiting for the user: unrealizable after environment characterization; call "
                                   "~add_env_liveness with an environment liveness assumption, or ~abort",
            Mode.INPUTS_UNKNOWN: "inputs unknown (no message within their freshness bound): not stepping; outputs "
                                 "keep the system safety for every value of them",
            Mode.ABORTED: f"aborted ({aborted}): every output is false"}[Mode(mode)]


def liveness_refusal(characterize: bool, started: bool, mode: str) -> str | None:
    """Why ``~add_env_liveness`` is not taken now (exit 1, nothing changes), or None: it is Alg. 3
    line 6, the user's answer once environment characterization found no realizable spec."""
    if not characterize:
        return ("environment characterization is off: start the executor with --characterize or "
                "--characterized-spec FILE (docs/resilience.md)")
    if mode == Mode.ABORTED.value:
        return "already aborted: every output is false"
    if not started:
        return "not ready: the controller has not started yet (waiting for every input to report)"
    if mode != Mode.WAITING_FOR_USER.value:
        return (f"not waiting for the user (mode {mode}): an environment liveness assumption is taken after "
                "environment characterization found no realizable specification (docs/resilience.md)")
    return None


def policy_text(policy: str, unsafe: bool) -> str:
    """How the outputs follow the ``--on-violation`` policy, for the violation report."""
    if unsafe:
        return f"no output valuation keeps the system safety: publishing the {policy} valuation as it is"
    if policy == "hold":
        return "holding the last outputs (the nearest valuation keeping the system safety if they do not)"
    return "the fewest outputs true that keep the system safety"


def in_words(clause: Any) -> str:
    """The env-safety clause in words (``formula_text``), or "" when it cannot be rendered."""
    try:
        return clause_in_words(clause, "env_safety")
    except Exception:  # noqa: BLE001 - a rendering problem must not hide the violation itself
        return ""


def shown(clause: Any) -> str:
    """``file:line: text`` and, when it says more, the clause in words in parentheses."""
    words = in_words(clause)
    text = f"{clause.location}: {clause.text}"
    return f"{text} ({words})" if words and words.strip() != (clause.text or "").strip() else text


@dataclass(frozen=True)
class ViolationReport:
    """One violation as the node reports it: the log line / diagnostic message, the diagnostic's
    key-value pairs and the ``--json`` event (without the outputs)."""

    text: str
    values: list[tuple[str, str]]
    event: dict[str, Any]
    #: WARN when a recovery move answered the violation, else ERROR
    level: int = ERROR


def violation_report(violation: Any, result: Any, unkeepable: list[Clause], readings: Mapping[str, bool],
                     state_id: int, recovered: bool, policy: str,
                     outputs: Mapping[str, bool] | None = None) -> ViolationReport:
    """The report of an environment-assumption violation: the broken clauses (``file:line``, text and
    English), how the robot answered — a recovery move (``result``: its kind), or the ``policy``'s
    outputs kept safe — and, when no move keeps the system safety, the guarantees that cannot all be
    kept (the recovery's, else the policy guard's ``unkeepable``)."""
    broken = violation.clauses or (result.violated if result is not None else [])
    clauses = [f"{c.location}: {c.text}" for c in broken] or ["(no single clause)"]
    meanings = [in_words(c) for c in broken]
    parts = [f"{c} ({m})" if m else c for c, m in zip(clauses, meanings + [""] * len(clauses))]
    unsafe = [f"{c.location}: {c.text}" for c in (result.unsafe if result is not None else unkeepable)]
    kind = result.kind.value if result is not None else None
    inputs = format_valuation(readings)
    if recovered:
        text = (f"environment assumption violated by inputs {inputs}: {'; '.join(parts)}; "
                f"recovering ({kind}), now in state {state_id}")
    else:
        cannot = (f"; no move keeps the system safety, these guarantees cannot all be kept: {'; '.join(unsafe)}"
                  if unsafe else "")
        text = (f"environment assumption violated by inputs {inputs} from state {state_id}: {'; '.join(parts)}"
                f"{cannot}; {policy_text(policy, bool(unkeepable))}"
                f"{f': publishing outputs {format_valuation(outputs)}' if outputs is not None else ''}"
                ", waiting for admissible inputs")
    values = [("clause", c) for c in clauses] + [("meaning", m) for m in meanings if m] + [
        ("unsafe_clause", c) for c in unsafe] + [
        ("inputs", inputs), ("state", str(state_id)), ("policy", f"recovery ({kind})" if recovered else policy)]
    event: dict[str, Any] = {"event": "violation", "state": state_id, "inputs": dict(readings), "clauses": clauses,
                             "recovered": recovered, "kind": kind}
    if unsafe:
        event["unsafe"] = unsafe
    return ViolationReport(text, values, event, WARN if recovered else ERROR)


def strategy_source(original: str, resilient: Any | None) -> tuple[str, int]:
    """``~state``'s ``spec_file`` and ``strategy_generation``: the file the running strategy was
    synthesized from and how many strategies were put in place after the one of start-up.

    ``resilient`` is the node's ``BackgroundResilience`` (None without characterization). After a
    resynthesis or an adoption the running spec is the characterized/adopted file, "" when it was
    not written to one (no path, or the write failed)."""
    if resilient is None or resilient.counters.resyntheses == 0:
        return (os.path.abspath(original) if original else ""), 0
    path = resilient.characterizer.path
    written = path is not None and getattr(resilient, "write_error", None) is None
    return (os.path.abspath(path) if written else ""), resilient.counters.resyntheses


@dataclass(frozen=True)
class Status:
    """One /diagnostics status of the node, for the concern ``what`` ("mode", "inputs", ...). A
    ``quiet`` one is only kept for the once-a-second publication, never sent on its own."""

    level: int
    what: str
    message: str
    values: list[tuple[str, str]] = field(default_factory=list)
    quiet: bool = False


#: The statuses the node starts with, besides those of ``NodeReports.mode_report`` and ``health``.
INITIAL_STATUSES = (Status(OK, "environment assumptions", "no violation", quiet=True),
                    Status(OK, "input publishers", "one publisher or none per input topic", quiet=True))


@dataclass(frozen=True)
class Publication:
    """What the node does with one controller update besides writing its changed outputs: publish
    ``~state``/``~valuation`` (``state``), log the step (``step``), report ``update``'s violation
    (``violation``, with the recovery's ``result``), report ``cleared`` (the inputs are admissible
    again), refresh the health and the mode statuses."""

    update: Update
    state: bool
    step: bool
    violation: bool
    result: StepResult | None
    cleared: Status | None
    health: bool
    mode: bool


@dataclass(frozen=True)
class ModeReport:
    """The "mode" status, the "spec file" status (None without a characterized/adopted spec path),
    whether the mode changed since the last report, and the ``--json`` event of a change."""

    mode: str
    status: Status
    spec_file: Status | None
    changed: bool
    event: dict[str, Any]


@dataclass(frozen=True)
class Answer:
    """A service's answer (``~add_env_liveness``, ``~abort``): success, the tool's exit code (README's
    table), the message, the mode after the call, and the line to log (``warn``/``info``, text) or None."""

    success: bool
    code: int
    message: str
    mode: str
    log: tuple[str, str] | None = None


#: why the user's ``~abort`` aborts (Alg. 3 line 11)
USER_ABORT = "aborted by the user (~abort)"


def aborted_report(reason: str) -> tuple[str, dict[str, Any]]:
    """The log line and the ``--json`` event of an abort (Alg. 3 line 11)."""
    return (f"execution aborted ({reason}): every output is false; the node stays up",
            {"event": "aborted", "reason": reason})


def waiting_text(explanation: Any) -> str:
    """The warning when environment characterization found no realizable spec (Alg. 3 S.1)."""
    return (f"environment characterization found no realizable specification:\n{explanation_text(explanation)}\n"
            "add an environment liveness assumption (rosrun ltl_stack add_env_liveness \"FORMULA\") or abort "
            "(rosrun ltl_stack add_env_liveness --abort)")


def readings_key(readings: Mapping[str, bool]) -> tuple:
    """The readings as a comparable key: a violation is reported once per distinct valuation."""
    return tuple(sorted(readings.items()))


def step_report(update: Update) -> tuple[str, dict[str, Any]]:
    """The log line and the ``--json`` event of a step (or of the initial state)."""
    state = update.state
    text = (f"{'initial' if update.started else 'step to'} state {state.id} (goal {goal_text(state.goal)}): inputs "
            f"{format_valuation(state.inputs)} -> outputs {format_valuation(update.outputs)}")
    return text, {"event": "start" if update.started else "step", "state": state.id, "goal": state.goal,
                  "inputs": dict(state.inputs), "outputs": update.outputs}


def counters_event(kind: str, counters: Counters, **fields: Any) -> dict[str, Any]:
    """A ``--json`` event (``mode``, ``resilience``) with the resynthesis counters."""
    return {"event": kind, **fields, "resyntheses": counters.resyntheses, "ec1": counters.ec1,
            "ec2": counters.ec2, "user": counters.user, "negotiated": counters.negotiated,
            "negotiations": counters.negotiations}


class NodeReports:
    """The executor node's decisions (thesis ch. 4 on /diagnostics and ``~state``), free of ROS.

    It remembers what the node needs between two publications: its own counters when no resilient
    strategy counts (no characterization), the mode last reported, the last violation reported and
    the input-topic publishers already warned about. Call it under the controller's lock, in the
    order the node publishes."""

    def __init__(self, controller: Controller, policy: str, recovery: bool, input_topics: Mapping[str, str],
                 ready_timeout: float) -> None:
        self.controller = controller
        strategy = controller.strategy
        self.resilient: BackgroundResilience | None = strategy if isinstance(strategy, BackgroundResilience) \
            else None
        self.policy = policy
        self.recovery = recovery
        self.input_topics = dict(input_topics)
        self.ready_timeout = ready_timeout
        #: what the node counts itself when the strategy does not (no characterization)
        self.own_counters = Counters()
        self._recovering = False
        self._violated_now: list[str] = []
        #: the mode of the last mode report
        self.mode = Mode.NORMAL.value
        #: recovery moves counted at the last publication, and whether the current update took one:
        #: a one-step violation followed by a normal settling step still shows as "recovering" once
        self._seen_recovery_steps = 0
        self._recovered_in_update = False
        self._last_violation_key: tuple | None = None
        self._warned_publishers: dict[str, tuple[str, ...]] = {}

    @property
    def counters(self) -> Counters:
        return self.resilient.counters if self.resilient is not None else self.own_counters

    def current_mode(self) -> str:
        """normal, recovering, holding, characterizing, waiting_for_user or aborted."""
        controller = self.controller
        with controller.lock:
            return current_mode(controller.aborted is not None, controller.violation is not None,
                                self.resilient.mode.value if self.resilient is not None else None,
                                self._recovered_in_update if self.resilient is not None else self._recovering,
                                bool(controller.unknown))

    def violated_clauses(self) -> list[str]:
        """The env-safety clauses the current inputs violate, ``file:line: text (English)``."""
        if self.resilient is not None:
            clauses = self.resilient.violated_now or (self.resilient.last_violated if self._recovered_in_update
                                                      else [])
            return [shown(c) for c in clauses]
        return list(self._violated_now)

    def account(self, update: Update) -> Update:
        """Count what the update did (without characterization the node counts), and make a
        violation the resilient strategy recovered from internally visible as one (also when the
        settling steps after the recovery move were normal again)."""
        if self.resilient is not None:
            steps = self.resilient.counters.recovery_steps
            self._recovered_in_update = steps > self._seen_recovery_steps
            self._seen_recovery_steps = steps
            violated = self.resilient.violated_now or (self.resilient.last_violated if self._recovered_in_update
                                                       else [])
            if update.stepped and update.violation is None and violated and self.controller.aborted is None:
                update = replace(update, violation=AssumptionViolation(violated, self.controller.readings),
                                 recovered=True)
            return update
        counters = self.own_counters
        if update.violation is not None:
            counters.violations += 1
            self._violated_now = [shown(c) for c in update.violation.clauses]
            strategy = self.controller.strategy
            last = strategy.last if isinstance(strategy, RecoveringStrategy) else None
            if update.recovered:
                counters.recovery_steps += 1
                self._recovering = True
            elif isinstance(update.violation, UnsafeStep) or (last is not None and last.kind is StepKind.UNSAFE):
                counters.unsafe += 1
        elif update.stepped:
            self._violated_now = []
            self._recovering = False
        return update

    def publication(self, update: Update, force_outputs: bool = False, force_state: bool = False) -> Publication:
        """What the node publishes for ``update`` once its changed outputs are written (``force_outputs``:
        all of them were; ``force_state``: publish ``~state`` and the statuses anyway)."""
        changed = update.outputs if force_outputs else update.changed_outputs
        update = self.account(update)
        moved = self.current_mode() != self.mode
        violation = update.violation is not None
        result = cleared = None
        if violation:
            strategy = self.controller.strategy
            result = strategy.last if isinstance(strategy, (RecoveringStrategy, BackgroundResilience)) else None
            if isinstance(update.violation, UnsafeStep) and result is not None and result.kind is not StepKind.UNSAFE:
                result = None
        elif self._last_violation_key is not None and self.controller.violation is None:
            self._last_violation_key = None
            cleared = Status(OK, "environment assumptions", "inputs admissible again")
        return Publication(update, state=bool(changed or update.stepped or force_state or force_outputs or violation
                                              or moved),
                           step=update.stepped, violation=violation, result=result, cleared=cleared,
                           health=bool(update.stepped or update.error or force_state),
                           mode=bool(update.stepped or violation or force_state or moved))

    def still_violated(self, update: Update, key: tuple) -> bool:
        """After the grace time: report ``update``'s violation only if the readings are still ``key``
        and (unless it was recovered) still inadmissible."""
        return bool(update.recovered or self.controller.violation is not None) and \
            readings_key(self.controller.readings) == key

    def violation(self, update: Update, result: StepResult | None = None) -> ViolationReport | None:
        """The report of ``update``'s violation, once per distinct readings (None when already reported)."""
        readings = self.controller.readings
        key = readings_key(readings)
        if key == self._last_violation_key:
            return None
        self._last_violation_key = key
        return violation_report(update.violation, result, update.unkeepable, readings, update.state.id,
                                update.recovered, self.policy, update.outputs)

    def mode_report(self) -> ModeReport:
        """The "mode" status: what the controller is doing and how many resyntheses happened."""
        mode = self.current_mode()
        counters = self.counters
        resilient = self.resilient
        values = [("mode", mode), ("violations", str(counters.violations)),
                  ("recovery_steps", str(counters.recovery_steps)), ("unsafe_steps", str(counters.unsafe)),
                  ("resyntheses", str(counters.resyntheses)), ("resyntheses_ec1", str(counters.ec1)),
                  ("resyntheses_ec2", str(counters.ec2)), ("resyntheses_user", str(counters.user)),
                  ("unrealizable", str(counters.unrealizable)), ("negotiations", str(counters.negotiations)),
                  ("resyntheses_negotiated", str(counters.negotiated))]
        violated = self.violated_clauses()
        values += [("violated_clause", c) for c in violated]
        text = mode_text(mode, self.policy, self.recovery, self.controller.aborted)
        level = MODE_LEVELS[mode]
        if mode == Mode.INPUTS_UNKNOWN.value:
            values += [("unknown_input", p) for p in self.controller.unknown]
            text += f"; unknown: {', '.join(self.controller.unknown)}"
            if self.controller.unkeepable:  # (before the start every output was false anyway: a WARN)
                level = ERROR if self.controller.state is not None else WARN
                text += "; no output valuation keeps it for every value: every output false"
        if violated and mode in (Mode.RECOVERING.value, Mode.HOLDING.value, Mode.CHARACTERIZING.value):
            text += "; violated: " + "; ".join(violated)
        if mode == Mode.WAITING_FOR_USER.value and resilient is not None and resilient.explanation is not None:
            explanation = resilient.explanation
            core = [clause_line(c, section) for section, c in explanation.core]
            text += f" ({explanation.kind}{': ' + '; '.join(core) if core else ''})"
            values.append(("explanation", explanation_text(explanation)))
        spec_file = None
        if resilient is not None and resilient.write_error:
            values.append(("write_error", resilient.write_error))
        if resilient is not None and resilient.characterizer.path is not None:
            error = resilient.write_error
            spec_file = Status(ERROR if error else OK, "spec file", error or
                               f"{resilient.characterizer.path}: written after each new strategy",
                               [("path", str(resilient.characterizer.path))])
        text += (f"; resyntheses {counters.resyntheses} (EC1 {counters.ec1}, EC2 {counters.ec2}, "
                 f"user {counters.user}, negotiated {counters.negotiated}); negotiations {counters.negotiations}"
                 if resilient is not None else "")
        changed = mode != self.mode
        self.mode = mode
        return ModeReport(mode, Status(level, "mode", text, values), spec_file, changed,
                          counters_event("mode", counters, mode=mode))

    def unknown_report(self, update: Update, named: str) -> Status:
        """The "input freshness" status after the set of unknown (stale) inputs changed to
        ``update.unknown`` (``named``: them with topic and age, ``runtime.executor.freshness.unknown_text``):
        WARN when the outputs keep rho_s for every value of them, ERROR when no valuation does (every
        output false, the clauses named), OK when every input is fresh again."""
        if not update.unknown:
            if update.started:
                return Status(OK, "input freshness", f"every input has reported; started in state {update.state.id}")
            state = f"; resuming from state {update.state.id}" if update.state is not None else ""
            return Status(OK, "input freshness", f"every input is fresh again{state}")
        values = [("unknown_input", p) for p in update.unknown] + [("outputs", format_valuation(update.outputs))]
        if update.unkeepable:
            clauses = [f"{c.location}: {c.text}" for c in update.unkeepable]
            values += [("unsafe_clause", c) for c in clauses]
            if update.state is None:  # not started: every output was false already (a WARN, not a failure)
                return Status(WARN, "input freshness", f"input(s) unknown: {named}; not starting until they report; "
                              f"no output valuation keeps the system safety for every value of them "
                              f"({'; '.join(clauses)}): every output false", values)
            return Status(ERROR, "input freshness", f"input(s) unknown: {named}; no output valuation keeps the system "
                          f"safety for every value of them ({'; '.join(clauses)}): every output false", values)
        doing = "not stepping" if update.state is not None else "not starting until they report"
        return Status(WARN, "input freshness", f"input(s) unknown: {named}; {doing}, publishing outputs "
                      f"{format_valuation(update.outputs)} (they keep the system safety for every value of them)",
                      values)

    def health(self, waited: float) -> list[Status]:
        """The "inputs" and "controller" statuses, ``waited`` seconds after the node started."""
        controller = self.controller
        missing = [p for p in controller.missing_inputs() if p not in controller.unknown]
        unheard = [p for p in controller.missing_inputs() if p in controller.unknown]
        if missing:
            late = self.ready_timeout > 0 and waited >= self.ready_timeout
            topics = ", ".join(self.input_topics[p] for p in missing)
            inputs = Status(WARN if late else OK, "inputs", f"waiting for input(s) {', '.join(missing)}",
                            [("silent_inputs", " ".join(missing)), ("topics", topics)])
        elif unheard:
            inputs = Status(WARN, "inputs", f"input(s) {', '.join(unheard)} never reported: unknown, outputs safe "
                            "for every value of them", [("unknown_input", p) for p in unheard])
        else:
            inputs = Status(OK, "inputs", "every input has reported", quiet=True)
        if controller.init_error:
            state = Status(ERROR, "controller", f"no initial state: {controller.init_error}")
        elif not controller.running:
            state = Status(OK, "controller", "paused: every output is false")
        elif controller.state is None and unheard and not missing:
            state = Status(WARN, "controller", f"not started: input(s) {', '.join(unheard)} unknown; starting when "
                           "they report")
        elif controller.state is None:
            state = Status(OK, "controller", "waiting for every input to report")
        else:
            s = controller.state
            state = Status(OK, "controller", f"running: state {s.id}, goal {goal_text(s.goal)}",
                           [("state", str(s.id)), ("goal", str(s.goal))], quiet=True)
        return [inputs, state]

    def add_env_liveness(self, formula: str, written_to: str = "") -> Answer:
        """Alg. 3 line 6 (``~add_env_liveness``): check ``formula``, refuse it when the node is not
        waiting for the user (``liveness_refusal``), else resynthesize with it (in the caller's thread,
        not under the controller's lock). ``written_to``: the ``--characterized-spec`` path, if any."""
        resilient = self.resilient
        if resilient is not None:
            try:
                resilient.characterizer.check_liveness(formula)
            except SpecError as err:
                return Answer(False, Exit.BAD_INPUT, str(err), self.current_mode(),
                              ("warn", f"~add_env_liveness {formula!r} refused: {err}"))
        refusal = liveness_refusal(resilient is not None, self.controller.state is not None, self.current_mode())
        if refusal is not None:
            return Answer(False, Exit.NEGATIVE, refusal, self.current_mode())
        try:
            attempt = resilient.add_env_liveness(formula)
        except SpecError as err:
            return Answer(False, Exit.BAD_INPUT, f"{err}", self.current_mode(),
                          ("warn", f"~add_env_liveness {formula!r} refused: {err}"))
        except (ExecutionAborted, Busy) as err:
            return Answer(False, Exit.NEGATIVE, str(err), self.current_mode())
        if attempt is not None and attempt.realizable:
            where = f"; written to {written_to}" if written_to and resilient.write_error is None else ""
            message = f"realizable with {formula!r} ({attempt.variant}); running the new strategy{where}"
            return Answer(True, Exit.OK, message, self.current_mode(), ("info", f"~add_env_liveness: {message}"))
        return Answer(False, Exit.UNREALIZABLE, f"still unrealizable with {formula!r}: aborted, every output is false",
                      self.current_mode())

    def abort_refusal(self) -> str | None:
        """Why ``~abort`` does nothing now (the tool's exit 1): the node already aborted."""
        aborted = self.controller.aborted
        return f"already aborted: {aborted}" if aborted is not None else None

    def silent_inputs(self, waited: float) -> str | None:
        """The ``--ready-timeout`` error line, None when every input has reported."""
        missing = [p for p in self.controller.missing_inputs() if p not in self.controller.unknown]
        if not missing:  # (inputs unknown since the timeout have their own WARN: "input freshness")
            return None
        topics = ", ".join(f"{p} ({self.input_topics[p]})" for p in missing)
        return (f"no message after {waited:.0f} s from input(s) {topics}; not stepping until every input "
                "has reported once — is each input proposition node running?")

    def publishers(self, by_topic: Mapping[str, tuple[str, ...]]) -> tuple[list[str], Status]:
        """Input topics with more than one publisher (thesis 3.5.1: one input proposition node each):
        the warnings to log now (a topic's set of publishers is warned about once) and the status."""
        issued = []
        crowded = []
        for prop, topic in self.input_topics.items():
            nodes = tuple(by_topic.get(topic, ()))
            if len(nodes) > 1:
                crowded.append((prop, topic, nodes))
            if len(nodes) > 1 and self._warned_publishers.get(topic) != nodes:
                issued.append(f"input {prop!r}: topic {topic} has {len(nodes)} publishers ({', '.join(nodes)}); "
                              "an input topic should have exactly one input proposition node (thesis 3.5.1)")
            self._warned_publishers[topic] = nodes
        if crowded:
            text = "; ".join(f"{t} has {len(n)} publishers ({', '.join(n)})" for _, t, n in crowded)
            return issued, Status(WARN, "input publishers", text, [("topic", t) for _, t, _ in crowded],
                                  quiet=not issued)
        return issued, INITIAL_STATUSES[1]
