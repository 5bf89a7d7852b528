"""Recovery transitions: thesis §4.6.1, §4.6.2 and Alg. 1 lines 19-25, on BDDs.

When the incoming inputs x' break the environment safety rho_e (or the robot is outside the winning
positions W after such a violation), the ordinary strategy has no move. With recovery the robot
still moves, and every move satisfies the system safety rho_s. For goal j and each (x, y, x') the
move is chosen by the first rule that has one:

1. NORMAL / RECOVER_TO_W (§4.6.1, Alg. 1 lines 9-18): a move of the goal's ordinary relation.
   It ranks targets by the earliest mu Y layer of goal j, and it ignores rho_e, so for violating
   inputs it already gives "some y' with rho_s and (x', y') in W, the earliest in the layers".
   (When the strategy was solved with the cooperative restriction of rho_s, the same ranking is
   repeated with the full rho_s for (x, y, x') the restricted one cannot answer.)
2. RECOVER_TOWARDS_W (§4.6.2): a move into the *recoverable region* R \\ W, where

       R = mu R. W | EPre(R),   EPre(T) = { (x, y) | exists x', y'. rho_s(x, y, x', y') & T(x', y') }

   i.e. the positions from which *some* sequence of rho_s transitions leads back into W. Game
   semantics: existential in both players, as the thesis words it ("W is reachable by some sequence
   of transitions that are all in rho_s"). The environment has already left its assumptions, so the
   robot cannot force anything: a forcing version against an arbitrary environment is empty in
   typical specs (the environment can keep the door closed forever), and the forcing version
   against an environment that keeps rho_e is W itself. R is what the robot can hope to recover
   from when the environment stops misbehaving.

   "Closer": targets in the earliest ring R_k \\ R_(k-1) (fewest rho_s steps back to W) first -
   the prose of §4.6.2 ("preferring transitions that move closer to positions in W ... recover as
   quickly as possible"); among those, Alg. 1's B_(j,c) order (fewest rho_s steps to a transition
   that meets goal j into W) breaks the tie. The algorithm alone ranks by B_(j,c) only, which can
   prefer a long detour outside W that passes near goal j over a move one step from W; we rank by
   distance to W first because the guarantees come back only inside W.
3. SAFE_ONLY: outside R but rho_s still holds. Among these, prefer targets from which the robot
   can keep rho_s for the most further steps whatever inputs come (``safety_levels``: S_0 = all,
   S_(k+1) = S_k & forall x'. exists y'. rho_s & S_k'; the deepest level first, up to the greatest
   fixpoint = safe forever). This is our reading of "keep the most options open".
4. UNSAFE: no y' satisfies rho_s for (x, y, x'). The only case where Lemma 1(a) cannot hold: the
   step reports it with a minimal set of sys-safety clauses that cannot be kept together
   (``unkeepable_clauses``) and the caller applies its fallback.

``RecoveryRelations.relation(j)`` is the union of these prioritized moves: exactly the goal's
ordinary relation where that has a move, so from a winning position with admissible inputs recovery
mode moves exactly as the normal strategy does.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from ltl_stack.spec.model import Clause
from ltl_stack.synthesis.errors import AssumptionViolation
from ltl_stack.synthesis.fixpoint import Solution
from ltl_stack.synthesis.game import Game
from ltl_stack.synthesis.relation import Relation

#: cap on the iterations of the safety levels (targets deeper than this are ranked equal)
MAX_SAFETY_LEVELS = 64


class StepKind(Enum):
    """Which rule produced a step (see the module docstring)."""

    NORMAL = "normal"
    RECOVER_TO_W = "recover_to_w"
    RECOVER_TOWARDS_W = "recover_towards_w"
    SAFE_ONLY = "safe_only"
    UNSAFE = "unsafe"


@dataclass(frozen=True)
class StepResult:
    """The outcome of a recovery-mode step.

    ``state`` is the successor (None for UNSAFE), ``violated`` the env-safety clauses the inputs
    broke (empty when they are admissible), ``unsafe`` the sys-safety clauses that cannot be kept
    together (UNSAFE only). ``in_winning`` says whether the new position is in W and
    ``recoverable`` whether it is in the recoverable region R (W included).
    """

    state: object
    kind: StepKind
    violated: list[Clause] = field(default_factory=list)
    unsafe: list[Clause] = field(default_factory=list)
    in_winning: bool = False
    recoverable: bool = False

    @property
    def outside_recoverable(self) -> bool:
        return self.kind in (StepKind.SAFE_ONLY, StepKind.UNSAFE)


class UnsafeStep(AssumptionViolation):
    """No move keeps the system safety for these inputs (recovery case 4).

    A subclass of ``AssumptionViolation`` (``clauses`` = the broken env-safety clauses, possibly
    none when the robot is outside W), so a caller that handles violations applies its fallback;
    ``unsafe`` names the sys-safety clauses that cannot all be kept.
    """

    def __init__(self, clauses: list[Clause], inputs: dict[str, bool], unsafe: list[Clause]) -> None:
        super().__init__(clauses, inputs)
        self.unsafe = list(unsafe)
        where = "; ".join(f"{c.location}: {c.text or '(no text)'}" for c in self.unsafe) or "(none found)"
        self.args = (f"{self.args[0]}; no move keeps the system safety, these guarantees cannot "
                     f"all be kept: {where}",)


def existential_pre(game: Game, target):
    """Positions with some rho_s transition (any next inputs, some next outputs) into ``target``."""
    return game.sys_rel.exist_and(game.prime(target), game.variables_next)


def rings(game: Game, base) -> list:
    """``[base, R_1 \\ base, R_2 \\ R_1, ...]`` of ``mu R. base | EPre(R)`` (breadth first)."""
    bdd = game.bdd
    result = [base]
    seen = base
    frontier = base
    while True:
        game.deadline.check()
        new = existential_pre(game, frontier) & ~seen
        if new == bdd.false:
            return result
        result.append(new)
        seen |= new
        frontier = new


def safety_levels(game: Game, limit: int = MAX_SAFETY_LEVELS) -> list:
    """``[S_1, S_2, ...]``: S_k = positions from which the robot can keep rho_s for k more steps
    whatever inputs come (no rho_e: the environment is outside its assumptions); the last entry is
    the greatest fixpoint (safe forever) unless ``limit`` stopped the iteration."""
    bdd = game.bdd
    levels = []
    S = bdd.true
    for _ in range(limit):
        game.deadline.check()
        keep = bdd.forall(game.inputs_next, game.sys_rel.exist_and(game.prime(S), game.outputs_next))
        S_next = S & keep
        if S_next == S:
            break
        levels.append(S_next)
        S = S_next
    return levels


def prefer(game: Game, block, layers: list):
    """For each (x, y, x') of ``block`` keep only the moves in the first of ``layers`` that has one
    (moves in none of them stay when nothing better exists)."""
    bdd = game.bdd
    result = bdd.false
    remaining = block
    for target in layers:
        chosen = remaining & target
        if chosen != bdd.false:
            result |= chosen
            remaining &= ~bdd.exist(game.outputs_next, chosen)
            if remaining == bdd.false:
                break
    return result | remaining


def layered_relation(game: Game, solution: Solution, j: int, trans: Relation, choose=None):
    """Goal j's moves under ``trans``, each (x, y, x') answered by its earliest (Y round c,
    assumption i) pair (thesis Alg. 1; ``SymbolicStrategy`` module docstring):

        paths[c][i] = trans & ((goal_j & W') | B[c][i]' | (X[c][i]' & !asm_i))
        B[c][i] = Y[c] | X[c][0] | ... | X[c][i-1]

    ``choose(block, i)``, when given, narrows each pair's block (the cooperative preferences)."""
    bdd = game.bdd
    layers = solution.layers[j]
    reached = game.sys_goals[j] & game.prime(solution.winning)
    not_asm = [~a for a in game.env_goals]
    covered = bdd.false
    relation = bdd.false
    for Yc, Xs in zip(layers.Y, layers.X):
        below = Yc  # Y[c] and the X sets of the assumptions before i in round c
        for i, X in enumerate(Xs):
            game.deadline.check()
            target = reached | game.prime(below) | (game.prime(X) & not_asm[i])
            below = below | X
            new = trans.exist_and(target, game.outputs_next) & ~covered
            if new == bdd.false:
                continue
            block = trans.conjoin(new & target)
            relation |= block if choose is None else choose(block, i)
            covered |= new
    return relation


class RecoveryRelations:
    """The prioritized recovery relation of each goal, built on first use (see module docstring)."""

    def __init__(self, game: Game, solution: Solution, relations: list) -> None:
        self.game = game
        self.solution = solution
        self.normal = list(relations)
        bdd = game.bdd
        self.winning = solution.winning
        self.rings = rings(game, solution.winning)
        recoverable = bdd.false
        for ring in self.rings:
            recoverable |= ring
        #: R: positions from which some sequence of rho_s transitions reaches W (W included)
        self.recoverable = recoverable
        self._safety = None
        self._relations: dict[int, object] = {}

    def safety_layers(self) -> list:
        """Primed safety levels, deepest first (case 3's preference)."""
        if self._safety is None:
            self._safety = [self.game.prime(S) for S in reversed(safety_levels(self.game))]
        return self._safety

    def goal_rings(self, j: int) -> list:
        """Alg. 1's B_(j,c) rings: positions c+1 rho_s steps from a transition meeting goal j into W."""
        game = self.game
        reached = game.sys_goals[j] & game.prime(self.winning)
        base = game.sys_rel.exist_and(reached, game.variables_next)
        return rings(game, base)

    def relation(self, j: int):
        """Every (x, y, x') with some rho_s move gets moves: rule 1, else 2, else 3."""
        if j in self._relations:
            return self._relations[j]
        game = self.game
        bdd = game.bdd
        outs = game.outputs_next
        trans = game.sys_rel
        relation = self.normal[j]
        covered = bdd.exist(outs, relation)
        if self.solution.sys_rel is not trans:  # cooperative restriction: rank the rest with full rho_s
            extra = layered_relation(game, self.solution, j, trans) & ~covered
            relation |= extra
            covered |= bdd.exist(outs, extra)
        goal_layers = None
        for ring in self.rings[1:]:
            block = trans.conjoin(game.prime(ring) & ~covered)
            if block == bdd.false:
                continue
            if goal_layers is None:
                goal_layers = [game.prime(r) for r in self.goal_rings(j)]
            block = prefer(game, block, goal_layers)
            relation |= block
            covered |= bdd.exist(outs, block)
        block = trans.conjoin(~covered)
        if block != bdd.false:
            relation |= prefer(game, block, self.safety_layers())
        self._relations[j] = relation
        return relation

    def classify(self, target: dict) -> tuple[bool, bool]:
        """(in W, in R) for a complete valuation of the current variables."""
        bdd = self.game.bdd
        in_w = bdd.let(target, self.winning) == bdd.true
        in_r = in_w or bdd.let(target, self.recoverable) == bdd.true
        return in_w, in_r


def unkeepable_clauses(game: Game, assign: dict, unknown_next: Sequence[str] = ()) -> list[Clause]:
    """A minimal set of sys-safety clauses that no next output satisfies together for the
    (current, next inputs) valuation ``assign`` — for every value of the next inputs ``unknown_next``
    (primed names) left out of it: the clauses false on their own when there are any, else a subset
    minimal by deletion."""
    bdd = game.bdd
    restricted = [(c, bdd.let(assign, u)) for c, u in game.clauses("sys_safety")]
    if unknown_next:  # forall distributes over the conjunction of the clauses
        restricted = [(c, bdd.forall(list(unknown_next), u)) for c, u in restricted]
    return unsatisfiable_core(bdd, restricted)


def unsatisfiable_core(bdd: Any, restricted: Sequence[tuple[Clause, Any]]) -> list[Clause]:
    """Of ``(clause, BDD)`` pairs whose BDDs have no common satisfying valuation: the clauses false
    on their own when there are any, else a subset minimal by deletion."""
    alone = [c for c, u in restricted if u == bdd.false]
    if alone:
        return alone
    core = list(restricted)
    k = 0
    while k < len(core):
        rest = core[:k] + core[k + 1:]
        acc = bdd.true
        for _, u in rest:
            acc &= u
        if acc == bdd.false:
            core = rest
        else:
            k += 1
    return [c for c, _ in core]
