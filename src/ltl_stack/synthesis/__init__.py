"""GR(1) synthesis on BDDs (dd): realizability, strategies, explanations, export.

    synthesize(spec, robotics_semantics=True, cooperative=True, timeout=None, max_memory=None)
        -> SynthesisResult
    is_realizable(spec, robotics_semantics=True) -> bool

The defaults are the one set every tool shares (``options.SynthesisOptions``: robotics init
semantics, cooperative strategy); ``result.options.describe()`` says which were used. A ``timeout``
(or a shared ``Deadline``) ends the work with ``TimeLimitReached`` and the memory cap with
``MemoryLimitReached`` (both ``Exit.LIMIT``).

Modules, bottom up: ``options`` (defaults, limits), ``game`` (the BDD game), ``fixpoint`` (thesis
Eq. 4.2), ``automaton`` (explicit automaton and its JSON / slugs JSON / DOT files, checked against
a spec on load), ``explicit`` (thesis Alg. 1), ``strategy`` (symbolic strategy and ``step``),
``explain`` (why a spec is unrealizable) and ``explain_render`` (its text / dict / DOT), ``cli``.

``Automaton``, ``AutomatonState``, ``SymbolicStrategy`` and ``State`` are imported on first use
(PEP 562 module ``__getattr__``, as in ``ltl_stack.spec``): a realizability check (``synthesize
SPEC`` without an export) needs neither the strategy nor the automaton modules, nor the YAML and
JSON readers they pull in (~10 ms of a command's start-up).
"""
from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ltl_stack.lazy import lazy_exports
from ltl_stack.spec.model import Spec
from ltl_stack.synthesis.errors import (
    AssumptionViolation,
    LimitReached,
    MemoryLimitReached,
    NoInitialState,
    StrategyFileError,
    SynthesisError,
    TimeLimitReached,
    UnrealizableError,
)
from ltl_stack.synthesis.fixpoint import Options, Progress, Solution, solve
from ltl_stack.synthesis.game import BACKEND, Game, memory_guard
from ltl_stack.synthesis.options import DEFAULT_OPTIONS, Deadline, SynthesisOptions

if TYPE_CHECKING:  # pragma: no cover - for type checkers and readers only
    from ltl_stack.synthesis.automaton import Automaton, AutomatonState
    from ltl_stack.synthesis.strategy import State, SymbolicStrategy

_LAZY = {"Automaton": "automaton", "AutomatonState": "automaton", "State": "strategy", "SymbolicStrategy": "strategy"}

__all__ = [
    "BACKEND", "DEFAULT_OPTIONS", "Automaton", "AutomatonState", "AssumptionViolation", "Deadline", "Game",
    "LimitReached", "MemoryLimitReached", "NoInitialState", "Options", "Solution", "State", "StrategyFileError",
    "SymbolicStrategy", "SynthesisError", "SynthesisOptions", "SynthesisResult", "TimeLimitReached",
    "UnrealizableError", "is_realizable", "synthesize",
]


@dataclass
class SynthesisResult:
    realizable: bool
    strategy: SymbolicStrategy | None
    seconds: float
    game: Game
    solution: Solution
    #: the init semantics and strategy kind used (``options.describe()`` for a log line)
    options: SynthesisOptions = DEFAULT_OPTIONS


def synthesize(spec: Spec, *, robotics_semantics: bool = DEFAULT_OPTIONS.robotics_semantics,
               cooperative: bool = DEFAULT_OPTIONS.cooperative, progress: Progress | None = None,
               options: Options | None = None, timeout: float | None = None, deadline: Deadline | None = None,
               max_memory: int | None = None, strategy: bool = True) -> SynthesisResult:
    """Solve the game of ``spec`` and, when realizable, build its symbolic strategy.

    ``strategy=False`` answers realizability only (``result.strategy`` is None): the ordinary game
    is solved once, stopping as soon as the answer is known to be "no" (``Solution.complete``
    False), with no cooperative game and no strategy relations; the verdict is the same.

    The verdict is the spec's (cooperation never changes it). With ``cooperative`` the game is first
    solved without moves that leave the environment no admissible input; only if that loses is the
    ordinary game solved, and its strategy then avoids such moves wherever it can
    (``strategy.fully_cooperative`` is False).

    ``timeout`` seconds (or ``deadline``, to share one across calls) and ``max_memory`` bytes bound
    the run (``TimeLimitReached``, ``MemoryLimitReached``); ``options`` are the performance switches.
    """
    start = time.perf_counter()
    limit = deadline if deadline is not None else Deadline(timeout)
    game = Game(spec, max_memory=max_memory, deadline=limit, progress=progress)
    with memory_guard(game.max_memory):
        if not strategy:
            solution = solve(game, robotics_semantics=robotics_semantics, early_exit=True, options=options,
                             progress=progress)
            game.keep_order()
            return SynthesisResult(solution.realizable, None, time.perf_counter() - start, game, solution,
                                   SynthesisOptions(robotics_semantics, cooperative))
        solution = solve(game, robotics_semantics=robotics_semantics, cooperative=cooperative,
                         options=options, progress=progress)
        if cooperative and not solution.realizable:
            if progress:
                progress("no strategy avoids trapping the environment; solving the ordinary game")
            solution = solve(game, robotics_semantics=robotics_semantics, options=options, progress=progress)
        # looked up on the module: resolved on first use (module ``__getattr__``) and replaceable in tests
        strategy_class = sys.modules[__name__].SymbolicStrategy
        strategy = strategy_class(game, solution, cooperative=cooperative) if solution.realizable else None
        game.keep_order()
    return SynthesisResult(solution.realizable, strategy, time.perf_counter() - start, game, solution,
                           SynthesisOptions(robotics_semantics, cooperative))


def is_realizable(spec: Spec, *, robotics_semantics: bool = DEFAULT_OPTIONS.robotics_semantics,
                  options: Options | None = None, timeout: float | None = None,
                  max_memory: int | None = None) -> bool:
    """Realizability only (stops as soon as the answer is known to be "no")."""
    game = Game(spec, max_memory=max_memory, deadline=Deadline(timeout))
    with memory_guard(game.max_memory):
        realizable = solve(game, robotics_semantics=robotics_semantics, early_exit=True, options=options).realizable
    game.keep_order()
    return realizable


__getattr__, __dir__ = lazy_exports(__name__, _LAZY, __all__)
