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

import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field

from ltl_stack.errors import Exit, UserError
from ltl_stack.gui.dotgraph import DotGraph
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import Automaton, synthesize
from ltl_stack.synthesis.automaton import AutomatonState

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
            g.add_node(sid, f"{sid} (goal {s.goal})\n{outs}{more}", shape="box",
                       color=INITIAL_COLOR if sid in initial else "black",
                       tooltip=f"state {sid}, goal {s.goal}; inputs: "
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


MODES = {  # the executor's ~state mode -> (what it means, colour)
    "normal": ("normal: following the strategy", "#2e9e44"),
    "recovering": ("recovering: recovery moves after an environment-assumption violation (thesis §4.4)", "#e08a00"),
    "holding": ("holding: a violation without a recovery move; safe outputs until the inputs are admissible",
                "#d05000"),
    "characterizing": ("characterizing: resynthesizing with the observed environment (thesis §4.5)", "#3a7bd5"),
    "waiting_for_user": ("waiting for the user: unrealizable; add an environment liveness or abort", "#c00000"),
    "aborted": ("aborted: every output false", "#800000"),
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


def mode_text(update: StateUpdate | None, violation: str) -> str:
    """The controller's mode: waiting, running, paused, the executor's resilience mode, or holding
    after an assumption violation."""
    if update is None:
        return "no state received yet"
    if update.state_id < 0:
        return "waiting for every input to report (ready handshake)"
    if update.mode in MODES and update.mode != "normal":
        return MODES[update.mode][0] + ("" if update.running else " (paused)")
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
