"""Why a GR(1) specification is unrealizable, said in terms of the spec (thesis ch. 4 feedback).

``explain(spec)`` answers, for an unrealizable spec:

- *what fails*: the initial condition itself (no initial output satisfies ``sys_init`` for some
  allowed input), a *deadlock* (the environment can force the robot into a position where every
  move breaks its safety) or a *livelock* (the robot can stay safe forever, but the environment can
  keep it from a goal while meeting all of its own assumptions); and which goals fail on their own;
- *a minimal unrealizable core*: a subset of the system safety and goal clauses that is still
  unrealizable, minimal by deletion (removing any one of its clauses makes it realizable);
- *the environment side*: whether a cooperative environment would let the robot meet everything.
  When it would not, the robot's requirements conflict with the assumptions themselves, and a
  minimal subset of env safety/liveness clauses that keeps the conflict is reported: weakening one
  of them matters. When it would, the environment *can* prevent success: stronger assumptions (ruling
  out the behaviour of the counterstrategy) are the way out;
- on request, an explicit environment *counterstrategy*: a graph of env moves that defeats every
  robot answer, from a losing initial position (JSON and DOT, for small specs).

Deletion only works because the questions are monotone: dropping a system clause can only make a
spec easier to realize, and dropping an assumption can only make a cooperative run easier to find.
All checks reuse one BDD manager (``Game``) with the clause BDDs built once, and every loop checks
the game's deadline. This module computes; ``explain_render`` turns the results into text, JSON
data and DOT.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Callable

from ltl_stack.compat import StrEnum
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.synthesis.fixpoint import init_ok, solve
from ltl_stack.synthesis.game import Game, memory_guard
from ltl_stack.synthesis.options import Deadline

Progress = Callable[[str], None]


class Kind(StrEnum):
    """What fails in an unrealizable spec (a ``str``, so it compares and serialises as its value)."""

    INIT = "init"
    DEADLOCK = "deadlock"
    LIVELOCK = "livelock"


INIT, DEADLOCK, LIVELOCK = Kind.INIT, Kind.DEADLOCK, Kind.LIVELOCK


# --- game variants sharing one BDD manager ------------------------------------------------------

class _Variants:
    """Realizability and cooperative checks of sub-specs of one Game, without rebuilding BDDs."""

    def __init__(self, game: Game, robotics_semantics: bool, progress: Progress | None) -> None:
        self.game = game
        self.robotics = robotics_semantics
        self.progress = progress
        self.checks = 0

    def variant(self, *, sys_safety=None, sys_goals=None, env_safety=None, env_goals=None) -> Game:
        """A shallow copy of the game with some sections replaced by lists of (Clause, BDD)."""
        g = copy.copy(self.game)
        bdd = self.game.bdd
        if sys_safety is not None:
            g.sys_trans = _conjoin(bdd, [u for _, u in sys_safety])
        if env_safety is not None:
            g.env_trans = _conjoin(bdd, [u for _, u in env_safety])
        if sys_goals is not None:
            g.sys_goals = [u for _, u in sys_goals] or [bdd.true]
        if env_goals is not None:
            g.env_goals = [u for _, u in env_goals] or [bdd.true]
        return g

    def realizable(self, game: Game) -> bool:
        self.checks += 1
        return solve(game, robotics_semantics=self.robotics, early_exit=True).realizable


def _let(bdd, values: dict, u):
    """``bdd.let`` that tolerates an empty assignment (a spec without inputs or outputs)."""
    return bdd.let(values, u) if values else u


def _conjoin(bdd, nodes):
    acc = bdd.true
    for u in nodes:
        acc &= u
    return acc


def cooperative_winning(game: Game):
    """Positions from which env and robot *together* can run forever inside both safety formulas
    while meeting every env and system liveness clause infinitely often (a fair cycle)."""
    bdd = game.bdd
    both = game.env_trans & game.sys_trans
    goals = list(game.sys_goals) + list(game.env_goals)

    def epre(target):
        return bdd.exist(game.variables_next, both & target)

    z = bdd.true
    while True:
        new_z = bdd.true
        for goal in goals:
            reach = goal & game.prime(z)
            y = bdd.false
            while True:
                game.deadline.check()
                new_y = epre(reach | game.prime(y))
                if new_y == y:
                    break
                y = new_y
            new_z &= y
        if new_z == z:
            return z
        z = new_z


def cooperative_possible(game: Game) -> bool:
    """Some initial position (env_init & sys_init) from which a cooperative run exists."""
    start = game.env_init & game.sys_init & cooperative_winning(game)
    return start != game.bdd.false


def minimal_core(items: list, still_fails: Callable[[list], bool], progress: Progress | None = None,
                 what: str = "core") -> list:
    """Deletion-based minimisation: drop each item in turn, keep it dropped if ``still_fails``."""
    kept = list(items)
    for k, item in enumerate(items):
        trial = [x for x in kept if x is not item]
        if still_fails(trial):
            kept = trial
        if progress:
            progress(f"{what}: {k + 1}/{len(items)} clauses tried, {len(kept)} kept")
    return kept


# --- counterstrategy ---------------------------------------------------------------------------

@dataclass
class CounterState:
    """A node of the environment's counterstrategy: a position plus the env's memory."""

    id: int
    inputs: dict[str, bool]
    outputs: dict[str, bool]
    blocked_goal: int          # index of the system goal the environment keeps the robot from
    env_goal: int              # index of the env liveness the environment is heading for
    env_move: dict[str, bool] | None = None   # the inputs the environment plays next
    robot_stuck: bool = False  # no next output satisfies the robot's safety after env_move
    successors: list[int] = field(default_factory=list)


@dataclass
class Counterstrategy:
    inputs: list[str]
    outputs: list[str]
    states: list[CounterState]
    initial: list[int]
    goals: list[Clause]        # the system goals (index = blocked_goal); none: the trivial goal true
    truncated: bool = False


class _EnvFixpoint:
    """The environment's winning positions (complement of Eq. 4.2's W) with the iterates needed to
    play: mu Z. \\/_j nu Y. /\\_i mu X. cpre_env((!goal_j | Z') & Y' & (asm_i | X'))."""

    def __init__(self, game: Game) -> None:
        self.game = game
        bdd = game.bdd
        self.levels = []  # per level k: (Z_k, [(Y_j, [ranks for each i])])
        z = bdd.false
        while True:
            per_goal = []
            new_z = z
            for goal in game.sys_goals:
                base = ~goal | game.prime(z)
                y = bdd.true
                while True:
                    ranks_per_asm = []
                    new_y = y
                    for asm in game.env_goals:
                        x = bdd.false
                        ranks = [x]
                        while True:
                            game.deadline.check()
                            new_x = x | game.cpre_env(base & game.prime(y) & (asm | game.prime(x)))
                            if new_x == x:
                                break
                            x = new_x
                            ranks.append(x)
                        ranks_per_asm.append(ranks)
                        new_y &= x
                    if new_y == y:
                        break
                    y = new_y
                per_goal.append((y, ranks_per_asm))
                new_z |= y
            if new_z == z:
                break
            self.levels.append((z, per_goal))
            z = new_z
        self.losing = z  # positions the environment wins from

    def mode(self, position) -> tuple[int, int] | None:
        """(level, goal) to play from ``position`` (a cube), or None when the robot wins there."""
        bdd = self.game.bdd
        for k, (_, per_goal) in enumerate(self.levels):
            for j, (y, _) in enumerate(per_goal):
                if (position & y) != bdd.false:
                    return k, j
        return None

    def move(self, position, k: int, j: int, i: int):
        """The env's set of good next inputs (BDD over next inputs) at ``position`` in mode (k, j, i)."""
        game, bdd = self.game, self.game.bdd
        z, per_goal = self.levels[k]
        y, ranks_per_asm = per_goal[j]
        ranks = ranks_per_asm[i]
        r = next(r for r, x in enumerate(ranks) if (position & x) != bdd.false)
        goal = game.sys_goals[j]
        target = (~goal | game.prime(z)) & game.prime(y) & (game.env_goals[i] | game.prime(ranks[r - 1]))
        good = game.env_trans & bdd.forall(game.outputs_next, ~game.sys_trans | target)
        return bdd.exist(game.variables, position & good)


def build_counterstrategy(game: Game, robotics_semantics: bool, max_states: int = 2000,
                          winning=None) -> Counterstrategy | None:
    """An explicit environment counterstrategy from a losing initial position (None if realizable)."""
    bdd = game.bdd
    env = _EnvFixpoint(game)
    if winning is not None and env.losing != ~winning:  # pragma: no cover - would be an engine bug
        raise AssertionError("the environment's winning region is not the complement of W")
    goals = [c for c, _ in game.clauses("sys_liveness")]
    result = Counterstrategy(list(game.inputs), list(game.outputs), [], [], goals)
    starts = _losing_starts(game, env.losing, robotics_semantics)
    if not starts:
        return None
    index: dict[tuple, int] = {}
    todo: list[tuple] = []

    def node(valuation: dict[str, bool], k: int, j: int, i: int) -> int:
        key = (tuple(valuation[v] for v in game.variables), k, j, i)
        if key not in index:
            index[key] = len(result.states)
            result.states.append(CounterState(
                index[key], {v: valuation[v] for v in game.inputs}, {v: valuation[v] for v in game.outputs},
                j, i))
            todo.append((key, valuation))
        return index[key]

    for valuation in starts:
        mode = env.mode(game.cube(valuation))
        if mode is not None:
            result.initial.append(node(valuation, mode[0], mode[1], 0))
    while todo:
        game.deadline.check()
        if len(result.states) >= max_states:
            result.truncated = True
            break
        (_, k, j, i), valuation = todo.pop(0)
        state = result.states[index[(tuple(valuation[v] for v in game.variables), k, j, i)]]
        here = game.cube(valuation)
        choices = env.move(here, k, j, i)
        pick = bdd.pick(choices, care_vars=set(game.inputs_next))
        if pick is None:  # pragma: no cover - the fixpoint guarantees a move
            continue
        x_next = {v: bool(pick[game.inputs_next[n]]) for n, v in enumerate(game.inputs)}
        state.env_move = x_next
        answers = bdd.exist(game.variables, here & game.cube({}, x_next) & game.sys_trans)
        answers = _let(bdd, {game.inputs_next[n]: x_next[v] for n, v in enumerate(game.inputs)}, answers)
        outputs = list(bdd.pick_iter(answers, care_vars=set(game.outputs_next)))
        if not outputs:
            state.robot_stuck = True
            continue
        env_goal_met = _let(bdd, game.assignment(valuation, x_next), game.env_goals[i]) == bdd.true
        next_i = (i + 1) % len(game.env_goals) if env_goal_met else i
        z_lower = env.levels[k][0]
        for out in outputs:
            nxt = dict(x_next)
            nxt.update({v: bool(out[game.outputs_next[n]]) for n, v in enumerate(game.outputs)})
            cube = game.cube(nxt)
            if (cube & z_lower) != bdd.false:
                mode = env.mode(cube)
                nk, nj = mode if mode is not None else (k, j)
            else:
                nk, nj = k, j
            succ = node(nxt, nk, nj, next_i)
            if succ not in state.successors:
                state.successors.append(succ)
    return result


def _losing_starts(game: Game, losing, robotics_semantics: bool) -> list[dict[str, bool]]:
    """Initial positions of one losing initial input (default semantics: every sys_init answer to it)
    or one losing initial position (robotics semantics)."""
    bdd = game.bdd
    care = set(game.variables)
    if robotics_semantics:
        bad = game.env_init & game.sys_init & losing
        pick = bdd.pick(bad, care_vars=care)
        return [] if pick is None else [{v: bool(pick[v]) for v in game.variables}]
    won = bdd.exist(game.outputs, game.env_init & game.sys_init & ~losing)
    bad_inputs = bdd.exist(game.outputs, game.env_init) & ~won
    answered = bad_inputs & bdd.exist(game.outputs, game.env_init & game.sys_init)
    # prefer an input the robot can answer: there is a game to show; otherwise init alone fails
    pick = bdd.pick(answered if answered != bdd.false else bad_inputs, care_vars=set(game.inputs))
    if pick is None:
        return []
    x = {v: bool(pick[v]) for v in game.inputs}
    answers = _let(bdd, x, game.sys_init & game.env_init)
    starts = []
    for out in bdd.pick_iter(answers, care_vars=set(game.outputs)):
        starts.append({**x, **{v: bool(out[v]) for v in game.outputs}})
    return starts


# --- the explanation ---------------------------------------------------------------------------

@dataclass
class Explanation:
    """The result of ``explain``; ``explain_render.explanation_text`` for people, ``explanation_dict``
    for tools (JSON-able)."""

    source: str
    realizable: bool
    robotics_semantics: bool
    kind: Kind | None = None                     # when unrealizable
    losing_initial: dict[str, bool] | None = None
    init_clauses: list[Clause] = field(default_factory=list)
    realizable_with_default_init: bool | None = None
    deadlock: dict | None = None                 # {"position", "inputs_next", "clauses"}
    failing_goals: list[Clause] = field(default_factory=list)
    core: list[tuple[str, Clause]] = field(default_factory=list)
    core_candidates: int = 0
    cooperative_possible: bool | None = None
    assumption_core: list[tuple[str, Clause]] = field(default_factory=list)
    checks: int = 0
    counterstrategy: Counterstrategy | None = None


def explain(spec: Spec, *, robotics_semantics: bool = True, counterstrategy: bool = False,
            progress: Progress | None = None, max_counterstrategy_states: int = 2000,
            deadline: Deadline | None = None, max_memory: int | None = None) -> Explanation:
    """Explain why ``spec`` is unrealizable (see the module docstring); cheap when it is realizable.

    ``deadline`` and ``max_memory`` bound the work as in ``synthesize`` (``Exit.LIMIT`` errors).
    """
    game = Game(spec, max_memory=max_memory, deadline=deadline or Deadline())
    with memory_guard(game.max_memory):
        return _explain(game, spec, robotics_semantics, counterstrategy, progress, max_counterstrategy_states)


def _explain(game: Game, spec: Spec, robotics_semantics: bool, counterstrategy: bool, progress: Progress | None,
             max_counterstrategy_states: int) -> Explanation:
    variants = _Variants(game, robotics_semantics, progress)
    full = solve(game, robotics_semantics=robotics_semantics)
    variants.checks += 1
    result = Explanation(spec.source, full.realizable, robotics_semantics)
    if full.realizable:
        return result
    bdd = game.bdd
    safety = [("sys_safety", c, u) for c, u in game.clauses("sys_safety")]
    goals = [("sys_liveness", c, u) for c, u in game.clauses("sys_liveness")]

    # what fails: init, deadlock or livelock
    if robotics_semantics:
        result.realizable_with_default_init = init_ok(game, full.winning, False)
        bad = game.env_init & game.sys_init & ~full.winning
        pick = bdd.pick(bad, care_vars=set(game.variables))
        result.losing_initial = {v: bool(pick[v]) for v in game.variables} if pick else None
    else:
        no_answer = bdd.exist(game.outputs, game.env_init) & ~bdd.exist(game.outputs, game.env_init & game.sys_init)
        lost = bdd.exist(game.outputs, game.env_init) & ~bdd.exist(game.outputs,
                                                                    game.env_init & game.sys_init & full.winning)
        pick = bdd.pick(no_answer if no_answer != bdd.false else lost, care_vars=set(game.inputs))
        result.losing_initial = {v: bool(pick[v]) for v in game.inputs} if pick else None
        if no_answer != bdd.false:
            result.kind = INIT
            result.init_clauses = [c for c, _ in game.clauses("sys_init")]
    if result.kind is None:
        safety_only = variants.variant(sys_goals=[], env_goals=[])
        safe = solve(safety_only, robotics_semantics=robotics_semantics)
        variants.checks += 1
        result.kind = LIVELOCK if safe.realizable else DEADLOCK
        if result.kind == DEADLOCK:
            result.deadlock = _deadlock_example(game, robotics_semantics)
    if result.kind == LIVELOCK:
        for _, clause, u in goals:
            if not variants.realizable(variants.variant(sys_goals=[(clause, u)])):
                result.failing_goals.append(clause)

    # minimal unrealizable core of the robot's safety and goal clauses
    candidates = safety + goals
    result.core_candidates = len(candidates)

    def still_unrealizable(subset) -> bool:
        g = variants.variant(sys_safety=[(c, u) for s, c, u in subset if s == "sys_safety"],
                             sys_goals=[(c, u) for s, c, u in subset if s == "sys_liveness"])
        return not variants.realizable(g)

    core = minimal_core(candidates, still_unrealizable, progress, "system core")
    result.core = [(s, c) for s, c, _ in core]

    # the environment side
    result.cooperative_possible = cooperative_possible(game)
    if not result.cooperative_possible:
        assumptions = [("env_safety", c, u) for c, u in game.clauses("env_safety")] + \
                      [("env_liveness", c, u) for c, u in game.clauses("env_liveness")]

        def still_conflicts(subset) -> bool:
            variants.checks += 1
            g = variants.variant(env_safety=[(c, u) for s, c, u in subset if s == "env_safety"],
                                 env_goals=[(c, u) for s, c, u in subset if s == "env_liveness"])
            return not cooperative_possible(g)

        if still_conflicts([]):
            result.assumption_core = []
        else:
            kept = minimal_core(assumptions, still_conflicts, progress, "assumption core")
            result.assumption_core = [(s, c) for s, c, _ in kept]
    result.checks = variants.checks
    if counterstrategy:
        result.counterstrategy = build_counterstrategy(game, robotics_semantics, max_counterstrategy_states,
                                                       full.winning)
    return result


def _deadlock_example(game: Game, robotics_semantics: bool) -> dict | None:
    """How the environment forces a deadlock: from an initial position, a sequence of env moves
    (with one robot answer each) that ends where, after the env's move, no next output satisfies
    sys safety; with the sys safety clauses some next output breaks there (each output breaks one).

    The moves come from the environment's attractor to such positions (``cpre_env`` layers)."""
    bdd = game.bdd
    stuck_moves = game.env_trans & bdd.forall(game.outputs_next, ~game.sys_trans)
    layers = [bdd.exist(game.inputs_next, stuck_moves)]
    while True:
        game.deadline.check()
        wider = layers[-1] | game.cpre_env(game.prime(layers[-1]))
        if wider == layers[-1]:
            break
        layers.append(wider)
    attractor = layers[-1]
    if robotics_semantics:
        starts = game.env_init & game.sys_init & attractor
    else:
        forced = bdd.forall(game.outputs, ~(game.env_init & game.sys_init) | attractor)
        starts = game.env_init & game.sys_init & forced
    if starts == bdd.false:
        starts = attractor
    pick = bdd.pick(starts, care_vars=set(game.variables))
    if pick is None:
        return None
    current = {v: bool(pick[v]) for v in game.variables}
    start = dict(current)
    path = []

    def rank(valuation) -> int:
        cube = game.cube(valuation)
        return next(k for k, layer in enumerate(layers) if (cube & layer) != bdd.false)

    k = rank(current)
    while k > 0:
        here = game.cube(current)
        moves = game.env_trans & bdd.forall(game.outputs_next, ~game.sys_trans | game.prime(layers[k - 1]))
        x_pick = bdd.pick(bdd.exist(game.variables, here & moves), care_vars=set(game.inputs_next))
        x_next = {v: bool(x_pick[game.inputs_next[n]]) for n, v in enumerate(game.inputs)}
        answers = bdd.exist(game.variables, here & game.cube({}, x_next) & game.sys_trans)
        y_pick = bdd.pick(answers, care_vars=set(game.outputs_next) | set(game.inputs_next))
        if y_pick is None:
            break  # this move already leaves the robot without a safe answer
        y_next = {v: bool(y_pick[game.outputs_next[n]]) for n, v in enumerate(game.outputs)}
        path.append({"position": current, "inputs_next": x_next, "outputs_next": y_next})
        current = {**x_next, **y_next}
        k = rank(current)
    here = game.cube(current)
    x_pick = bdd.pick(bdd.exist(game.variables, here & stuck_moves), care_vars=set(game.inputs_next))
    x_next = {v: bool(x_pick[game.inputs_next[n]]) for n, v in enumerate(game.inputs)}
    values = game.assignment(current, x_next)
    clauses = [c for c, u in game.clauses("sys_safety") if _let(bdd, values, u) != bdd.true]
    return {"start": start, "path": path, "steps": len(path), "position": current, "inputs_next": x_next,
            "clauses": clauses}


def counterstrategy(spec: Spec, *, robotics_semantics: bool = True,
                    max_states: int = 2000) -> Counterstrategy | None:
    """The environment's counterstrategy for ``spec`` (None when the spec is realizable)."""
    game = Game(spec)
    with memory_guard(game.max_memory):
        return build_counterstrategy(game, robotics_semantics, max_states)
