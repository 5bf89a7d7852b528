"""GR(1) synthesis on BDDs (dd): realizability, strategies, explanations, export.

    synthesize(spec, robotics_semantics=True, cooperative=True) -> SynthesisResult
    is_realizable(spec, robotics_semantics=False) -> bool

See ``game`` (the BDD game), ``fixpoint`` (thesis Eq. 4.2), ``strategy`` (symbolic strategy and
``step``), ``explicit`` (thesis Alg. 1) and ``automaton`` (JSON / slugs JSON / DOT export).
"""
from __future__ import annotations

import time
from dataclasses import dataclass

from ltl_stack.spec.model import Spec
from ltl_stack.synthesis.automaton import Automaton, AutomatonState
from ltl_stack.synthesis.errors import AssumptionViolation, NoInitialState, SynthesisError, UnrealizableError
from ltl_stack.synthesis.fixpoint import Options, Progress, Solution, solve
from ltl_stack.synthesis.game import BACKEND, Game
from ltl_stack.synthesis.strategy import State, SymbolicStrategy

__all__ = [
    "BACKEND", "Automaton", "AutomatonState", "AssumptionViolation", "Game", "NoInitialState", "Options",
    "Solution", "State", "SymbolicStrategy", "SynthesisError", "SynthesisResult", "UnrealizableError",
    "is_realizable", "synthesize",
]


@dataclass
class SynthesisResult:
    realizable: bool
    strategy: SymbolicStrategy | None
    seconds: float
    game: Game
    solution: Solution


def synthesize(spec: Spec, *, robotics_semantics: bool = True, cooperative: bool = True,
               progress: Progress | None = None, options: Options | None = None) -> SynthesisResult:
    """Solve the game of ``spec`` and, when realizable, build its symbolic strategy.

    The verdict is the spec's (cooperation never changes it). With ``cooperative`` the game is first
    solved without moves that leave the environment no admissible input; only if that loses is the
    ordinary game solved, and its strategy then avoids such moves wherever it can
    (``strategy.fully_cooperative`` is False).
    """
    start = time.perf_counter()
    game = Game(spec)
    solution = solve(game, robotics_semantics=robotics_semantics, cooperative=cooperative,
                     options=options, progress=progress)
    if cooperative and not solution.realizable:
        if progress:
            progress("no strategy avoids trapping the environment; solving the ordinary game")
        solution = solve(game, robotics_semantics=robotics_semantics, options=options, progress=progress)
    strategy = SymbolicStrategy(game, solution, cooperative=cooperative) if solution.realizable else None
    return SynthesisResult(solution.realizable, strategy, time.perf_counter() - start, game, solution)


def is_realizable(spec: Spec, *, robotics_semantics: bool = False, options: Options | None = None) -> bool:
    """Realizability only (stops as soon as the answer is known to be "no")."""
    game = Game(spec)
    return solve(game, robotics_semantics=robotics_semantics, early_exit=True, options=options).realizable
