"""Explicit reference of the recovery rules (thesis §4.6), for checking the engine's recovery moves.

Shares no code with ``ltl_stack.synthesis.recovery``: it works on ``reference_solver``'s numpy arrays.

- ``ring_distance``: for each position, the fewest rho_s transitions (any inputs, some outputs) to
  the reference W (0 inside W, -1 when W cannot be reached: outside the recoverable region);
- ``safety_depth``: for each position, how many more steps the robot can keep rho_s whatever inputs
  come (capped; the greatest fixpoint gets the cap);
- ``model_check``: the properties an exported recovery automaton must have (see its docstring), from
  the automaton and the spec's formulas only.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import reference_solver

from ltl_stack.spec.formula import evaluate
from ltl_stack.synthesis.automaton import Automaton

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


# --- the independent model check of exported recovery automata ---------------------------------
def valuations(names):
    return [dict(zip(names, bits)) for bits in itertools.product((False, True), repeat=len(names))]


def key(inputs: dict, names: list[str]) -> tuple:
    return tuple(bool(inputs[n]) for n in names)


def model_check(spec, automaton: Automaton, plain: Automaton, winning) -> dict:
    """Assert what an exported recovery automaton must be; ``winning(valuation)`` is W from an
    independent solver, ``plain`` the automaton exported without recovery. Returns edge counts.

    - every edge satisfies the system safety;
    - every (state, input) for which some next output satisfies the system safety has exactly one
      edge; none has an edge when no output does;
    - from a winning state an admissible input never leads out of W, and that edge is the ordinary
      strategy's (not marked recovery, and the same target as in ``plain``);
    - an edge is marked recovery exactly when the input breaks env safety or the state is outside W;
    - ``plain`` is exactly the part of it that ordinary edges reach, with the same state ids.
    """
    by_id = {s.id: s for s in automaton.states}
    outputs = valuations(spec.outputs)
    inputs = valuations(spec.inputs)
    counts = {"edges": 0, "recovery": 0}
    for s in automaton.states:
        current = {**s.inputs, **s.outputs}
        here_winning = winning(current)
        assert set(s.recovery) <= set(s.successors)
        answered = {}
        for t in s.successors:
            target = by_id[t]
            k = key(target.inputs, spec.inputs)
            assert k not in answered, f"state {s.id} answers {target.inputs} twice"
            answered[k] = target
            nxt = {**target.inputs, **target.outputs}
            assert all(evaluate(c.formula, current, nxt) for c in spec.sys_safety), (s, target)
            admissible = all(evaluate(c.formula, current, target.inputs) for c in spec.env_safety)
            assert (t in s.recovery) == (not (here_winning and admissible)), (s.id, t)
            if here_winning and admissible:
                assert winning(nxt), f"{s.id} -> {t} leaves W on an admissible input"
        for x in inputs:
            can = any(all(evaluate(c.formula, current, {**x, **y}) for c in spec.sys_safety) for y in outputs)
            assert (key(x, spec.inputs) in answered) == can, (s.id, x, can)
        counts["edges"] += len(s.successors)
        counts["recovery"] += len(s.recovery)
    # the ordinary automaton is the part reached without recovery edges, state for state
    ordinary = set(automaton.initial)
    todo = list(automaton.initial)
    while todo:
        n = todo.pop()
        for t in by_id[n].successors:
            if t not in by_id[n].recovery and t not in ordinary:
                ordinary.add(t)
                todo.append(t)
    assert len(ordinary) == len(plain.states)
    for s in plain.states:
        twin = automaton.find(s.inputs, s.outputs, s.goal)
        assert twin is not None and twin.id in ordinary and twin.id == s.id, (s.id, twin)
        plain_targets = sorted((key(plain.states[t].inputs, spec.inputs), key(plain.states[t].outputs, spec.outputs),
                                plain.states[t].goal) for t in s.successors)
        rec_targets = sorted((key(by_id[t].inputs, spec.inputs), key(by_id[t].outputs, spec.outputs), by_id[t].goal)
                             for t in twin.successors if t not in twin.recovery)
        assert plain_targets == rec_targets, s.id
    return counts
