"""A symbolic GR(1) strategy: one BDD relation per system goal, executed step by step.

Built from the X/Y iterates of the last Z iteration (``fixpoint.Solution.layers``), following
thesis §4.6 and Alg. 1: for goal j and each (x, y, x') the strategy allows exactly the moves of the
earliest (Y iterate c, assumption i) pair that covers (x, y, x'):

    paths[j][c][i] = sys_trans & ((goal_j & W') | B[c][i]' | (X[c][i]' & !asm_i))
    B[c][i] = Y[c] | X[c][0] | ... | X[c][i-1]

so every move reaches goal j (T.1), gets closer to it (T.2: to an earlier (c, i) pair in
lexicographic order) or waits for an environment goal (T.3).
The goal counter advances when a move satisfies ``goal_j & W'``.

``step`` never builds the explicit automaton: it restricts the goal's relation to the current
position and the new inputs and picks one output valuation deterministically (each output keeps its
current value when it may, in the spec's output order). The cooperative variant (slugs'
``--cooperativeGR1Strategy`` idea) comes from the game solved without moves that leave the
environment no admissible input (``synthesize`` falls back to the ordinary game, preferring such
moves only as a last resort, when that one loses) and, among equally good moves, prefers those that
let the environment reach the liveness assumption the strategy is waiting for soonest.

Recovery (thesis §4.6, Alg. 1 lines 19-25; ``ltl_stack.synthesis.recovery``): with
``strategy.recovery = True`` (or ``step_result``), inputs that break env safety, and positions outside
W, still get a move that keeps sys safety; see ``step_result`` and ``explicit(recovery=True)``.
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ltl_stack.synthesis.automaton import Automaton
from ltl_stack.synthesis.errors import AssumptionViolation, NoInitialState, SynthesisError
from ltl_stack.synthesis.explicit import TooManyStates, extract, traps_environment
from ltl_stack.synthesis.fixpoint import Progress, Solution, initial_positions
from ltl_stack.synthesis.game import Game, memory_guard
from ltl_stack.synthesis.recovery import (
    RecoveryRelations,
    StepKind,
    StepResult,
    UnsafeStep,
    layered_relation,
    prefer,
    unkeepable_clauses,
)
from ltl_stack.synthesis.state import State

__all__ = ["State", "SymbolicStrategy"]


class SymbolicStrategy:
    """Execute the winning strategy of a realizable game without enumerating it."""

    def __init__(self, game: Game, solution: Solution, *, cooperative: bool = False,
                 recovery: bool = False) -> None:
        if not solution.realizable:
            raise SynthesisError("cannot build a strategy: the specification is unrealizable")
        self.game = game
        self.solution = solution
        self.cooperative = cooperative
        #: every move leaves the environment an admissible input (False when the spec is only
        #: realizable by trapping the environment somewhere; such moves are then a last resort)
        self.fully_cooperative = solution.cooperative
        self.inputs = list(game.inputs)
        self.outputs = list(game.outputs)
        self.winning = solution.winning
        self.initial = initial_positions(game, solution.winning)
        W_next = game.prime(solution.winning)
        self.reached = [g & W_next for g in game.sys_goals]
        self.relations = [self._goal_relation(j) for j in range(len(game.sys_goals))]
        #: recovery mode: ``step`` answers violating inputs (and positions outside W) with
        #: ``step_result``'s safe moves instead of raising ``AssumptionViolation``
        self.recovery = recovery
        self._recovery: RecoveryRelations | None = None

    # --- construction ---------------------------------------------------------------------
    def _goal_relation(self, j: int):
        """``recovery.layered_relation`` with the cooperative preferences on each block."""
        if not self.cooperative:
            return layered_relation(self.game, self.solution, j, self.solution.sys_rel)
        game = self.game
        alive_next = game.prime(game.alive())

        def choose(block, i: int):
            if not self.solution.cooperative:
                block = prefer(game, block, [alive_next])
            return self._prefer_helping(block, i)

        return layered_relation(game, self.solution, j, self.solution.sys_rel, choose)

    def _prefer_helping(self, block, i: int):
        """Keep, for each (x, y, x') of ``block``, only the moves that let the environment satisfy
        liveness assumption i soonest (both players cooperating, within the winning positions)."""
        game = self.game
        bdd = game.bdd
        if game.env_goals[i] == bdd.true:
            return block
        return prefer(game, block, self._help_layers(i))

    def _help_layers(self, i: int) -> list:
        """Transition sets ordered by how soon the environment can then satisfy assumption i:
        first the moves that satisfy it, then those entering positions one joint move away, ..."""
        cache = self.__dict__.setdefault("_help_cache", {})
        if i in cache:
            return cache[i]
        game = self.game
        bdd = game.bdd
        W = self.winning
        joint = game.joint_rel(self.solution.sys_rel)
        inside = game.prime(W) & W
        layers = [game.env_goals[i]]
        near = joint.exist_and(inside & game.env_goals[i], game.variables_next)
        seen = near
        while near != bdd.false:
            game.deadline.check()
            layers.append(game.prime(near))
            step_back = joint.exist_and(inside & game.prime(near), game.variables_next)
            near = step_back & ~seen
            seen |= near
        cache[i] = layers
        return layers

    # --- execution --------------------------------------------------------------------------
    def _full(self, values: Mapping[str, bool] | None, names: list[str], what: str) -> dict[str, bool]:
        values = dict(values or {})
        unknown = set(values) - set(names)
        if unknown:
            raise ValueError(f"unknown {what} {', '.join(sorted(unknown))}; expected {', '.join(names)}")
        missing = [n for n in names if n not in values]
        if missing:
            raise ValueError(f"missing {what} {', '.join(missing)}")
        return {n: bool(values[n]) for n in names}

    def _pick(self, u, names: list[str], prefer: Mapping[str, bool]) -> dict[str, bool]:
        """One satisfying valuation of ``names`` in ``u``: each variable takes its preferred value
        when possible, in order (deterministic, independent of the BDD variable order)."""
        bdd = self.game.bdd
        chosen = {}
        for name in names:
            want = bool(prefer.get(name, False))
            v = bdd.let({name: want}, u)
            if v == bdd.false:
                want = not want
                v = bdd.let({name: want}, u)
            chosen[name] = want
            u = v
        return chosen

    def initial_state(self, inputs: Mapping[str, bool] | None = None,
                      outputs: Mapping[str, bool] | None = None) -> State:
        """A winning initial state matching the partial valuations (unspecified values prefer False)."""
        game = self.game
        bdd = game.bdd
        partial = {**dict(inputs or {}), **dict(outputs or {})}
        unknown = set(partial) - set(game.variables)
        if unknown:
            raise NoInitialState(f"unknown propositions {', '.join(sorted(unknown))}")
        u = bdd.let({k: bool(v) for k, v in partial.items()}, self.initial) if partial else self.initial
        if u == bdd.false:
            raise NoInitialState(self._why_no_initial(partial))
        values = self._pick(u, game.variables, partial)
        return self.start_state({n: values[n] for n in self.inputs}, {n: values[n] for n in self.outputs})

    def start_state(self, inputs: dict[str, bool], outputs: dict[str, bool]) -> State:
        """The state for an initial position (goal 0, or later when goal 0 is already met there)."""
        return State(dict(inputs), dict(outputs), self._skip_satisfied(inputs, outputs, 0))

    def _why_no_initial(self, partial: Mapping[str, bool]) -> str:
        game = self.game
        bdd = game.bdd
        shown = ", ".join(f"{k}={int(bool(v))}" for k, v in sorted(partial.items())) or "(none)"
        assign = {k: bool(v) for k, v in partial.items()}
        for section in ("env_init", "sys_init"):
            broken = [c for c, u in game.clauses(section) if bdd.let(assign, u) == bdd.false]
            if broken:
                where = "; ".join(f"{c.location}: {c.text}" for c in broken)
                return f"no initial state with {shown}: it violates {section} ({where})"
        return f"no winning initial state with {shown}"

    def step(self, state: State, inputs: Mapping[str, bool]) -> State:
        """The successor of ``state`` for the new ``inputs`` (raises ``AssumptionViolation``).

        In recovery mode (``self.recovery``) the successor of ``step_result``; only when no move
        keeps sys safety it raises ``UnsafeStep`` (an ``AssumptionViolation``)."""
        if self.recovery:
            result = self.step_result(state, inputs)
            if result.kind is StepKind.UNSAFE:
                raise UnsafeStep(result.violated, self._full(inputs, self.inputs, "inputs"), result.unsafe)
            return result.state
        game = self.game
        bdd = game.bdd
        new_inputs = self._full(inputs, self.inputs, "inputs")
        assign = game.assignment(state.valuation, new_inputs)
        if game.admissible(assign) == bdd.false:
            raise AssumptionViolation(game.violated("env_safety", state.valuation, new_inputs), new_inputs)
        outputs = self._move(state, new_inputs, assign)
        if outputs is None:
            raise SynthesisError(f"state {state.id} (goal {state.goal}) is outside the strategy: "
                                 "no move keeps the specification")
        return self._successor(state, new_inputs, outputs)

    def _move(self, state: State, new_inputs: dict[str, bool], assign: dict) -> dict[str, bool] | None:
        """The next outputs for goal ``state.goal``, or None when the strategy has no move."""
        game = self.game
        bdd = game.bdd
        u = bdd.let(assign, self.relations[state.goal])
        if u == bdd.false:
            return None  # recovery mode answers in ``step_result`` (Alg. 1 lines 19-25)
        return self._pick_outputs(state, u)

    def _pick_outputs(self, state: State, moves: Any) -> dict[str, bool]:
        """One move of ``moves`` (a non-empty BDD over the primed outputs), keeping outputs as they are
        where it can."""
        game = self.game
        prefer = {game.outputs_next[k]: state.outputs[n] for k, n in enumerate(self.outputs)}
        picked = self._pick(moves, game.outputs_next, prefer)
        return {n: picked[game.outputs_next[k]] for k, n in enumerate(self.outputs)}

    def _moves(self, state: State, assign: dict, admissible: bool) -> tuple[Any, bool]:
        """The moves ``step_result`` picks from after ``assign`` (the current valuation and the new
        inputs), as a BDD over the primed outputs, and whether they are the goal's own relation (a
        NORMAL step: a winning position, admissible inputs, a move there) or else the recovery one."""
        bdd = self.game.bdd
        if admissible and bdd.let(self.game.assignment(state.valuation), self.winning) == bdd.true:
            u = bdd.let(assign, self.relations[state.goal])
            if u != bdd.false:
                return u, True
        return bdd.let(assign, self.recovery_relations().relation(state.goal)), False

    # --- recovery (thesis §4.6) ----------------------------------------------------------------
    def recovery_relations(self) -> RecoveryRelations:
        """The prioritized recovery relations (built on first use)."""
        if self._recovery is None:
            self._recovery = RecoveryRelations(self.game, self.solution, self.relations)
        return self._recovery

    def step_result(self, state: State, inputs: Mapping[str, bool]) -> StepResult:
        """One step in recovery mode: the successor and which rule produced it (``StepKind``).

        From a winning position with admissible inputs this is exactly ``step`` (NORMAL). Otherwise
        every move satisfies sys safety: into W (RECOVER_TO_W), else into the recoverable region
        (RECOVER_TOWARDS_W), else anywhere safe (SAFE_ONLY); when no move is safe the result is
        UNSAFE with ``state=None`` and the sys-safety clauses that cannot be kept.
        """
        game = self.game
        bdd = game.bdd
        new_inputs = self._full(inputs, self.inputs, "inputs")
        assign = game.assignment(state.valuation, new_inputs)
        admissible = game.admissible(assign) != bdd.false
        violated = [] if admissible else game.violated("env_safety", state.valuation, new_inputs)
        u, normal = self._moves(state, assign, admissible)
        if u == bdd.false:
            return StepResult(None, StepKind.UNSAFE, violated, unkeepable_clauses(game, assign))
        outputs = self._pick_outputs(state, u)
        nxt = self._successor(state, new_inputs, outputs)
        if normal:
            return StepResult(nxt, StepKind.NORMAL, [], [], True, True)
        in_w, in_r = self.recovery_relations().classify(game.assignment({**new_inputs, **outputs}))
        kind = StepKind.RECOVER_TO_W if in_w else StepKind.RECOVER_TOWARDS_W if in_r else StepKind.SAFE_ONLY
        return StepResult(nxt, kind, violated, [], in_w, in_r)

    def allows(self, state: State, inputs: Mapping[str, bool], outputs: Mapping[str, bool]) -> bool:
        """Whether this strategy may answer ``inputs`` from ``state`` with ``outputs``: the move is
        in the relation ``step_result`` picks from (the goal's relation from a winning position with
        admissible inputs and a move there, else the recovery relation). Lets a runner prefer,
        among equally good moves, one whose successor an exported automaton has."""
        game = self.game
        bdd = game.bdd
        new_inputs = self._full(inputs, self.inputs, "inputs")
        new_outputs = self._full(outputs, self.outputs, "outputs")
        assign = game.assignment(state.valuation, new_inputs)
        moves, _ = self._moves(state, assign, game.admissible(assign) != bdd.false)
        return bdd.let(game.assignment(state.valuation, {**new_inputs, **new_outputs}), moves) == bdd.true

    def keeps_safety(self, state: State, inputs: Mapping[str, bool], outputs: Mapping[str, bool]) -> bool:
        """Whether the move from ``state`` to (``inputs``, ``outputs``) satisfies the system safety."""
        game = self.game
        move = game.assignment(state.valuation, {**inputs, **outputs})
        return self.solution.sys_rel.holds(move)

    def _successor(self, state: State, new_inputs: dict[str, bool], outputs: dict[str, bool]) -> State:
        game = self.game
        bdd = game.bdd
        full = game.assignment(state.valuation, {**new_inputs, **outputs})
        goal = state.goal
        if bdd.let(full, self.reached[goal]) == bdd.true:
            goal = (goal + 1) % len(self.relations)
        return State(dict(new_inputs), dict(outputs), self._skip_satisfied(new_inputs, outputs, goal))

    def _skip_satisfied(self, inputs: dict[str, bool], outputs: dict[str, bool], goal: int) -> int:
        """Advance past goals that the next move from this winning position satisfies whatever it is.

        Goals are transition properties (slugs): a goal ``o`` is met by the move *leaving* a position
        where o holds. Without this, the robot would first pick a move for a goal it already meets.
        """
        game = self.game
        bdd = game.bdd
        here = game.assignment({**inputs, **outputs})
        if bdd.let(here, self.winning) != bdd.true:
            return goal
        for _ in range(len(self.relations) - 1):
            if bdd.let(here, self.game.sys_goals[goal]) != bdd.true:
                break
            goal = (goal + 1) % len(self.relations)
        return goal

    def admissible_inputs(self, state: State) -> list[dict[str, bool]]:
        """Every next input valuation allowed by env safety from ``state`` (sorted by bits)."""
        game = self.game
        bdd = game.bdd
        u = game.admissible(game.assignment(state.valuation))
        result = []
        for a in bdd.pick_iter(u, care_vars=set(game.inputs_next)):
            result.append({n: bool(a[game.inputs_next[k]]) for k, n in enumerate(self.inputs)})
        result.sort(key=lambda d: sum(int(v) << k for k, v in enumerate(d.values())))
        return result

    def explicit(self, max_states: int | None = None, progress: Progress | None = None,
                 recovery: bool = False) -> Automaton:
        """The explicit automaton (thesis Alg. 1 lines 1-18, with ``recovery`` lines 19-25 too);
        see ``ltl_stack.synthesis.explicit``.

        A cooperative strategy's automaton is compared with the one of the plain relations of the
        same solution (no preference for moves that help the environment's liveness): the smaller
        is returned, provided that it never leaves the environment without an admissible input
        (``traps_environment``), so the default export is never larger than it needs to be for
        that promise (fastslow_ICRA 599 -> 270 states, slugs 552)."""
        with memory_guard(self.game.max_memory):
            if not self.cooperative:
                return extract(self, max_states=max_states, progress=progress, recovery=recovery)
            first: Automaton | TooManyStates
            try:
                first = extract(self, max_states=max_states, progress=progress, recovery=recovery)
            except TooManyStates as too_many:
                first = too_many
            bound = len(first.states) - 1 if isinstance(first, Automaton) else max_states
            plain = SymbolicStrategy(self.game, self.solution, cooperative=False, recovery=self.recovery)
            try:
                smaller = extract(plain, max_states=bound, progress=progress, recovery=recovery)
            except TooManyStates:
                smaller = None
            if smaller is None or traps_environment(self.game, smaller):
                if isinstance(first, TooManyStates):
                    raise first
                return first
            smaller.metadata.update(cooperative=True, moves="plain relations (smaller than the helping ones)")
            return smaller
