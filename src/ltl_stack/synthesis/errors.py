"""Errors raised by synthesis and by executing a strategy."""
from __future__ import annotations

from ltl_stack.errors import Exit, UserError
from ltl_stack.spec.model import Clause


class SynthesisError(Exception):
    """Base class of the errors of ``ltl_stack.synthesis``."""


class UnrealizableError(SynthesisError):
    """A strategy was asked for but the specification is unrealizable."""


class NoInitialState(SynthesisError):
    """No winning initial position matches the requested (partial) valuation."""


class LimitReached(SynthesisError, UserError):
    """Work stopped at a limit the caller set (time, memory, states); exit code ``Exit.LIMIT``."""

    code = Exit.LIMIT


class TimeLimitReached(LimitReached):
    """The deadline passed (``synthesize --timeout``, ``Deadline``)."""


class MemoryLimitReached(LimitReached):
    """The BDD manager reached its memory cap (``synthesize --max-memory``)."""


class StrategyFileError(UserError, ValueError):
    """A saved strategy file that cannot be read or used with its spec; ``str()`` names the file,
    the state or edge, and the clause. Also a ``ValueError``, which ``Automaton.load`` raised before."""


class AssumptionViolation(SynthesisError):
    """The new inputs break the environment safety assumptions.

    ``clauses`` are the violated env-safety clauses; the message names their text and ``file:line``.
    """

    def __init__(self, clauses: list[Clause], inputs: dict[str, bool] | None = None) -> None:
        self.clauses = list(clauses)
        self.inputs = dict(inputs or {})
        if self.clauses:
            where = "; ".join(f"{c.location}: {c.text or '(no text)'}" for c in self.clauses)
        else:
            where = "no single clause is violated, but the inputs have no admissible successor"
        super().__init__(f"environment safety assumption violated: {where}")
