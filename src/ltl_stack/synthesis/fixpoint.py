"""Winning positions of a GR(1) game: the three nested fixpoints of thesis Eq. 4.2.

    W = nu Z. /\\_j mu Y. \\/_i nu X. cpre( (goal_j & Z') | Y' | (!asm_i & X') )

computed on transitions as slugs does (goals and assumptions may mention next-state variables),
with ``Game.cpre_sys`` as the controllable predecessor.

Techniques (each can be switched off to measure it, see ``Options``):

- *recycling* (slugs' ``--fixedPointRecycling``): Z only shrinks, so every inner X fixpoint of the
  next Z iteration lies inside the one computed at the same (goal j, Y iteration c, assumption i)
  in the previous Z iteration; we start the X iteration there instead of at ``true``.
- *early exit* for realizability-only queries: Z only shrinks, so as soon as an upper bound of W
  fails the initial condition the answer is "unrealizable".
- *dynamic reordering* during the fixpoints (CUDD sifting with each x/x' pair grouped), adaptive:
  off at the start of ``solve``; switched on once the manager holds ``Options.reorder_threshold``
  live nodes when the game is small (its order then fits only the transition relation and the
  fixpoint's sets grow far past it), and only once they pass ``Options.big_game_growth`` times the
  game's own nodes when the game is big (``Game.nodes >= Options.big_game``: construction already
  sifted it into an order that suits the fixpoint too). ``solve`` restores the manager's setting on
  return (CUDD's default is on: ``SymbolicStrategy`` builds its relations with reordering, and
  switches it off once they are built, so that enumeration and stepping see a stable order).
- conjunction fused with quantification inside ``cpre_sys`` (``and_exists``/``or_forall``).
- *Gauss-Seidel rounds* of mu Y: the X set of assumption i is computed with Y already grown by the
  X sets of assumptions 0..i-1 of the same round (a chaotic iteration of the same least fixpoint:
  every intermediate Y stays below it), so Y needs fewer rounds; on the grid-patrol family this
  halves the number of cpre calls.
- the first X iterate from ``true`` is ``live | (!asm_i & cpre(true))`` with cpre(true) computed once.
- *the kernel* (``kernel.py``): a fixpoint that outlasts ``kernel.WARMUP_CPRE`` controllable
  predecessors in CUDD is redone in oxidd, in the order CUDD has sifted into, and its sets are copied
  back (basicEvasion 53 -> 8 s CPU); ``Options.kernel`` / ``LTL_STACK_KERNEL`` choose it.

When no liveness formula mentions next-state variables, the equivalent state-based iterates of
Bloem et al. (JCSS 2012) are used instead: ``X = (goal_j & cpre(Z')) | cpre(Y') | (!asm_i & cpre(X'))``
(same W; each cpre has a smaller target, and cpre(Z') is shared by all goals, cpre(Y') by all
assumptions). The strategy relation of ``strategy.py`` is valid for both kinds of iterates.

The X and Y iterates of the last Z iteration (computed with Z = W) are kept in ``Solution.layers``
for strategy extraction (thesis Alg. 1 prefers the earliest Y iterate; here the earliest
(Y round, assumption) pair in lexicographic order, see ``GoalLayers``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

from ltl_stack.synthesis import kernel
from ltl_stack.synthesis.game import BACKEND, BIG_GAME, BIG_GAME_GROWTH, REORDER_THRESHOLD, Game
from ltl_stack.synthesis.relation import Relation

Progress = Callable[[str], None]


@dataclass
class Options:
    """Switches for the performance techniques (all on by default)."""

    recycle: bool = True
    #: dynamic reordering, switched on once the manager holds ``reorder_threshold`` nodes (tiny
    #: games lose more to sifting than they gain) ...
    reorder: bool = True
    reorder_threshold: int = REORDER_THRESHOLD
    #: ... or, for a game of at least ``big_game`` nodes, ``big_game_growth`` times its nodes
    big_game: int = BIG_GAME
    big_game_growth: float = BIG_GAME_GROWTH
    early_exit: bool = False
    #: None: state-based iterates when no liveness formula mentions next-state variables
    state_based: bool | None = None
    #: within a round of mu Y, compute the X of assumption i with the Y already grown by the X
    #: sets of assumptions 0..i-1 (chaotic iteration: same fixpoint, fewer rounds)
    gauss_seidel: bool = True
    #: the fixpoint's BDD kernel: "cudd", "oxidd" or "auto" (``kernel.py``); None: the
    #: ``LTL_STACK_KERNEL`` variable, "auto" when unset
    kernel: str | None = None


@dataclass
class GoalLayers:
    """Iterates for one system goal j in the last Z iteration.

    ``Y[c]`` is the c-th iterate of mu Y (``Y[0]`` is false) and ``Y[c+1] = Y[c] | X[c][0] | ... |
    X[c][p-1]``. ``X[c][i]`` is the nu X fixpoint for assumption i computed with
    ``Y[c] | X[c][0] | ... | X[c][i-1]`` (``Options.gauss_seidel``; with ``Y[c]`` alone otherwise).
    """

    Y: list = field(default_factory=list)
    X: list = field(default_factory=list)


@dataclass
class Solution:
    realizable: bool
    winning: object
    layers: list[GoalLayers]
    #: the system's safety the game was solved with (``relation.Relation``): ``Game.sys_rel``, or
    #: with ``cooperative`` its restriction ``Game.deadlock_free_sys_rel()``
    sys_rel: Relation
    z_iterations: int
    seconds: float
    robotics_semantics: bool
    complete: bool = True  # False when an early exit stopped before the fixpoint
    cooperative: bool = False  # solved without moves that leave the environment no admissible input
    #: ``cpre(winning')`` as the last Z iteration computed it (state-based iterates of a complete
    #: solve; None otherwise): the vacuity check reads from it which winning positions have a move
    cpre_winning: object = None
    #: the kernel the fixpoints ran on ("cudd" or "oxidd"; the sets above are CUDD's either way)
    kernel: str = "cudd"


def init_ok(game: Game, winning, robotics_semantics: bool) -> bool:
    """The initial condition of realizability for the winning set ``winning``.

    Robotics semantics (slugs' ``--sysInitRoboticsSemantics``): every position satisfying
    env_init & sys_init is winning. Default (slugs): for every input valuation allowed by env_init
    some output valuation satisfies sys_init (and env_init, should it mention outputs) and is winning.
    """
    bdd = game.bdd
    if robotics_semantics:
        return (game.env_init & game.sys_init & ~winning) == bdd.false
    allowed = bdd.exist(game.outputs, game.env_init)
    good = bdd.exist(game.outputs, game.env_init & game.sys_init & winning)
    return (allowed & ~good) == bdd.false


def initial_positions(game: Game, winning):
    """Winning positions satisfying both init conditions: the strategy's initial positions."""
    return game.env_init & game.sys_init & winning


def reorder_threshold(game: Game, opts: Options) -> int:
    """Live nodes from which ``solve`` switches dynamic reordering on (see the module docstring)."""
    if game.nodes >= opts.big_game:
        return max(opts.reorder_threshold, int(opts.big_game_growth * game.nodes))
    return opts.reorder_threshold


def solve(game: Game, *, robotics_semantics: bool = False, early_exit: bool = False,
          cooperative: bool = False, options: Options | None = None,
          progress: Progress | None = None) -> Solution:
    """Compute W (Eq. 4.2) and the iterates needed for strategy extraction.

    ``cooperative`` solves the game where the system may only use moves after which the
    environment still has an admissible input (it never forces a violation of the assumptions).
    Every controllable-predecessor call checks ``game.deadline`` (``TimeLimitReached``).

    The kernel (``kernel.py``): with oxidd available and chosen (``Options.kernel``, the
    ``LTL_STACK_KERNEL`` variable), the fixpoint first runs ``kernel.WARMUP_CPRE`` controllable
    predecessors in CUDD, which sifts the order; a game that finishes within them is answered there.
    Otherwise the game is copied into oxidd in CUDD's order, solved there from the start, and the
    solution copied back into CUDD (the same sets: the iterates are determined by the game, not the
    kernel). oxidd running out of its memory share falls back to CUDD (``progress`` says so).
    """
    opts = options or Options()
    start = time.perf_counter()
    kind = kernel.requested() if opts.kernel is None else opts.kernel
    if kind not in kernel.KINDS:
        raise ValueError(f"unknown BDD kernel {kind!r}; expected one of {', '.join(kernel.KINDS)}")
    if kind != "cudd" and kernel.available() and BACKEND == "cudd":
        if kind == "auto":
            try:
                return _solve(game, robotics_semantics, early_exit, cooperative, opts, progress,
                              stop_after=kernel.WARMUP_CPRE)
            except _WarmedUp:
                pass
        try:
            return _solve_oxidd(game, robotics_semantics, early_exit, cooperative, opts, progress, start)
        except Exception as e:
            if not kernel.is_memory_error(e):
                raise
            if progress:
                progress("oxidd ran out of its memory share: solving in CUDD")
    return _solve(game, robotics_semantics, early_exit, cooperative, opts, progress)


class _WarmedUp(Exception):
    """The CUDD warm-up before the oxidd kernel has made its controllable predecessors."""


def _solve_oxidd(game: Game, robotics_semantics: bool, early_exit: bool, cooperative: bool,
                 opts: Options, progress: Progress | None, start: float) -> Solution:
    """``_solve`` on a copy of ``game`` in oxidd (in CUDD's current order), its result copied back."""
    bdd = game.bdd
    old_reordering = bdd.configure()["reordering"]
    bdd.configure(reordering=False)  # both managers keep one order while BDDs are copied
    try:
        view, copier = kernel.oxidd_game(game, game.max_memory)
        if progress:
            progress(f"fixpoint in oxidd ({len(view.bdd)} nodes copied from CUDD)")
        sol = _solve(view, robotics_semantics, early_exit, cooperative, opts, progress)
        back = copier.to_cudd
        layers = [GoalLayers(Y=[back(u) for u in gl.Y], X=[[back(u) for u in xs] for xs in gl.X])
                  for gl in sol.layers]
        return Solution(sol.realizable, back(sol.winning), layers,
                        game.deadlock_free_sys_rel() if cooperative else game.sys_rel,
                        sol.z_iterations, time.perf_counter() - start, robotics_semantics,
                        complete=sol.complete, cooperative=cooperative,
                        cpre_winning=None if sol.cpre_winning is None else back(sol.cpre_winning),
                        kernel="oxidd")
    finally:
        bdd.configure(reordering=old_reordering)


def _solve(game: Game, robotics_semantics: bool, early_exit: bool, cooperative: bool, opts: Options,
           progress: Progress | None, stop_after: int | None = None) -> Solution:
    """The fixpoints of ``solve`` on ``game``'s kernel (``game.bdd``: CUDD, or ``kernel.OxiddManager``);
    ``stop_after`` controllable predecessors raise ``_WarmedUp`` (the warm-up before oxidd)."""
    early_exit = early_exit or opts.early_exit
    bdd = game.bdd
    start = time.perf_counter()
    cudd = BACKEND == "cudd" and getattr(bdd, "kernel", "cudd") == "cudd"
    reorder = opts.reorder and game.may_reorder
    old_reordering = bdd.configure()["reordering"] if cudd else False
    reordering_on = False
    calls = 0
    threshold = reorder_threshold(game, opts)
    # len(bdd) makes CUDD collect garbage (and so drop cache entries): look only every 8th call, and
    # every 64th in a big game, where the check is only a safety net
    every = 8 if threshold == opts.reorder_threshold else 64

    def maybe_reorder() -> None:
        nonlocal reordering_on, calls
        calls += 1
        if reorder and not reordering_on and calls % every == 1 and len(bdd) >= threshold:
            bdd.configure(reordering=True)
            reordering_on = True
            if progress:
                progress(f"dynamic reordering on ({len(bdd)} nodes)")

    if cudd:
        bdd.configure(reordering=False)
    check = game.deadline.check

    def cpre(target):
        check()
        maybe_reorder()
        if stop_after is not None and calls > stop_after:
            raise _WarmedUp
        return game.cpre_sys(target, sys_rel)
    sys_rel = game.deadlock_free_sys_rel() if cooperative else game.sys_rel

    def x_fixpoint(live, nasm, old: list, c: int, i: int):
        """nu X. live | (nasm & cpre(X')) (state-based) or nu X. cpre(live | (X' & nasm))."""
        if nasm == bdd.false:  # no waiting allowed (assumption "true"): no iteration needed
            return live if state_based else cpre(live)
        # start from an upper bound: the X at the same place in the previous Z iteration (the
        # last round there ran at the fixpoint of Y, so it bounds every later round), or true
        if opts.recycle and old:
            X = old[min(c, len(old) - 1)][i]
        elif state_based:
            X = live | (nasm & cox_true)  # the first iterate from true
        else:
            X = bdd.true
        while True:
            if state_based:
                X_new = live | (nasm & cpre(game.prime(X)))
            else:
                X_new = cpre(live | (game.prime(X) & nasm))
            if X_new == X:
                return X
            X = X_new

    not_asm = [~a for a in game.env_goals]
    try:
        Z = bdd.true
        recycled: list[list[list]] = [[] for _ in game.sys_goals]  # [j][c][i] from last Z iteration
        iteration = 0
        state_based = opts.state_based
        if state_based is None:
            state_based = not game.liveness_has_next
        cox_true = cpre(bdd.true) if state_based else None
        while True:
            iteration += 1
            layers: list[GoalLayers] = []
            Z_next = bdd.true
            cox_z = cpre(game.prime(Z)) if state_based else None
            for j, goal in enumerate(game.sys_goals):
                reach_goal = goal & (cox_z if state_based else game.prime(Z))
                gl = GoalLayers(Y=[], X=[])
                Y = bdd.false
                live = None  # recomputed only when Y grows
                while True:
                    c = len(gl.X)  # the round
                    gl.Y.append(Y)
                    Y_round = Y
                    Xs: list = []
                    gl.X.append(Xs)
                    for i, nasm in enumerate(not_asm):
                        if live is None:
                            live = reach_goal | (cpre(game.prime(Y)) if state_based else game.prime(Y))
                        X = x_fixpoint(live, nasm, recycled[j], c, i)
                        Xs.append(X)
                        grown = Y | X
                        if opts.gauss_seidel and grown != Y:
                            live = None
                        Y = grown
                    if Y == Y_round:
                        break
                    live = None
                layers.append(gl)
                recycled[j] = gl.X
                Z_next &= Y
                if early_exit and not init_ok(game, Z_next, robotics_semantics):
                    if progress:
                        progress(f"Z iteration {iteration}: goal {j} already fails the initial condition")
                    return Solution(False, Z_next, layers, sys_rel, iteration,
                                    time.perf_counter() - start, robotics_semantics, complete=False,
                                    cooperative=cooperative)
            if progress:
                progress(f"Z iteration {iteration}: {', '.join(str(len(g.Y)) for g in layers)} "
                         f"Y iterations per goal, {time.perf_counter() - start:.2f} s")
            if Z_next == Z:
                break
            Z = Z_next
        realizable = init_ok(game, Z, robotics_semantics)
        # the last iteration started from Z and ended at it: its cox_z is cpre of the winning set
        return Solution(realizable, Z, layers, sys_rel, iteration,
                        time.perf_counter() - start, robotics_semantics, cooperative=cooperative,
                        cpre_winning=cox_z)
    finally:
        if cudd:
            bdd.configure(reordering=old_reordering)
