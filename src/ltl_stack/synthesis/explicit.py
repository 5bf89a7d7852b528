"""Explicit strategy extraction: thesis Alg. 1, lines 1-18 (and 19-25 with ``recovery``).

Starting from every winning initial position with goal 0, breadth first, each state gets exactly
one successor per next input admissible under env safety. The successor's outputs are a move of the
symbolic strategy's relation for the current goal (``SymbolicStrategy.relations``: only moves of the
earliest (Y iterate, assumption) pair, so any of them is a correct move), chosen so that the
automaton stays small:

1. a move into a state that already exists (same next position and goal), when the relation allows
   one — slugs' extractor gets small automata by always picking the same canonical outputs; we pick
   among the allowed moves the one that re-uses a state;
2. otherwise, for a move that reaches the current goal, one into a position from which the goal it
   advances to is reached soonest (the earliest of that goal's Y iterates, ``GoalLayers.Y``): slugs'
   twoDimensionalCost simple1 exported 20 states against slugs' 18 when the move kept an output the
   next goal needs changed;
3. then the outputs ``SymbolicStrategy.step`` picks (each output keeps its current value when it
   may, in the spec's output order).

So the automaton is a correct strategy but not always the one ``step`` follows; the executor steps
the automaton itself (``runtime.executor.explicit``), so its ``~state`` ids are the export's. The goal index
advances when the move reaches the goal, and past the following goals the same move reaches as
well (slugs' extractor does the same; ``step`` stops after the first), then past goals the new
position meets whatever comes (``_skip_satisfied``); a move into an existing state may stop earlier
in that chain when that state has the smaller goal.

Each state's moves are computed at once as a BDD over the next inputs and outputs (the relation
restricted to the state) and enumerated as integer codes (input k is bit k, output k bit
n_in + k; ``_Codes``), never one dict per valuation.

With ``recovery=True`` (Alg. 1 lines 19-25, ``ltl_stack.synthesis.recovery``) every (state, input)
for which some move satisfies sys safety gets one edge: inputs that break env safety, and every
input from states outside W (which only recovery edges reach). Those edges are the recovery
relation's moves (``RecoveryRelations.relation``, the moves ``SymbolicStrategy.step_result`` picks
from) and are listed in ``AutomatonState.recovery``. The automaton without recovery is built first
and kept as it is (same ids, same edges: ``metadata["states_without_recovery"]`` says how many), then
recovery edges are added to every state, and states they reach get both kinds of edges.

This enumerates the automaton and is meant for export, viewing and small specs; executing a
strategy needs only ``SymbolicStrategy.step``.
"""
from __future__ import annotations

from collections import deque
from typing import Any, Callable, Protocol

from ltl_stack.synthesis.automaton import Automaton, AutomatonState
from ltl_stack.synthesis.errors import LimitReached
from ltl_stack.synthesis.game import BACKEND
from ltl_stack.synthesis.recovery import prefer
from ltl_stack.synthesis.state import State

Progress = Callable[[str], None]


class TooManyStates(LimitReached):
    """The explicit automaton exceeds ``max_states`` (``Exit.LIMIT``)."""


class SymbolicStrategy(Protocol):
    """What extraction needs of ``strategy.SymbolicStrategy`` (which imports this module)."""

    game: Any
    solution: Any
    cooperative: bool
    initial: Any
    winning: Any
    relations: list
    reached: list

    def start_state(self, inputs: dict[str, bool], outputs: dict[str, bool]) -> State: ...

    def recovery_relations(self) -> Any: ...

    def _skip_satisfied(self, inputs: dict[str, bool], outputs: dict[str, bool], goal: int) -> int: ...


def extract(strategy: SymbolicStrategy, *, max_states: int | None = None, progress: Progress | None = None,
            recovery: bool = False) -> Automaton:
    """The explicit automaton of ``strategy`` (with recovery edges when ``recovery``);
    ``TooManyStates`` past ``max_states``."""
    return _Extraction(strategy, max_states, progress).run(recovery)


def traps_environment(game: Any, automaton: Automaton) -> bool:
    """Whether a state the automaton reaches without recovery edges leaves the environment no
    admissible next input (a strategy that wins by blocking the environment: what the cooperative
    default promises never to do; slugs' 2-state export of error_resilience_exampleA does)."""
    bdd = game.bdd
    alive = game.alive()
    plain = automaton.metadata.get("states_without_recovery", len(automaton.states))
    return any(bdd.let(game.assignment({**s.inputs, **s.outputs}), alive) != bdd.true
               for s in automaton.states[:plain])


class _Codes:
    """Valuations of BDDs as integer codes, bottom-up over their nodes: each node's valuations of
    the variables below it are computed once and kept (until ``clear``) for every later BDD that
    shares the node (the moves of neighbouring states share most of theirs); variables skipped
    between two nodes are expanded with integer arithmetic. ``pick_iter`` builds one dict per
    valuation, which dominated extraction (millions of edges on thesis Ex. 8 with recovery).

    The kept results depend on the variable order, so it must not change while they are kept
    (``_Extraction`` switches dynamic reordering off meanwhile).
    """

    def __init__(self, bdd, bit_of: dict[str, int]) -> None:
        self.bdd = bdd
        order = sorted(bit_of, key=bdd.level_of_var)
        self.position = {bdd.level_of_var(v): k for k, v in enumerate(order)}
        self.bits = [1 << bit_of[v] for v in order]
        self.end = len(order)
        self.memo: dict = {}
        self.bit_of = bit_of

    def clear(self) -> None:
        self.memo.clear()

    def expand(self, codes: list[int], start: int, stop: int) -> list[int]:
        bits = self.bits
        for k in range(start, stop):  # variables skipped between two nodes are free
            codes = codes + [c | bits[k] for c in codes]
        return codes

    def __call__(self, u) -> list[int]:
        bdd = self.bdd
        if u == bdd.false:
            return []
        if BACKEND != "cudd":  # pragma: no cover - the autoref fallback
            return [sum(1 << self.bit_of[v] for v, val in a.items() if val)
                    for a in bdd.pick_iter(u, care_vars=set(self.bit_of))]
        if u == bdd.true:
            return self.expand([0], 0, self.end)
        return self.expand(self.below(u), 0, self.position[u.level])

    def below(self, u) -> list[int]:
        """Valuations of the variables from u's own on (u not constant), iteratively."""
        memo = self.memo
        found = memo.get(u)
        if found is not None:
            return found
        position, bits, end = self.position, self.bits, self.end
        true = self.bdd.true
        terminal = true.level
        stack = [u]
        while stack:
            f = stack[-1]
            if f in memo:
                stack.pop()
                continue
            low, high = (~f.low, ~f.high) if f.negated else (f.low, f.high)
            waiting = [c for c in (low, high) if c.level != terminal and c not in memo]
            if waiting:
                stack.extend(waiting)
                continue
            stack.pop()
            k = position[f.level]
            codes: list[int] = []
            for child, bit in ((low, 0), (high, bits[k])):
                level = child.level
                if level == terminal:
                    if child != true:
                        continue
                    sub, j = [0], end
                else:
                    sub, j = memo[child], position[level]
                if j > k + 1:
                    sub = self.expand(sub, k + 1, j)
                codes.extend([c | bit for c in sub] if bit else sub)
            memo[f] = codes
        return memo[u]


class _Restricted:
    """A BDD restricted to positions (integer codes of the current variables), cached by the
    values of only the current variables it depends on: a goal mentions a few propositions, so
    its restrictions repeat across thousands of states. With ``truth`` the result is whether the
    restriction is true. Without, results stay uncached when it depends on more than
    ``MAX_CACHED_BITS`` current variables (one BDD kept per position would be too many)."""

    MAX_CACHED_BITS = 16

    def __init__(self, bdd, u, current_bit: dict[str, int], truth: bool = False) -> None:
        self.bdd = bdd
        self.u = u
        support = bdd.support(u)
        self.bits = [(v, k) for v, k in current_bit.items() if v in support]
        self.mask = sum(1 << k for _, k in self.bits)
        self.truth = truth
        self.cache: dict[int, Any] | None = {} if truth or len(self.bits) <= self.MAX_CACHED_BITS else None

    def __call__(self, code: int):
        cache = self.cache
        key = code & self.mask
        if cache is not None:
            found = cache.get(key)
            if found is not None:
                return found
        bdd = self.bdd
        result = bdd.let({v: bool(key >> k & 1) for v, k in self.bits}, self.u) if self.bits else self.u
        if self.truth:
            result = result == bdd.true
        if cache is not None:
            cache[key] = result
        return result


class _Extraction:
    """One breadth-first extraction; positions are integer codes (input k bit k, output k bit
    n_in + k), states are numbered in the order they are created."""

    def __init__(self, strategy: SymbolicStrategy, max_states: int | None, progress: Progress | None) -> None:
        self.strategy = strategy
        self.max_states = max_states
        self.progress = progress
        game = self.game = strategy.game
        self.bdd = game.bdd
        self.n_in = len(game.inputs)
        self.n_vars = len(game.variables)
        self.goals = len(strategy.relations)
        self.current_bit = {v: k for k, v in enumerate(game.variables)}
        self.next_bit = {v: k for k, v in enumerate(game.variables_next)}
        self.input_bit = {v: k for k, v in enumerate(game.inputs_next)}
        self.numbers: dict[int, int] = {}   # position code | goal << n_vars -> state number
        self.states: list[AutomatonState] = []
        self.codes: list[int] = []
        self.todo: deque[int] = deque()
        self.skip_cache: dict[int, int] = {}
        self.values: dict[int, dict[str, bool]] = {}
        bdd = self.bdd
        self._winning = _Restricted(bdd, strategy.winning, self.current_bit, truth=True)
        #: per goal k: is it met at a position (code)
        self._met_at = [_Restricted(bdd, g, self.current_bit, truth=True) for g in game.sys_goals]
        #: per goal g: the moves from a position that reach it (``goal_g & W'`` restricted)
        self._reached_at = [_Restricted(bdd, r, self.current_bit) for r in strategy.reached]
        #: per goal s a move starts its target with: next positions p' whose state (p, skip(p, s)) exists
        self.existing = [self.bdd.false] * self.goals
        #: per goal: the strategy's moves on admissible inputs
        self.ordinary = [game.env_rel.conjoin(strategy.relations[j]) for j in range(self.goals)]
        #: per goal: its Y iterates (``GoalLayers.Y``) as next positions, earliest first: the
        #: targets from which that goal is reached soonest come first
        self.closer = [[game.prime(y) for y in layers.Y[1:]] for layers in strategy.solution.layers]
        self.reported = 0
        #: valuations of move BDDs over the next variables (node results kept for the extraction)
        self.next_codes = _Codes(self.bdd, self.next_bit)

    # --- states -----------------------------------------------------------------------------
    def valuation(self, code: int) -> dict[str, bool]:
        """The position as an assignment of the current variables (cached: the BDDs are
        restricted to it several times)."""
        values = self.values.get(code)
        if values is None:
            values = self.values[code] = {v: bool(code >> k & 1) for v, k in self.current_bit.items()}
        return values

    def _met(self, code: int, k: int) -> bool:
        return self._met_at[k](code)

    def skip(self, code: int, goal: int) -> int:
        """``SymbolicStrategy._skip_satisfied`` on a position code (cached)."""
        key = code | goal << self.n_vars
        g = self.skip_cache.get(key)
        if g is None:
            g = goal
            if self._winning(code):
                for _ in range(self.goals - 1):
                    if not self._met(code, g):
                        break
                    g = (g + 1) % self.goals
            self.skip_cache[key] = g
        return g

    def number(self, code: int, goal: int) -> int:
        key = code | goal << self.n_vars
        n = self.numbers.get(key)
        if n is not None:
            return n
        n = self.numbers[key] = len(self.states)
        if self.max_states is not None and n >= self.max_states:
            raise TooManyStates(f"the explicit strategy has more than {self.max_states} states")
        game = self.game
        values = self.valuation(code)
        self.states.append(AutomatonState(n, {v: values[v] for v in game.inputs},
                                          {v: values[v] for v in game.outputs}, goal))
        self.codes.append(code)
        self.todo.append(n)
        bdd = self.bdd
        cube = bdd.cube({v: bool(code >> k & 1) for v, k in self.next_bit.items()})
        s = goal  # the start goals s with skip(code, s) == goal: goal and those skipped to it
        for _ in range(self.goals):
            if self.skip(code, s) == goal:
                self.existing[s] |= cube
            s = (s - 1) % self.goals
            if s == goal or not self._met(code, s):
                break
        return n

    # --- moves ------------------------------------------------------------------------------
    def split(self, code: int, moves, goal: int) -> list[tuple[Any, tuple[int, ...]]]:
        """``moves`` split by the goals a move may start its target with. A move that reaches the
        current goal (``goal & W'``, thesis Alg. 1 line 14) advances it (``SymbolicStrategy._successor``);
        when it reaches the next ones too it may advance past them as well (slugs' extractor always
        does; ``edges`` does unless stopping earlier re-uses a state). Each part comes with its
        admissible goals, the furthest last; a move that reaches no goal keeps it."""
        bdd = self.bdd
        leaves = []
        part, g, passed = moves, goal, ()
        for _ in range(self.goals):
            reached = self._reached_at[g](code)
            met = part & reached
            rest = part & ~reached
            if rest != bdd.false:
                leaves.append((rest, passed or (g,)))
            if met == bdd.false:
                return leaves
            g = (g + 1) % self.goals
            part, passed = met, (*passed, g)
        leaves.append((part, passed))
        return leaves

    def choose(self, moves, leaves: list[tuple[Any, tuple[int, ...]]], outputs: dict[str, bool], goal: int):
        """One move per next input of ``moves`` (a BDD over the next inputs and outputs): into an
        existing state when one is allowed; else, for a move that reaches the current goal, into a
        position from which the goal it advances to is reached soonest (``closer``); then each
        output keeping its current value when it may, decided in the spec's output order (as
        ``SymbolicStrategy`` steps)."""
        bdd = self.bdd
        game = self.game
        reuse = bdd.false
        for part, goals in leaves:
            existing = bdd.false
            for g in goals:
                existing |= self.existing[g]
            reuse |= part & existing
        free = moves
        if reuse != bdd.false:
            free = moves & ~bdd.exist(game.outputs_next, reuse)
            moves = reuse | free
        for part, goals in leaves:
            ahead = free & part if goals[-1] != goal else bdd.false
            if ahead != bdd.false:
                moves = (moves & ~ahead) | prefer(game, ahead, self.closer[goals[-1]])
        for name, name_next in zip(game.outputs, game.outputs_next):
            keep = bdd.var(name_next) if outputs[name] else ~bdd.var(name_next)
            kept = moves & keep
            if kept == bdd.false:
                continue
            if kept != moves:
                moves = kept | (moves & ~bdd.exist(game.outputs_next, kept))
        return moves

    def edges(self, n: int, moves, marked: bool) -> list[tuple[int, int, bool]]:
        """The edges of state n for ``moves`` (a BDD over the next inputs and outputs)."""
        if moves == self.bdd.false:
            return []
        state = self.states[n]
        leaves = self.split(self.codes[n], moves, state.goal)
        moves = self.choose(moves, leaves, state.outputs, state.goal)
        in_mask = (1 << self.n_in) - 1
        numbers = self.numbers
        shift = self.n_vars
        result = []
        for part, goals in leaves:
            for code in self.next_codes(moves & part):
                t = None
                for g in reversed(goals):  # an existing state, the furthest goal first
                    t = numbers.get(code | self.skip(code, g) << shift)
                    if t is not None:
                        break
                if t is None:
                    t = self.number(code, self.skip(code, goals[-1]))
                result.append((code & in_mask, t, marked))
        return result

    def run(self, recovery: bool) -> Automaton:
        """The automaton, with dynamic reordering off meanwhile (``_Codes`` keeps results that
        depend on the variable order; the manager's setting is restored afterwards)."""
        bdd = self.bdd
        reordering = BACKEND == "cudd" and bdd.configure()["reordering"]
        if reordering:
            bdd.configure(reordering=False)
        try:
            return self._run(recovery)
        finally:
            self.next_codes.clear()
            if reordering:
                bdd.configure(reordering=True)

    def _run(self, recovery: bool) -> Automaton:
        strategy = self.strategy
        game = self.game
        bdd = self.bdd
        # every winning initial position (goal 0 unless already met there) as codes, ordered by
        # ``State.id`` (goal, then the position's bits)
        starts = _Codes(bdd, self.current_bit)(strategy.initial)
        for goal, code in sorted((self.skip(code, 0), code) for code in starts):
            self.number(code, goal)
        initial = list(range(len(self.states)))
        check = game.deadline.check
        while self.todo:  # the ordinary automaton (Alg. 1 lines 1-18)
            check()
            n = self.todo.popleft()
            here = self.valuation(self.codes[n])
            edges = self.edges(n, bdd.let(here, self.ordinary[self.states[n].goal]), False)
            edges.sort()
            self.states[n].successors = [t for _, t, _ in edges]
            self._report()
        plain = len(self.states)
        if recovery:
            self._add_recovery(plain)
        meta = {"cooperative": strategy.cooperative,
                "robotics_semantics": strategy.solution.robotics_semantics,
                "source": getattr(game.spec, "source", "")}
        if recovery:
            meta.update(recovery=True, states_without_recovery=plain)
        return Automaton(list(game.inputs), list(game.outputs), self.states, initial, len(game.sys_goals), meta)

    def _add_recovery(self, plain: int) -> None:
        """Alg. 1 lines 19-25: recovery edges for every (state, input) outside (W, admissible)."""
        game = self.game
        bdd = self.bdd
        rec = self.strategy.recovery_relations()
        normal = game.env_rel.conjoin(self.strategy.winning)
        self.todo = deque(range(plain))
        check = game.deadline.check
        while self.todo:
            check()
            n = self.todo.popleft()
            state = self.states[n]
            here = self.valuation(self.codes[n])
            ordinary = bdd.let(here, normal)  # over the next inputs
            edges = [] if n < plain else self.edges(n, bdd.let(here, self.ordinary[state.goal]) & ordinary, False)
            edges += self.edges(n, bdd.let(here, rec.relation(state.goal)) & ~ordinary, True)
            if n < plain:  # keep the ordinary automaton's edges as they are
                old = self.states[n].successors
                in_mask = (1 << self.n_in) - 1
                edges += [(self.codes[t] & in_mask, t, False) for t in old]
            edges.sort()
            state.successors = [t for _, t, _ in edges]
            state.recovery = [t for _, t, r in edges if r]
            self._report()

    def _report(self) -> None:
        if self.progress and len(self.states) >= self.reported + 5000:
            self.reported = len(self.states) // 5000 * 5000
            self.progress(f"explicit strategy: {len(self.states)} states, {len(self.todo)} to expand")
