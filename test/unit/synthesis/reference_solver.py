"""An explicit-state GR(1) solver used only to check the BDD engine (differential testing).

It shares no code with ``ltl_stack.synthesis``: it reads the spec's formula dataclasses, evaluates them
with its own evaluator on every (x, y, x', y') combination, and computes the winning positions with the
transition-based fixpoint of thesis Eq. 4.2 on explicit arrays (numpy booleans, one cell per position).

Semantics (those of slugs, checked against its documented input format and algorithm):
- a position is a valuation (x, y) of inputs and outputs; the environment moves first (x'), the
  system answers having seen x' (Mealy): cpre(T) = {(x,y) | for all x': rho_e(x,y,x') implies
  exists y': rho_s(x,y,x',y') and T(x,y,x',y')}. So the system wins when the environment has no
  move that respects its safety;
- liveness formulas may mention primed variables: a goal is a set of transitions, not of positions;
- an empty liveness section means one ``true`` goal (as slugs adds);
- init: slugs' default ``forall x. env_init(x) -> exists y. sys_init(x,y) and W(x,y)``; robotics
  semantics ``forall x,y. env_init(x) and sys_init(x,y) -> W(x,y)``.
Small specs only: the arrays have 4^(inputs+outputs) cells.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ltl_stack.spec.formula import And, Const, Iff, Implies, Not, Or, Var, Xor

MAX_PROPOSITIONS = 10


class Grid:
    """Every (x, y, x', y') combination of a spec, as the axes of 4-dimensional boolean arrays."""

    def __init__(self, inputs: list[str], outputs: list[str]):
        if len(inputs) + len(outputs) > MAX_PROPOSITIONS:
            raise ValueError(f"{len(inputs) + len(outputs)} propositions: too many for the explicit solver")
        self.inputs = list(inputs)
        self.outputs = list(outputs)
        self.nx = 2 ** len(inputs)
        self.ny = 2 ** len(outputs)
        self.shape = (self.nx, self.ny, self.nx, self.ny)

    def var_array(self, name: str, primed: bool) -> np.ndarray:
        """The truth value of ``name`` (or ``name'``) in every cell, broadcastable to ``shape``."""
        if name in self.inputs:
            bit, count, axis = self.inputs.index(name), self.nx, 2 if primed else 0
        elif name in self.outputs:
            bit, count, axis = self.outputs.index(name), self.ny, 3 if primed else 1
        else:
            raise KeyError(f"unknown proposition {name!r}")
        values = (np.arange(count) >> bit) & 1 == 1
        shape = [1, 1, 1, 1]
        shape[axis] = count
        return values.reshape(shape)

    def evaluate(self, formula) -> np.ndarray:
        """``formula`` in every cell (a full-shape boolean array)."""
        return np.broadcast_to(self._eval(formula), self.shape)

    def _eval(self, f) -> np.ndarray | bool:
        if isinstance(f, Var):
            return self.var_array(f.name, f.primed)
        if isinstance(f, Const):
            return np.bool_(f.value)
        if isinstance(f, Not):
            return np.logical_not(self._eval(f.arg))
        if isinstance(f, And):
            result = np.bool_(True)
            for arg in f.args:
                result = np.logical_and(result, self._eval(arg))
            return result
        if isinstance(f, Or):
            result = np.bool_(False)
            for arg in f.args:
                result = np.logical_or(result, self._eval(arg))
            return result
        left, right = self._eval(f.left), self._eval(f.right)
        if isinstance(f, Xor):
            return np.logical_xor(left, right)
        if isinstance(f, Implies):
            return np.logical_or(np.logical_not(left), right)
        if isinstance(f, Iff):
            return np.logical_not(np.logical_xor(left, right))
        raise TypeError(f"not a formula: {f!r}")

    def conjunction(self, clauses) -> np.ndarray:
        result = np.ones(self.shape, dtype=bool)
        for clause in clauses:
            result &= self.evaluate(clause.formula)
        return result


@dataclass
class Game:
    """The explicit game of a spec: arrays over positions (x, y) and transitions (x, y, x', y')."""

    grid: Grid
    env_init: np.ndarray      # (x, y); depends on x only
    sys_init: np.ndarray      # (x, y)
    env_trans: np.ndarray     # (x, y, x'); env safety never mentions y'
    sys_trans: np.ndarray     # (x, y, x', y')
    env_goals: list[np.ndarray]   # (x, y, x', y'), one per env liveness (true when none)
    sys_goals: list[np.ndarray]   # (x, y, x', y'), one per sys liveness (true when none)


def build_game(spec, cooperative: bool = False) -> Game:
    """Evaluate every section of ``spec`` on every cell.

    ``cooperative``: the robot may only move to positions where the environment still has an input
    that respects its safety (the game a strategy that never traps the environment must win)."""
    grid = Grid(spec.inputs, spec.outputs)
    full_env_trans = grid.conjunction(spec.env_safety)
    env_trans = full_env_trans[:, :, :, 0]
    if not (full_env_trans == env_trans[:, :, :, None]).all():
        raise ValueError("env safety mentions a primed output; slugs forbids that")
    env_goals = [grid.evaluate(c.formula) for c in spec.env_liveness] or [np.ones(grid.shape, dtype=bool)]
    sys_goals = [grid.evaluate(c.formula) for c in spec.sys_liveness] or [np.ones(grid.shape, dtype=bool)]
    sys_trans = grid.conjunction(spec.sys_safety)
    if cooperative:
        env_can_move = env_trans.any(axis=2)                      # (x, y)
        sys_trans = sys_trans & env_can_move[None, None, :, :]
    return Game(grid=grid,
                env_init=grid.conjunction(spec.env_init)[:, :, 0, 0],
                sys_init=grid.conjunction(spec.sys_init)[:, :, 0, 0],
                env_trans=env_trans,
                sys_trans=sys_trans,
                env_goals=env_goals,
                sys_goals=sys_goals)


def cpre(game: Game, transitions: np.ndarray) -> np.ndarray:
    """Positions from which the system can force the next transition into ``transitions``."""
    answer = (game.sys_trans & transitions).any(axis=3)          # (x, y, x')
    return (~game.env_trans | answer).all(axis=2)                # (x, y)


def primed(positions: np.ndarray) -> np.ndarray:
    """A set of positions seen as the set of transitions that end in it."""
    return positions[None, None, :, :]


def winning_positions(game: Game) -> np.ndarray:
    """nu Z. /\\_j mu Y. \\/_i nu X. cpre((G_j & Z') | Y' | (!A_i & X')), explicitly."""
    shape = game.env_init.shape
    z = np.ones(shape, dtype=bool)
    while True:
        new_z = np.ones(shape, dtype=bool)
        for goal in game.sys_goals:
            reach_goal = goal & primed(z)
            y = np.zeros(shape, dtype=bool)
            while True:
                closer = reach_goal | primed(y)
                new_y = y.copy()
                for assumption in game.env_goals:
                    x = np.ones(shape, dtype=bool)
                    while True:
                        new_x = cpre(game, closer | (~assumption & primed(x)))
                        if (new_x == x).all():
                            break
                        x = new_x
                    new_y |= x
                if (new_y == y).all():
                    break
                y = new_y
            new_z &= y
        if (new_z == z).all():
            return z
        z = new_z


def realizable_from(game: Game, winning: np.ndarray, robotics_semantics: bool) -> bool:
    """The init condition on top of the winning positions."""
    if robotics_semantics:
        return bool((~(game.env_init & game.sys_init) | winning).all())
    some_output = (game.sys_init & winning).any(axis=1)          # (x,)
    env_allows = game.env_init.any(axis=1)                       # env_init depends on x only
    return bool((~env_allows | some_output).all())


def is_realizable(spec, *, robotics_semantics: bool = False) -> bool:
    """Reference realizability verdict of ``spec`` (small specs only)."""
    game = build_game(spec)
    return realizable_from(game, winning_positions(game), robotics_semantics)


def cooperative_winning(game: Game) -> np.ndarray:
    """Positions with a run that env and system play together: both safety formulas hold forever and
    every liveness clause (env and system) holds on infinitely many transitions."""
    both = game.env_trans[:, :, :, None] & game.sys_trans
    shape = game.env_init.shape
    z = np.ones(shape, dtype=bool)
    while True:
        new_z = np.ones(shape, dtype=bool)
        for goal in game.sys_goals + game.env_goals:
            reach_goal = goal & primed(z)
            y = np.zeros(shape, dtype=bool)
            while True:
                new_y = (both & (reach_goal | primed(y))).any(axis=(2, 3))
                if (new_y == y).all():
                    break
                y = new_y
            new_z &= y
        if (new_z == z).all():
            return z
        z = new_z


def cooperative_possible(spec) -> bool:
    """Some position satisfying env_init and sys_init starts a cooperative run."""
    game = build_game(spec)
    return bool((game.env_init & game.sys_init & cooperative_winning(game)).any())
