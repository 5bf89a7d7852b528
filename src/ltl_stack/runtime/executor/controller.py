"""A running synthesized controller, free of ROS: the logic of the controller node (thesis §3.5.1).

The ``Controller`` owns a strategy (anything with ``inputs``, ``outputs``, ``initial_state(inputs=,
outputs=)`` and ``step(state, inputs)``, such as ``ltl_stack.synthesis.SymbolicStrategy`` or
``ltl_stack.runtime.executor.explicit.AutomatonStrategy``), the current state, the latest input readings,
and the run/pause switch. It is event driven: a reading that changes the input valuation steps the
strategy at once; a repeated reading does nothing.

* Settling: after a step the strategy may still want to move with the same inputs (head for the
  next region, start the next action). Event driven, nothing would change the inputs to trigger
  that move, so the controller keeps stepping with unchanged readings — moves the environment's
  "nothing happened" allows — until the state stops changing, at most ``settle_steps`` times.
  Only the final state's outputs are published: the intermediate ones took no time. The states
  passed on the way are in the Update (``passed``), so that a record of the run (the executor's
  ``~state``) holds every state the strategy went through, and the goals met there count.
* Ready handshake: nothing is stepped before every input has reported once (``missing_inputs``).
* Pause: while paused every output is false and nothing is stepped; on resume the strategy steps
  from its last state with the current readings.
* Environment-assumption violation: the strategy raises ``AssumptionViolation``; the controller keeps
  its last state, remembers the violation, and — by ``on_violation`` — holds the last outputs or drives
  all outputs false. Each later change of the readings is tried again from the last state, so the
  controller resumes on its own once the inputs are admissible again. A ``recovery`` callable
  (``ltl_stack.runtime.executor.recovery.RecoveringStrategy.recover``, thesis §4.6) may return a state to
  continue from instead: the controller takes it like a step (the Update says ``recovered``, the
  outputs are the new state's, no policy applies); None means no recovery, and the policy applies.

* Lemma 1(a) (thesis ch. 4): a ``guard`` (``ltl_stack.runtime.executor.output_guard.OutputGuard``, installed by
  ``make_controller``) turns the policy's valuation into one that keeps the system safety rho_s for
  the move the world sees: from the position last *published* (the readings then and the outputs
  published then, which differ from the last state's after an earlier policy valuation) to the
  current readings. Guarantees that tie consecutive outputs (``stop -> brake'``) are thereby kept
  across holds too. Hold keeps the last state's outputs if they keep rho_s, else the nearest safe
  valuation; all-false the safe valuation with the fewest outputs true. ``unkeepable`` names the
  rho_s clauses when none exists (the policy's valuation is then published as it is, and the
  Update carries them).

* Unknown inputs (``set_unknown``): inputs whose last reading is older than their freshness bound
  (``runtime.executor.freshness``; a partition, a dead sensor), or, before the start, inputs never heard of
  that the node stopped waiting for (a peer's host down when the robot starts): the outputs until
  they report keep ``[SYS_INIT]`` for every value of them, and the strategy starts when they have. Nothing is stepped while there are any (a step
  would take a stale reading for the truth); the outputs are those nearest to the ones published
  that keep rho_s for *every* value of the unknown inputs (the guard, from the position last
  published), else every output false with ``unkeepable`` naming the clauses. When every input is
  fresh again the strategy steps from its last state with the current readings (like a tick): the
  execution resumes where it was, no restart.

* Abort (``abort``; thesis Alg. 3 line 11, the executor's ``~abort``): every output false, nothing
  stepped any more; the node stays up. ``restart_from(state)`` continues from a state of a strategy
  that was put in place meanwhile (environment characterization, ``runtime.resilience.resilient_executor``).

Every method takes ``lock`` (re-entrant), and callers that publish the result should hold it too, so
that the order of published outputs is the order of the steps.
"""
from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Protocol

from ltl_stack.compat import StrEnum
from ltl_stack.synthesis.errors import AssumptionViolation, NoInitialState


class ViolationPolicy(StrEnum):
    """What the outputs do after an environment-assumption violation."""

    HOLD = "hold"            # keep the last safe outputs
    ALL_FALSE = "all-false"  # drive every output false


HOLD = ViolationPolicy.HOLD
ALL_FALSE = ViolationPolicy.ALL_FALSE
#: the policies' names, as flags and parameters spell them
VIOLATION_POLICIES = tuple(p.value for p in ViolationPolicy)


class StrategyLike(Protocol):
    inputs: list[str]
    outputs: list[str]

    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> Any: ...

    def step(self, state: Any, inputs: Mapping[str, bool]) -> Any: ...


Recovery = Callable[["Controller", AssumptionViolation], Any]
#: (position published last: every input and output, readings, the policy's outputs) -> an object
#: with ``outputs`` and ``unkeepable``
Guard = Callable[[Mapping[str, bool], Mapping[str, bool], Mapping[str, bool]], Any]


@dataclass(frozen=True)
class Update:
    """The outcome of one call, for the adapter to publish and log.

    ``outputs`` is the valuation the output topics must carry now. ``stepped`` says a new state was
    taken (``started`` when it is the initial one); ``violation`` is set when the readings broke an
    environment assumption on this call (``recovered`` when the recovery hook stepped past it);
    ``error`` holds a message when no initial state matched.
    """

    outputs: dict[str, bool]
    state: Any = None
    stepped: bool = False
    started: bool = False
    violation: AssumptionViolation | None = None
    recovered: bool = False
    error: str | None = None
    changed_outputs: dict[str, bool] = field(default_factory=dict)
    #: the rho_s clauses no output valuation keeps while a policy applies (then ``outputs`` break them)
    unkeepable: list = field(default_factory=list)
    #: the inputs unknown now (stale), in spec order
    unknown: list = field(default_factory=list)
    #: the states settling went through before ``state``, in order (their outputs were not published)
    passed: tuple = ()


class Controller:
    """Steps a strategy on input changes, with the ready handshake, pause and violation policy."""

    def __init__(self, strategy: StrategyLike, *, on_violation: ViolationPolicy | str = HOLD,
                 init_props: Mapping[str, bool] | None = None, running: bool = True,
                 recovery: Recovery | None = None, settle_steps: int = 16, guard: Guard | None = None) -> None:
        if on_violation not in VIOLATION_POLICIES:
            raise ValueError(f"on_violation must be one of {', '.join(VIOLATION_POLICIES)}, got {on_violation!r}")
        on_violation = ViolationPolicy(on_violation)
        self.strategy = strategy
        self.inputs = list(strategy.inputs)
        self.outputs = list(strategy.outputs)
        init_props = dict(init_props or {})
        unknown = [p for p in init_props if p not in self.inputs and p not in self.outputs]
        if unknown:
            raise ValueError(f"--init-props names unknown proposition(s) {', '.join(unknown)} "
                             f"(inputs: {', '.join(self.inputs) or 'none'}; outputs: {', '.join(self.outputs) or 'none'})")
        self.on_violation = on_violation
        self.recovery = recovery
        self.guard = guard
        #: the rho_s clauses the last policy valuation could not keep (empty: it kept them)
        self.unkeepable: list = []
        if not isinstance(settle_steps, int) or isinstance(settle_steps, bool) or settle_steps < 0:
            raise ValueError(f"settle_steps must be an integer >= 0, got {settle_steps!r}")
        self.settle_steps = settle_steps
        self.lock = threading.RLock()
        self.state: Any = None
        self.running = running
        self.violation: AssumptionViolation | None = None
        self.init_error: str | None = None
        #: why the execution was aborted (None while it runs)
        self.aborted: str | None = None
        self.init_outputs = {p: v for p, v in init_props.items() if p in self.outputs}
        # Inputs given in init_props count as readings until their topic says otherwise.
        self._readings: dict[str, bool] = {p: v for p, v in init_props.items() if p in self.inputs}
        #: inputs whose reading is stale (``set_unknown``), in spec order
        self.unknown: list[str] = []
        self._published: dict[str, bool] | None = None
        #: the positions (readings and outputs) of the last two distinct publications, oldest first:
        #: a policy valuation is a move from the latest one; re-asked (``current_outputs``) with the
        #: same readings, it is the same move, from the one before
        self._moves: tuple[dict[str, bool] | None, dict[str, bool] | None] = (None, None)

    # --- what the adapter reads -------------------------------------------------------------
    @property
    def readings(self) -> dict[str, bool]:
        """The latest reading of every input that has reported, in spec order."""
        with self.lock:
            return {p: self._readings[p] for p in self.inputs if p in self._readings}

    def missing_inputs(self) -> list[str]:
        """Inputs that have not reported yet (the ready handshake waits for them)."""
        with self.lock:
            return [p for p in self.inputs if p not in self._readings]

    @property
    def ready(self) -> bool:
        return not self.missing_inputs()

    @property
    def started(self) -> bool:
        return self.state is not None

    def current_outputs(self) -> dict[str, bool]:
        """The output valuation to publish: all false while paused, before the start or once aborted;
        on a violation the policy's valuation (through ``guard``: the nearest one keeping rho_s from
        the position last published); otherwise the current state's outputs."""
        with self.lock:
            before, last = self._moves
            same = last is not None and all(last.get(p) == v for p, v in self.readings.items())
            return self._outputs_from(before if same else last)

    def _outputs_from(self, published: Mapping[str, bool] | None) -> dict[str, bool]:
        """``current_outputs`` for a move from the position ``published`` (None: the last state's)."""
        with self.lock:
            self.unkeepable = []
            if not self.running or self.aborted is not None:
                return dict.fromkeys(self.outputs, False)
            if self.state is None:
                return self._initial_for_unknown() if self.unknown else dict.fromkeys(self.outputs, False)
            last = {p: bool(self.state.outputs[p]) for p in self.outputs}
            if self.unknown and self.guard is not None:
                return self._outputs_for_unknown(published, last)
            if self.violation is None:
                return last
            wanted = dict.fromkeys(self.outputs, False) if self.on_violation == ALL_FALSE else last
            if self.guard is None:
                return wanted
            position = {**self.state.inputs, **self.state.outputs, **(published or {})}
            guarded = self.guard(position, self.readings, wanted)
            self.unkeepable = list(guarded.unkeepable)
            return dict(guarded.outputs)

    def _outputs_for_unknown(self, published: Mapping[str, bool] | None, last: dict[str, bool]) -> dict[str, bool]:
        """The outputs nearest to those published (else the last state's) keeping rho_s for every
        value of the unknown inputs; every output false when none does (``unkeepable`` says why)."""
        position = {**self.state.inputs, **self.state.outputs, **(published or {})}
        wanted = {p: bool(position.get(p, last[p])) for p in self.outputs}
        guarded = self.guard(position, self.readings, wanted, unknown=self.unknown)
        if guarded.unkeepable:
            self.unkeepable = list(guarded.unkeepable)
            return dict.fromkeys(self.outputs, False)
        return dict(guarded.outputs)

    def _initial_for_unknown(self) -> dict[str, bool]:
        """Before the start, with never-heard inputs unknown: the outputs nearest to all false (or
        ``init_props``' outputs) that keep ``[SYS_INIT]`` for every value of them; all false when
        none does (``unkeepable`` says why)."""
        wanted = {p: bool(self.init_outputs.get(p, False)) for p in self.outputs}
        initial = getattr(self.guard, "initial", None)
        if initial is None:
            return dict.fromkeys(self.outputs, False)
        guarded = initial(self.readings, wanted, self.unknown)
        if guarded.unkeepable:
            self.unkeepable = list(guarded.unkeepable)
            return dict.fromkeys(self.outputs, False)
        return dict(guarded.outputs)

    # --- what the adapter calls -------------------------------------------------------------
    def report(self, prop: str, value: bool) -> Update:
        """Record one input reading; step when it changes the input valuation."""
        return self.report_many({prop: value})

    def report_many(self, values: Mapping[str, bool]) -> Update:
        """Record several input readings at once (one step at most)."""
        with self.lock:
            return self._advance(force=False) if self.record(values) else self._result()

    def record(self, values: Mapping[str, bool]) -> bool:
        """Record input readings without stepping (``advance`` steps later); True if one changed."""
        with self.lock:
            changed = False
            for prop, value in values.items():
                if prop not in self.inputs:
                    raise ValueError(f"{prop!r} is not an input of the strategy (inputs: {', '.join(self.inputs)})")
                if self._readings.get(prop) is not bool(value):
                    self._readings[prop] = bool(value)
                    changed = True
            return changed

    def advance(self) -> Update:
        """Start or step if the readings call for it (e.g. when ``init_props`` already made it ready)."""
        with self.lock:
            return self._advance(force=False)

    def tick(self) -> Update:
        """Step even though no reading changed (the optional fixed-rate stepping)."""
        with self.lock:
            return self._advance(force=True)

    def set_running(self, running: bool) -> Update:
        """Run or pause. Pausing drives every output false; running resumes from the last state."""
        with self.lock:
            was = self.running
            self.running = bool(running)
            if self.running and not was:
                return self._advance(force=False)
            return self._result()

    def abort(self, reason: str) -> Update:
        """Stop for good (Alg. 3 line 11): every output false from now on, no more steps."""
        with self.lock:
            self.aborted = reason
            return self._result()

    def set_unknown(self, props: Any) -> Update:
        """Mark the inputs ``props`` unknown (stale, or never heard of) and every other one known.
        While any is unknown nothing is stepped; when the last one is known again, step from the last
        state with the current readings (``tick``), as if the execution had never stopped — or, before
        the start, start once every input has reported (preferring an initial state with the outputs
        published meanwhile, which the robot already has)."""
        with self.lock:
            unknown = [p for p in self.inputs if p in set(props)]
            if unknown == self.unknown:
                return self._result()
            self.unknown = unknown
            if unknown:
                return self._result()
            return self._advance(force=self.state is not None)

    def restart_from(self, state: Any) -> Update:
        """Continue from ``state`` (of a strategy just put in place): step once with the current
        readings and settle, like a tick. Nothing happens once aborted or before the start."""
        with self.lock:
            if self.aborted is not None or self.state is None:
                return self._result()
            self.state = state
            self.violation = None
            return self._advance(force=True)

    def outputs_published(self) -> dict[str, bool] | None:
        """The valuation the last ``Update`` told the adapter to publish (None before the first)."""
        return self._published

    # --- internals ---------------------------------------------------------------------------
    def _advance(self, force: bool) -> Update:
        if not self.running or not self.ready or self.aborted is not None or self.unknown:
            return self._result()
        readings = self.readings
        if self.state is None:
            try:
                self.state = self._initial_state(readings)
            except NoInitialState as err:
                self.init_error = str(err)
                return self._result(error=self.init_error)
            self.init_error = None
            return self._result(stepped=True, started=True, passed=self._settle(readings))
        if not force and self.violation is None and readings == _valuation(self.state.inputs, self.inputs):
            return self._result()
        try:
            new_state = self.strategy.step(self.state, readings)
        except AssumptionViolation as violation:
            self.violation = violation
            recovered = self.recovery(self, violation) if self.recovery is not None else None
            if recovered is None:
                return self._result(violation=violation)
            self.violation = None
            self.state = recovered
            passed = self._settle(readings)
            return self._result(stepped=True, violation=violation, recovered=True, passed=passed)
        self.violation = None
        self.state = new_state
        return self._result(stepped=True, passed=self._settle(readings))

    def _initial_state(self, readings: dict[str, bool]) -> Any:
        """The strategy's initial state for ``readings``: one whose outputs are those published while
        inputs were unknown before the start, when the strategy has one; else as ``init_props`` say."""
        published = self._published
        if published is not None and any(published.values()):
            try:
                return self.strategy.initial_state(inputs=readings, outputs=published)
            except NoInitialState:
                pass
        return self.strategy.initial_state(inputs=readings, outputs=self.init_outputs or None)

    def _settle(self, readings: dict[str, bool]) -> tuple:
        """Step with unchanged readings while the state changes (at most ``settle_steps`` times);
        return the states left on the way."""
        passed = []
        for _ in range(self.settle_steps):
            try:
                following = self.strategy.step(self.state, readings)
            except AssumptionViolation:
                break  # the environment may not stay still here: wait for it to move
            if type(following) is type(self.state) and following.id == self.state.id:
                break  # (a recovered state may be symbolic, its ids another numbering)
            passed.append(self.state)
            self.state = following
        return tuple(passed)

    def _result(self, **kwargs: Any) -> Update:
        outputs = self._outputs_from(self._moves[1])
        position = {**self.readings, **outputs}
        if position != self._moves[1]:
            self._moves = (self._moves[1], position)
        before = self._published or {}
        changed = {p: v for p, v in outputs.items() if self._published is None or before.get(p) != v}
        self._published = outputs
        return Update(outputs=outputs, state=self.state, changed_outputs=changed, unkeepable=list(self.unkeepable),
                      unknown=list(self.unknown), **kwargs)


def _valuation(values: Mapping[str, bool], names: list[str]) -> dict[str, bool]:
    return {p: bool(values[p]) for p in names if p in values}
