"""What the controller view shows, without Qt or ROS: the explicit automaton of the executor's spec and
where the executor is in it.

The automaton is synthesized with the options the executor runs with (robotics init semantics and
the cooperative strategy unless told otherwise) and extracted as ``synthesize --dot/--strategy-json`` export it,
so the ids in the view are the ids of those files. A ``ControllerState`` message is located in that
automaton by its ``state_id`` (an explicit id, or a symbolic ``State.id`` decoded to its valuation and
goal) and, failing that, by its valuation and goal (``Automaton.find``: unique in the automaton).
Small automata are drawn whole; large ones as the neighbourhood of the current state.
``Latest`` hands the newest message from ROS's thread to the GUI's timer, so a view that redraws
less often than states arrive never falls behind: it skips to the newest.
"""
from __future__ import annotations

import os
import tempfile
import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field

from ltl_stack.errors import Exit, UserError
from ltl_stack.gui.dotgraph import DotGraph
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.executor.running_spec import RunningSpec, read_spec
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import Automaton, synthesize
from ltl_stack.synthesis.automaton import AutomatonState, goal_text

CURRENT_COLOR = "#ff9a00"
GOAL_COLOR = "#3a7bd5"
INITIAL_COLOR = "#2e9e44"
DEFAULT_FULL_LIMIT = 40
DEFAULT_RADIUS = 2
#: the most edges a readable picture has: beyond it Graphviz's labels and splines overlap (looked at on
#: alice, 30 states and 232 edges: a tangle) and the layout takes seconds; edges past it are counted
MAX_DRAWN_EDGES = 80
MAX_STATES = 200_000


@dataclass(frozen=True)
class StateUpdate:
    """One ``ControllerState`` message as the view needs it."""

    state_id: int
    goal: int
    inputs: dict[str, bool]
    outputs: dict[str, bool]
    running: bool
    stamp: float = 0.0  # seconds (the message's header stamp)
    # resilient execution (thesis ch. 4): the executor's mode, counters and the clauses broken now
    mode: str = ""
    violations: int = 0
    recovery_steps: int = 0
    unsafe_steps: int = 0
    resyntheses: int = 0
    negotiations: int = 0  # negotiations held with a collaborative robot (thesis §4.8)
    negotiated: int = 0  # new strategies adopted from one (also in resyntheses)
    violated_clauses: tuple[str, ...] = ()
    spec_file: str = ""  # the spec of the running strategy (original, characterized or adopted)
    generation: int = 0  # 0: the start-up strategy; +1 per strategy put in place


@dataclass
class ViewOptions:
    robotics_semantics: bool = True
    cooperative: bool = True
    full_limit: int = DEFAULT_FULL_LIMIT  # draw every state up to this many, else a neighbourhood
    radius: int = DEFAULT_RADIUS


@dataclass
class ControllerModel:
    """The spec's explicit automaton and the state the executor was last seen in."""

    spec_path: str
    automaton: Automaton
    options: ViewOptions = field(default_factory=ViewOptions)
    current: int | None = None
    last: StateUpdate | None = None
    generation: int = 0  # the executor's strategy generation this automaton is of
    source: ExecutorSource | None = None  # what the executor said it runs (None: it did not say)
    _pred: dict[int, list[int]] = field(default_factory=dict)
    _edges: int | None = None

    @classmethod
    def synthesize(cls, spec_path: str, options: ViewOptions | None = None,
                   progress: Callable[[str], None] | None = None) -> ControllerModel:
        """Synthesize ``spec_path`` as the executor does and extract the explicit automaton, in this
        process (the view runs ``synthesize_automaton`` in its worker process: ``gui.worker_process``).

        Raises ``SpecError`` for a bad spec, ``UserError`` (shown, no traceback) when it is unrealizable, ``TooManyStates``
        beyond ``MAX_STATES``.
        """
        options = options or ViewOptions()
        return cls.indexed(str(spec_path), synthesize_automaton(spec_path, options, progress), options)

    @classmethod
    def assemble(cls, spec_path: str, options: ViewOptions, parts: Iterable[tuple]) -> ControllerModel:
        """The model of an automaton sent in parts (``automaton_parts``)."""
        return cls.indexed(str(spec_path), assemble_automaton(parts), options)

    @classmethod
    def indexed(cls, spec_path: str, automaton: Automaton, options: ViewOptions) -> ControllerModel:
        model = cls(spec_path, automaton, options)
        model.predecessors(0)  # the indexes the view needs, made here on the worker thread, not the GUI's
        model.edge_count()
        return model

    def predecessors(self, state: int) -> list[int]:
        if not self._pred:
            for s in self.automaton.states:
                for t in s.successors:
                    self._pred.setdefault(t, []).append(s.id)
        return self._pred.get(state, [])

    def locate(self, update: StateUpdate) -> int | None:
        """The automaton id of the executor's state, or None (before the start, or not in it).

        The message's inputs are the executor's current readings, which differ from its state's while
        a change is on its way (leaving one region before entering the next) or while it is paused, so
        the state is found from ``state_id`` first: an id of the explicit automaton (what the executor
        publishes when it has extracted it) with the same goal and, while running, the same outputs;
        else a symbolic ``State.id`` (valuation bits plus goal), decoded; else the message's valuation.
        """
        if update.state_id < 0 or update.goal < 0:
            return None
        a = self.automaton
        sid = update.state_id
        if sid < len(a):
            s = a.states[sid]
            if s.goal == update.goal and (not update.running or all(
                    bool(update.outputs.get(n, False)) == s.outputs[n] for n in a.outputs)):
                return sid
        n = len(a.inputs) + len(a.outputs)
        if sid >> n == update.goal:
            bits = [bool(sid >> k & 1) for k in range(n)]
            found = a.find(dict(zip(a.inputs, bits)),
                           dict(zip(a.outputs, bits[len(a.inputs):])), update.goal)
            if found is not None:
                return found.id
        if any(p not in update.inputs for p in a.inputs) or any(p not in update.outputs for p in a.outputs):
            return None
        state = a.find(update.inputs, update.outputs, update.goal)
        return None if state is None else state.id

    def follow(self, update: StateUpdate) -> int | None:
        self.last = update
        self.current = self.locate(update)
        return self.current

    @property
    def whole(self) -> bool:
        """Drawn whole only when readable: few states and few edges (``MAX_DRAWN_EDGES``)."""
        a = self.automaton
        return len(a) <= self.options.full_limit and self.edge_count() <= MAX_DRAWN_EDGES

    def edge_count(self) -> int:
        if self._edges is None:
            self._edges = sum(len(s.successors) for s in self.automaton.states)
        return self._edges

    def shown_states(self, center: int | None = None) -> list[int]:
        """Every state when the automaton is small, else the states within ``radius`` steps of
        ``center`` (forwards and backwards; the initial states when there is no centre yet)."""
        a = self.automaton
        if self.whole:
            return [s.id for s in a.states]
        # no centre yet: one initial state (an automaton may have thousands, one per input valuation)
        starts = [center] if center is not None else list(a.initial[:1]) or [0]
        seen = dict.fromkeys(starts, 0)
        queue = deque(starts)
        limit = max(self.options.full_limit, 1)
        while queue and len(seen) < limit:
            s = queue.popleft()
            if seen[s] >= self.options.radius:
                continue
            for t in (*a.states[s].successors, *self.predecessors(s)):
                if t not in seen and len(seen) < limit:
                    seen[t] = seen[s] + 1
                    queue.append(t)
        return sorted(seen)

    def graph(self, center: int | None = None) -> DotGraph:
        """The states to draw (labels as ``Automaton.to_dot``: id, goal, true outputs; edges: true inputs),
        at most ``MAX_DRAWN_EDGES`` edges (the centre's first); each state says how many of its edges
        are not drawn."""
        a = self.automaton
        shown = self.shown_states(center)
        inside = set(shown)
        initial = set(a.initial)
        edges = [(sid, t) for sid in sorted(shown, key=lambda x: x != center)
                 for t in a.states[sid].successors if t in inside][:MAX_DRAWN_EDGES]
        degree = dict.fromkeys(shown, 0)
        for sid, t in edges:
            degree[sid] += 1
            if t != sid:
                degree[t] += 1
        g = DotGraph(name="controller", rankdir="LR")
        for sid in shown:
            s = a.states[sid]
            outs = ", ".join(n for n in a.outputs if s.outputs[n]) or "-"
            total = len(s.successors) + len(self.predecessors(sid)) - s.successors.count(sid)
            cut = total - degree[sid]
            more = f"\n(+{cut} edges)" if cut > 0 else ""
            g.add_node(sid, f"{sid} (goal {goal_text(s.goal)})\n{outs}{more}", shape="box",
                       color=INITIAL_COLOR if sid in initial else "black",
                       tooltip=f"state {sid}, goal {goal_text(s.goal)}; inputs: "
                               + (", ".join(n for n in a.inputs if s.inputs[n]) or "-") + f"; outputs: {outs}")
        for sid, t in edges:
            g.add_edge(sid, t, ", ".join(n for n in a.inputs if a.states[t].inputs[n]) or "-")
        return g

    def needs_new_layout(self, drawn: set[int], center: int | None) -> bool:
        """A neighbourhood view is laid out again only when the current state leaves what is drawn."""
        if self.whole:
            return not drawn
        return not drawn or (center is not None and center not in drawn)

    def lamps(self, update: StateUpdate | None = None) -> tuple[list[tuple[str, bool]], list[tuple[str, bool]]]:
        """(input, value) and (output, value) pairs in spec order for the lamps."""
        u = update or self.last
        a = self.automaton
        if u is None:
            return [(n, False) for n in a.inputs], [(n, False) for n in a.outputs]
        return [(n, bool(u.inputs.get(n, False))) for n in a.inputs], \
            [(n, bool(u.outputs.get(n, False))) for n in a.outputs]


@dataclass(frozen=True)
class ExecutorSource:
    """One ``~source`` message (``ltl_stack/ControllerSource``): what the executor runs, since when."""

    spec: RunningSpec
    started: float  # the node's start time (seconds): another value is another run of the executor

    @property
    def key(self) -> tuple:
        return (self.started, *self.spec.key)

    def options(self, view: ViewOptions) -> ViewOptions:
        """The view's options with the executor's synthesis options."""
        return ViewOptions(self.spec.robotics_semantics, self.spec.cooperative, view.full_limit, view.radius)


def source_spec(source: ExecutorSource, named: str = "") -> tuple[str | None, str]:
    """Which file to synthesize to draw what ``source``'s executor runs, and a warning for a red banner
    ("" when none): the executor's own file when it is readable here with the content the executor
    runs; else its text, written to a file of the same suffix in the temporary folder; None when
    neither is available. ``named`` is the spec the user named: a different content is warned about,
    naming both files (for the start-up strategy; a later one is the characterized or adopted spec)."""
    spec = source.spec
    path: str | None = None
    text, digest = read_spec(spec.spec_file)
    if text and (not spec.spec_sha256 or digest == spec.spec_sha256):
        path = spec.spec_file
    elif spec.spec_text:
        suffix = os.path.splitext(spec.spec_file)[1] or ".structuredslugs"
        path = os.path.join(tempfile.gettempdir(), f"ltl_stack_view_{spec.spec_sha256[:16]}{suffix}")
        if read_spec(path)[1] != spec.spec_sha256:
            with open(path, "w", encoding="utf-8") as f:
                f.write(spec.spec_text)
    if path is None:
        return None, (f"The executor runs {spec.spec_file or 'a strategy written to no file'}, which this view "
                      "cannot read: no picture of the running strategy.")
    warning = ""
    if named and spec.generation == 0:
        named_digest = read_spec(named)[1]
        if named_digest != spec.spec_sha256:
            warning = (f"The executor runs {spec.spec_file}, not {named} (named here"
                       f"{'' if named_digest else ', unreadable'}; their contents differ): drawing the "
                       "executor's spec.")
    if spec.strategy_file:
        warning = (warning + " " if warning else "") + (
            f"The executor runs a saved strategy ({spec.strategy_file}); the picture is synthesized from its "
            "spec and its ids may differ.")
    return path, warning


#: Seconds without any message of the executor (its /diagnostics come every second) before the view
#: says it is gone; and the grace after attaching before a missing publisher counts.
STALE_AFTER = 5.0
CONNECT_GRACE = 3.0


def liveness(now: float, heard: float, state_heard: float | None, connected: bool, master_ok: bool,
             since: float) -> tuple[bool, str]:
    """(alive, text) of an attached executor: ``heard`` the time of its last message of any kind (state,
    source or its /diagnostics, which come every second), ``state_heard`` of its last ``~state`` (None:
    none yet), ``connected`` whether its ``~state`` publisher is connected, ``since`` when the view
    attached (all ``time.monotonic()``)."""
    text = "no state yet" if state_heard is None else f"last state {max(0.0, now - state_heard):.0f} s ago"
    if not master_ok:
        return False, f"no ROS master answers; {text}"
    if not connected and now - since > CONNECT_GRACE:
        return False, f"no executor publishes its state topic; {text}"
    if now - heard > STALE_AFTER:
        return False, f"nothing from the executor for {now - heard:.0f} s; {text}"
    return True, text


MODES = {  # the executor's ~state mode (runtime.resilience.characterize.Mode) -> (what it means, colour)
    Mode.NORMAL.value: ("normal: following the strategy", "#2e9e44"),
    Mode.RECOVERING.value: ("recovering: recovery moves after an environment-assumption violation (thesis §4.4)",
                            "#e08a00"),
    Mode.HOLDING.value: ("holding: a violation without a recovery move; safe outputs until the inputs are admissible",
                         "#d05000"),
    Mode.CHARACTERIZING.value: ("characterizing: resynthesizing with the observed environment (thesis §4.5)",
                                "#3a7bd5"),
    Mode.WAITING_FOR_USER.value: ("waiting for the user: unrealizable; add an environment liveness or abort",
                                  "#c00000"),
    Mode.INPUTS_UNKNOWN.value: ("inputs unknown: stale readings (a partition?); outputs safe for every value of them",
                                "#b05000"),
    Mode.ABORTED.value: ("aborted: every output false", "#800000"),
}


def mode_color(update: StateUpdate | None) -> str:
    """The colour of the mode label ("" when the executor reports no resilience mode)."""
    return MODES.get(update.mode, ("", ""))[1] if update is not None else ""


def resilience_text(update: StateUpdate | None) -> str:
    """The counters of resilient execution, one line."""
    if update is None:
        return ""
    return (f"violations {update.violations}, recovery steps {update.recovery_steps}, unsafe steps "
            f"{update.unsafe_steps}, new strategies {update.resyntheses} ({update.negotiated} negotiated), "
            f"negotiations {update.negotiations}")


def mode_text(update: StateUpdate | None, violation: str, statuses: Mapping[str, tuple[int, str]] | None = None) -> str:
    """The controller's mode: waiting, running, paused, the executor's resilience mode, or holding
    after an assumption violation. Before the first state, what the executor's own /diagnostics say
    (``statuses``: its "controller" and "inputs" statuses, level and message)."""
    statuses = statuses or {}
    if update is None:
        return "no state received yet"
    if update.state_id < 0:
        controller = statuses.get("controller")
        inputs = statuses.get("inputs")
        if update.mode == Mode.ABORTED.value:
            return MODES[Mode.ABORTED.value][0]
        if controller is not None and (controller[0] >= 2 or not update.running):
            return "executor: " + controller[1]
        if not update.running:
            return "paused (every output false)"
        if inputs is not None and inputs[1] != "every input has reported":
            return "executor: " + inputs[1]
        if controller is not None:
            return "executor: " + controller[1]
        return "no state yet (the executor has not reported why)"
    if update.mode in MODES and update.mode != Mode.NORMAL.value:
        return MODES[update.mode][0] + ("" if update.running else " (paused)")
    if update.mode and update.mode not in MODES:  # a mode this view does not know: as the executor says it
        return update.mode.replace("_", " ") + ("" if update.running else " (paused)")
    if violation:
        return "environment assumption violated: " + ("running, " if update.running else "paused, ") + \
            "waiting for admissible inputs"
    return "running" if update.running else "paused (every output false)"


class Latest:
    """The newest value put by one thread, taken by another; counts what was put and taken."""

    def __init__(self):
        self._lock = threading.Lock()
        self._value = None
        self._fresh = False
        self.put_count = 0
        self.taken_count = 0

    def put(self, value) -> None:
        with self._lock:
            self._value, self._fresh = value, True
            self.put_count += 1

    def peek(self):
        """The newest value, taken or not (None before the first)."""
        with self._lock:
            return self._value

    def take(self):
        """The newest value if it was not taken yet, else None."""
        with self._lock:
            if not self._fresh:
                return None
            self._fresh = False
            self.taken_count += 1
            return self._value


def executor_of(state_topic: str) -> str:
    """``/ns/controller_executor/state`` -> ``/ns/controller_executor`` (the node that owns ``~state``)."""
    return state_topic.rstrip("/").rsplit("/", 1)[0] or "/"


def options_from_params(params: Mapping[str, object], defaults: ViewOptions | None = None) -> ViewOptions:
    """The executor's ``~robotics_semantics``/``~cooperative`` parameters, where it has them."""
    o = defaults or ViewOptions()
    rs, coop = params.get("robotics_semantics"), params.get("cooperative")
    return ViewOptions(rs if isinstance(rs, bool) else o.robotics_semantics,
                       coop if isinstance(coop, bool) else o.cooperative, o.full_limit, o.radius)


def synthesize_automaton(spec_path: str, options: ViewOptions | None = None,
                         progress: Callable[[str], None] | None = None) -> Automaton:
    """The explicit automaton the executor runs for ``spec_path`` (see ``ControllerModel.synthesize``)."""
    options = options or ViewOptions()
    say = progress or (lambda _t: None)
    spec = load_spec(spec_path)
    say(f"synthesizing {spec_path} (robotics semantics {options.robotics_semantics}, "
        f"cooperative {options.cooperative})")
    result = synthesize(spec, robotics_semantics=options.robotics_semantics, cooperative=options.cooperative,
                        progress=say)
    if not result.realizable:
        raise UserError(f"{spec_path}: the specification is unrealizable (robotics semantics "
                        f"{options.robotics_semantics}); the executor cannot run it", Exit.UNREALIZABLE)
    say("extracting the explicit automaton")
    automaton = result.strategy.explicit(max_states=MAX_STATES, progress=say)
    say(f"{len(automaton)} states")
    return automaton


def automaton_parts(automaton: Automaton, chunk: int = 1000) -> Iterator[tuple]:
    """``automaton`` as ``assemble_automaton`` takes it: its header, then its states ``chunk`` at a time
    as plain tuples (a state's inputs and outputs as values in the automaton's order), so that reading
    any one part is short (gui.worker_process)."""
    yield ("automaton", {"inputs": list(automaton.inputs), "outputs": list(automaton.outputs),
                         "initial": list(automaton.initial), "goals": automaton.goals,
                         "metadata": dict(automaton.metadata), "path": automaton.path})
    ins, outs = automaton.inputs, automaton.outputs
    for start in range(0, len(automaton.states), chunk):
        yield ("states", [(s.id, s.goal, tuple(bool(s.inputs[n]) for n in ins), tuple(bool(s.outputs[n]) for n in outs),
                           list(s.successors), list(s.recovery)) for s in automaton.states[start:start + chunk]])


def assemble_automaton(parts: Iterable[tuple]) -> Automaton:
    automaton = None
    for part in parts:
        if part[0] == "automaton":
            automaton = Automaton(states=[], **part[1])
        elif part[0] == "states":
            ins, outs = automaton.inputs, automaton.outputs
            automaton.states.extend(AutomatonState(i, dict(zip(ins, iv)), dict(zip(outs, ov)),
                                                   goal, succ, rec) for i, goal, iv, ov, succ, rec in part[1])
    if automaton is None:
        raise ValueError("no automaton in the parts")
    return automaton
