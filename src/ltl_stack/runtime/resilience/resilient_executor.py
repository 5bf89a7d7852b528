"""Environment characterization inside a running executor: resynthesis off the stepping thread. ROS-free.

``ResilientStrategy`` (``runtime.resilience.characterize``) resynthesizes inside ``step``, so whoever steps it
waits for the synthesizer. The executor node steps in its subscriber callbacks, under the
controller's lock; a resynthesis there would hold every input callback for as long as synthesis
takes. ``BackgroundResilience`` keeps the same monitor, threshold, EC sets and Alg. 2/3 logic, but:

* when characterization is due, ``step`` records the observation, starts one *job* (``runner``,
  a worker thread in the node) and returns the recovery move as usual, so the robot keeps moving
  safely (thesis §4.6) — or, with recovery off, the step raises and the controller holds its
  ``--on-violation`` outputs. ``mode`` is CHARACTERIZING while the job runs. Violations seen meanwhile
  are recorded into both EC sets (they go into the next resynthesis), no second job starts;
* the job renders the spec text under ``lock`` (the EC sets are appended to by the stepping thread),
  parses and synthesizes *outside* it, and installs the result under ``lock``: a stepping callback
  waits at most for the rendering and the installation, never for the synthesizer;
* consistency: the new strategy's init is the observation the job started from (Alg. 2 lines 2-3;
  that is what the written spec says). By the time it is installed the robot may have moved on
  (recovery moves, new readings), so the strategy continues from the *current* position P (the
  latest readings and the current outputs, ``adopt``): from P itself when P is winning for the
  new strategy, also when it is not but recovery is on (recovery moves lead back into W keeping
  the system safety relative to the outputs the robot really has), else (recovery off) from the
  observed initial position, from which the controller steps with the current readings — a
  violation of the new spec there is just the next observation. ``on_installed(state)`` hands the
  state to the controller (under ``lock``);
* a job whose generation is stale (an abort, or a user resynthesis, happened meanwhile) is dropped;
* ``add_env_liveness`` (the ``~add_env_liveness`` service) synthesizes in the caller's thread, also
  outside ``lock``, and refuses while a job runs.

``on_changed()`` is called (under ``lock``) whenever the mode changes outside a step — job done,
waiting for the user, aborted — so the node republishes its state and diagnostics.
"""
from __future__ import annotations

import ctypes
import gc
import threading
import time
from collections.abc import Mapping
from typing import Any, Callable

from ltl_stack.fileio import write_atomic
from ltl_stack.runtime.resilience.characterize import (
    EC1,
    EC2,
    Attempt,
    ExecutionAborted,
    Mode,
    NegotiationAbort,
    Observation,
    ResilientStrategy,
    _Pending,
    characterizing_message,
)
from ltl_stack.runtime.resilience.characterized_english import english_text, is_english
from ltl_stack.spec import SpecError
from ltl_stack.spec.model import Clause
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.errors import NoInitialState, SynthesisError
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.state import State
from ltl_stack.synthesis.strategy import SymbolicStrategy

#: glibc's ``mallopt`` parameter and its default: blocks of at least this many bytes are mmapped
M_MMAP_THRESHOLD, MMAP_THRESHOLD = -3, 128 * 1024
_FIXED_MMAP_THRESHOLD: list[bool] = []


def fix_mmap_threshold() -> bool:
    """Keep glibc's mmap threshold at its default, so that a freed BDD manager's tables go back to
    the system (memory stays bounded under a flood of violations). glibc raises the threshold to the
    largest mmapped block freed (up to 32 MiB); after the first replaced manager every later manager's tables (MiBs) came from the
    heap and, once freed, stayed in the process as fragmented free memory: ``bench_flood.py --trace``
    found 16-19 MiB of freed heap kept after 26-136 resyntheses. Setting the threshold explicitly stops that
    adjustment. Process-wide, once; False where there is no glibc ``mallopt``."""
    if not _FIXED_MMAP_THRESHOLD:
        try:
            done = bool(ctypes.CDLL(None).mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD))
        except (OSError, AttributeError):  # not glibc
            done = False
        _FIXED_MMAP_THRESHOLD.append(done)
    return _FIXED_MMAP_THRESHOLD[0]


#: Runs a job (a callable without arguments) in the background.
Runner = Callable[[Callable[[], None]], None]


def thread_runner(job: Callable[[], None]) -> None:
    """Run ``job`` in a new daemon thread (one at a time: ``BackgroundResilience`` starts no second)."""
    threading.Thread(target=job, name="resynthesis", daemon=True).start()


def is_winning(strategy: SymbolicStrategy, valuation: Mapping[str, bool]) -> bool:
    """Whether the position ``valuation`` (every input and output) is in the strategy's W."""
    game = strategy.game
    bdd = game.bdd
    return bdd.let(game.assignment(dict(valuation)), strategy.winning) == bdd.true


def adopt(strategy: SymbolicStrategy, position: tuple[Mapping[str, bool], Mapping[str, bool]],
          observation: Observation, recovery: bool) -> State:
    """The state a freshly synthesized ``strategy`` continues from (see the module docstring):
    the current ``position`` (inputs, outputs) when it is winning or recovery is on, else the
    observed initial position (Alg. 2 lines 2-3)."""
    inputs = {n: bool(position[0][n]) for n in strategy.inputs}
    outputs = {n: bool(position[1][n]) for n in strategy.outputs}
    if recovery or is_winning(strategy, {**inputs, **outputs}):
        return strategy.start_state(inputs, outputs)
    try:
        return strategy.initial_state(inputs=observation.incoming, outputs=observation.current_outputs)
    except NoInitialState:
        return strategy.start_state(inputs, outputs)


class BackgroundResilience(ResilientStrategy):
    """``ResilientStrategy`` whose resyntheses run in a job (see the module docstring).

    ``lock`` is the controller's (re-entrant) lock (``make_controller`` sets it; None: a new one); ``runner`` starts a job; ``on_installed(state)``
    is called under ``lock`` with the state a new strategy continues from; ``on_changed()`` when the
    mode changed outside a step. Remaining keyword arguments are ``ResilientStrategy``'s.
    """

    def __init__(self, spec: Any, *, lock: Any, runner: Runner = thread_runner,
                 on_installed: Callable[[State], None] | None = None,
                 on_changed: Callable[[], None] | None = None, **kwargs: Any) -> None:
        fix_mmap_threshold()  # before the first synthesis: its manager's tables are mmapped too
        super().__init__(spec, **kwargs)
        self.lock = lock if lock is not None else threading.RLock()
        self.runner = runner
        self.on_installed = on_installed
        self.on_changed = on_changed
        #: the env-safety clauses the latest step's inputs broke (empty: admissible)
        self.violated_now: list[Clause] = []
        #: the clauses of the latest violating step (kept after it, for reports of a brief violation)
        self.last_violated: list[Clause] = []
        #: the latest readings passed to ``step`` (with the current outputs: the position P)
        self.readings: dict[str, bool] = {}
        #: set while a job runs (the observation it started from)
        self.job: Observation | None = None
        #: the last file write that failed (the new strategy runs anyway), or None
        self.write_error: str | None = None
        self._generation = 0

    # --- stepping (under lock, from the controller) ------------------------------------------------
    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> State:
        state = super().initial_state(inputs=inputs, outputs=outputs)
        self.readings = dict(state.inputs)
        return state

    def step(self, state: State, inputs: Mapping[str, bool]) -> State:
        with self.lock:
            self.readings = {n: bool(inputs[n]) for n in self.inputs}
            self.violated_now = self.strategy.game.violated("env_safety", state.valuation, self.readings) \
                if self.mode is not Mode.ABORTED else []
            if self.violated_now:
                self.last_violated = self.violated_now
            try:
                return super().step(state, inputs)
            finally:
                if self.job is not None and self.mode not in (Mode.ABORTED, Mode.WAITING_FOR_USER):
                    self.mode = Mode.CHARACTERIZING

    def _characterize(self, observation: Observation, violated: list[Clause]) -> State | None:
        if self.job is not None:
            self.characterizer.record(observation)  # learned now, part of the next resynthesis
            return None
        self.mode = Mode.CHARACTERIZING
        self._event(characterizing_message(self.threshold.count, violated))
        self.characterizer.record(observation)
        self.job = observation
        self._generation += 1
        generation = self._generation
        self.runner(lambda: self._job(observation, generation))
        return None

    def poll(self) -> bool:
        """Start characterization when a violation has lasted past the threshold's seconds, or past
        the handover after a negotiation, without a step (the node calls this from a timer: event
        driven, nothing else steps while the inputs stay the same). True when a job was started."""
        with self.lock:
            threshold = self.threshold
            if (self.job is not None or not self.characterize_enabled or self._state is None
                    or self.mode in (Mode.WAITING_FOR_USER, Mode.ABORTED)):
                return False
            late = self._handover is not None and bool(self.violated_now) and self._handover_over()
            due = (threshold.since is not None and threshold.seconds is not None
                   and threshold.clock() - threshold.since > threshold.seconds)
            if not (late or due):
                return False
            if late:
                self._event(f"the handover after the negotiated adoption is over ({self.HANDOVER_SECONDS:g} s) and "
                            "the violation still stands: the peer has not kept its promise")
            self._handover = None
            state = self._state
            observation = Observation(self.steps, self.wall_clock(), dict(state.inputs), dict(state.outputs),
                                      dict(self.readings))
            self._characterize(observation, self.violated_now)
            return True

    # --- the job (a worker thread) ---------------------------------------------------------------
    def _job(self, observation: Observation, generation: int) -> None:
        try:
            self._run_job(observation, generation)
        finally:
            # the replaced strategy's BDD manager sits in reference cycles: free it now, in this
            # thread (not under the lock), so that managers do not pile up between collections
            gc.collect()

    def _run_job(self, observation: Observation, generation: int) -> None:
        try:
            attempt = self._synthesize(EC1, observation)
            if not attempt.realizable:
                attempt = self._synthesize(EC2, observation)
            if attempt.realizable:
                self._finish(generation, lambda: self._accept(attempt, observation))
                return
            if self.negotiate is not None:  # S.2 (Alg. 3 line 9, §4.8): a collaborative robot
                self._finish(generation, lambda: self._count_unrealizable(observation))
                try:
                    spec = self.negotiate(self, observation)
                except NegotiationAbort as ended:
                    reason = f"unrealizable after environment characterization and negotiation: {ended}"
                    self._finish(generation, lambda: self.abort(reason), always=True)
                    return
                result = synthesize(spec, **self.characterizer.synthesis_options) if spec is not None else None
                if result is not None and result.realizable:
                    text = self.characterizer.text(None, observation)
                    agreed = Attempt(True, "negotiation", spec, text, result.strategy, 0.0)
                    self._finish(generation, lambda: self._accept(agreed, observation, write=False))
                    return
                if spec is not None:
                    self._finish(generation, lambda: self.abort("the negotiated specification is unrealizable"),
                                 always=True)
                    return
                # negotiation does not apply (no peer involved, absent or silent, already negotiated):
                # S.1, the peer is uncontrollable environment (§4.4)
                with self.lock:
                    self._event("no collaborative robot to negotiate with (none involved, absent or silent, or "
                                "already negotiated): S.1")
                counted = True
            else:
                counted = False
            explanation = explain(attempt.spec, robotics_semantics=self.characterizer.synthesis_options.get(
                "robotics_semantics", True))
            self._finish(generation, lambda: self._wait_for_user(observation, explanation, counted))
        except Exception as err:  # noqa: BLE001 - a failed job must not end the thread silently
            failure = err
            self._finish(generation, lambda: self._failed(failure), always=True)

    def _synthesize(self, variant: str, observation: Observation) -> Attempt:
        with self.lock:  # the stepping thread appends to the EC sets
            text = self.characterizer.text(variant, observation)
        spec = self.characterizer.parse(text)
        start = time.perf_counter()
        result = synthesize(spec, **self.characterizer.synthesis_options)
        attempt = Attempt(result.realizable, variant, spec, text, result.strategy, time.perf_counter() - start)
        with self.lock:
            self.characterizer.history.append(attempt)
        return attempt

    def _finish(self, generation: int, action: Callable[[], None], always: bool = False) -> None:
        with self.lock:
            if generation != self._generation or (self.mode is Mode.ABORTED and not always):
                return  # stale: aborted or replaced meanwhile
            self.job = None
            action()
            if self.on_changed is not None:
                self.on_changed()

    def _count_unrealizable(self, observation: Observation) -> None:
        self.counters.unrealizable += 1
        self.job = observation  # still busy: negotiating

    def _accept(self, attempt: Attempt, observation: Observation, write: bool = True,
                liveness: list[str] = ()) -> None:
        self.job = None
        self.write_error = None
        if write:
            self._keep(attempt, observation, list(liveness))
        self.counters.new_strategy("user" if liveness else attempt.variant)
        self.threshold.reset()
        if attempt.variant == "negotiation":  # this robot initiated it (a responder adopts with ``adopt``)
            self._begin_handover(self.readings)
        strategy = self._switch_to(attempt)
        current = self._state
        position = ({**(current.inputs if current else {}), **self.readings}, current.outputs if current else {})
        state = adopt(strategy, position, observation, self.recovery)
        self._state = state
        self.violated_now = []
        self._event(f"resynthesized with {attempt.variant} in {attempt.seconds * 1000:.1f} ms; continuing "
                    f"from state {state.id}")
        if self.on_installed is not None:
            self.on_installed(state)

    def _keep(self, attempt: Attempt, observation: Observation, liveness: list[str]) -> None:
        """``Characterizer.accept``'s bookkeeping, then the file: the user's Structured English with
        the learned sentences when the running spec and the file are English and that says exactly
        what runs (``characterized_english``), else the structured text that runs."""
        ch = self.characterizer
        ch.variant = attempt.variant if attempt.variant in (EC1, EC2) else ch.variant
        ch.observation = observation
        for text in liveness:
            ch.user_liveness.append((text, time.time()))
        if ch.path is None:
            return
        text = attempt.text
        if is_english(ch.path):
            variant = attempt.variant if attempt.variant in (EC1, EC2) else None
            english, why = english_text(ch, variant, observation, attempt.spec, ch.user_liveness)
            if english is not None:
                text = english
            else:
                text = f"# Written in the structured format, not in English: {why}.\n" + text
                self._event(f"{ch.path}: structured format, not English: {why}")
        try:
            write_atomic(ch.path, text)
        except OSError as err:  # keep the robot running; say what was not kept
            self.write_error = f"cannot write {ch.path}: {err.strerror or err}"
            self._event(self.write_error)

    def _wait_for_user(self, observation: Observation, explanation: Any, counted: bool = False) -> None:
        if not counted:
            self.counters.unrealizable += 1
        self.explanation = explanation
        self._pending = _Pending(observation, explanation)
        self.mode = Mode.WAITING_FOR_USER
        self._event("unrealizable with EC1 and EC2; waiting for the user's env liveness "
                    "(add_env_liveness) or abort")

    def _failed(self, err: Exception) -> None:
        self.job = None
        self.mode = Mode.WAITING_FOR_USER
        self._event(f"resynthesis failed: {type(err).__name__}: {err}; waiting for the user (add_env_liveness "
                    "or abort)")

    # --- the user (any thread) ------------------------------------------------------------------
    def add_env_liveness(self, texts: list[str] | str) -> Attempt:
        """Alg. 3 lines 6-7 without holding ``lock`` during synthesis. Raises ``SpecError`` for a
        formula that does not parse (nothing changes), ``ExecutionAborted`` once aborted,
        ``Busy`` while a characterization job runs. Unrealizable: aborts (Alg. 3 line 11)."""
        texts = [texts] if isinstance(texts, str) else list(texts)
        for text in texts:
            self.characterizer.check_liveness(text)
        with self.lock:
            if self.mode is Mode.ABORTED:
                raise ExecutionAborted(self._abort_reason)
            if self.job is not None:
                raise Busy("a resynthesis is running; try again when it is done")
            if self._state is None:
                raise NotReady("not ready: the controller has not started yet (waiting for every input to report)")
            state = self._state
            readings = {**(state.inputs if state else {}), **self.readings}
            observation = Observation(self.steps, self.wall_clock(), dict(state.inputs) if state else {},
                                      dict(state.outputs) if state else {}, readings)
            self._generation += 1
            generation = self._generation
            self.job = observation
            previous = self.mode
            self.mode = Mode.CHARACTERIZING
            variants = (EC1, EC2) if self.characterizer.ec1 else (None,)
        attempt = None
        try:
            for variant in variants:
                with self.lock:
                    text = self.characterizer.text(variant, observation, texts)
                spec = self.characterizer.parse(text)
                start = time.perf_counter()
                result = synthesize(spec, **self.characterizer.synthesis_options)
                attempt = Attempt(result.realizable, variant or "user", spec, text, result.strategy,
                                  time.perf_counter() - start)
                if attempt.realizable:
                    break
        except Exception:
            with self.lock:
                if generation == self._generation:
                    self.job = None
                    self.mode = previous
            raise
        with self.lock:
            if generation != self._generation:
                raise ExecutionAborted(getattr(self, "_abort_reason", "replaced while resynthesizing"))
            self.job = None
            if attempt.realizable:
                self._accept(attempt, observation, liveness=texts)
                self._event(f"user env liveness {'; '.join(texts)}: realizable ({attempt.variant}); continuing")
            else:
                self.mode = previous
                self.abort(f"still unrealizable with the user's env liveness {'; '.join(texts)}")
            if self.on_changed is not None:
                self.on_changed()
        return attempt

    def adopt(self, spec: Any, text: str, strategy: SymbolicStrategy, inputs: Mapping[str, bool],
              outputs: Mapping[str, bool], write: bool = True) -> State:
        """``ResilientStrategy.adopt`` (a spec agreed by negotiation, installed by the responder) under
        ``lock``; a running job's result is dropped."""
        with self.lock:
            self._generation += 1
            self.job = None
            self.write_error = None
            try:
                state = super().adopt(spec, text, strategy, inputs, outputs, write=write)
            except OSError as err:  # written after the agreement (no two-phase staging): say so, run it
                self.write_error = f"cannot write {self.characterizer.path}: {err.strerror or err}"
                state = super().adopt(spec, text, strategy, inputs, outputs, write=False)
            self.readings = dict(state.inputs)
            self.violated_now = []
            if self.on_changed is not None:
                self.on_changed()
            return state

    def install_negotiated(self, spec: Any, text: str, strategy: SymbolicStrategy, inputs: Mapping[str, bool],
                           outputs: Mapping[str, bool], write: bool = True) -> State | None:
        """``ResilientStrategy.install_negotiated``; the state goes to ``on_installed`` (the node
        continues with the current readings and publishes), when there is one."""
        with self.lock:
            state = self.adopt(spec, text, strategy, inputs, outputs, write=write)
            if self.on_installed is None:
                return state
            self.on_installed(state)
            return None

    def abort(self, reason: str = "aborted by the user") -> None:
        """Abort (Alg. 3 line 11); a running job's result is dropped."""
        with self.lock:
            self._generation += 1
            self.job = None
            super().abort(reason)
            if self.on_changed is not None:
                self.on_changed()


class Busy(SynthesisError):
    """A user request arrived while a resynthesis job runs."""


class NotReady(Busy):
    """A user request arrived before the controller started (no position to resynthesize from)."""


__all__ = ["BackgroundResilience", "Busy", "NotReady", "SpecError", "adopt", "fix_mmap_threshold", "is_winning",
           "thread_runner"]
