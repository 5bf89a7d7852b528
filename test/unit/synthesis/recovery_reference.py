"""Explicit reference of the recovery rules (thesis §4.6), for checking the engine's recovery moves.

Shares no code with ``ltl_stack.synthesis.recovery``: it works on ``reference_solver``'s numpy arrays.

- ``ring_distance``: for each position, the fewest rho_s transitions (any inputs, some outputs) to
  the reference W (0 inside W, -1 when W cannot be reached: outside the recoverable region);
- ``safety_depth``: for each position, how many more steps the robot can keep rho_s whatever inputs
  come (capped; the greatest fixpoint gets the cap).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import reference_solver

from ltl_stack.spec.formula import evaluate

CAP = 64


@dataclass
class Reference:
    game: reference_solver.Game
    winning: np.ndarray        # (x, y)
    distance: np.ndarray       # (x, y): rho_s steps to W, -1 when unreachable
    depth: np.ndarray          # (x, y): steps of guaranteed safety, CAP = forever (within the cap)

    def index(self, spec, valuation) -> tuple[int, int]:
        x = sum(int(bool(valuation[n])) << k for k, n in enumerate(spec.inputs))
        y = sum(int(bool(valuation[n])) << k for k, n in enumerate(spec.outputs))
        return x, y


def build(spec, cooperative: bool = False) -> Reference:
    game = reference_solver.build_game(spec, cooperative=cooperative)
    winning = reference_solver.winning_positions(game)
    # plain rho_s (the cooperative restriction only shapes W)
    sys_trans = reference_solver.build_game(spec).sys_trans
    distance = np.where(winning, 0, -1)
    k = 0
    while True:
        k += 1
        reached = distance >= 0
        # positions with some rho_s transition into a position already reached
        can = (sys_trans & reached[None, None, :, :]).any(axis=(2, 3))
        new = can & ~reached
        if not new.any():
            break
        distance[new] = k
    depth = np.full(winning.shape, 0)
    safe = np.ones(winning.shape, dtype=bool)
    for level in range(1, CAP + 1):
        keep = (sys_trans & safe[None, None, :, :]).any(axis=3).all(axis=2)
        new_safe = safe & keep
        depth[new_safe] = level
        if (new_safe == safe).all():
            depth[new_safe] = CAP
            break
        safe = new_safe
    return Reference(game, winning, distance, depth)


def safe_moves(spec, current: dict, new_inputs: dict, outputs_list: list[dict]) -> list[dict]:
    """The output valuations that keep every sys-safety clause for (current, new inputs)."""
    return [y for y in outputs_list
            if all(evaluate(c.formula, current, {**new_inputs, **y}) for c in spec.sys_safety)]
