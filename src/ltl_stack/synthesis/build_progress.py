"""Progress while a game's BDDs are built: a large circuit (a multiplier written clause by clause)
can take minutes before the fixpoint's own progress starts.

A line comes between two BDD operations (each one ``Game.to_bdd`` and the conjunctions make) once
both ``every`` operations and ``interval`` seconds have passed since the last line: a fast build
prints nothing, a slow one a line every few seconds whether its time goes into many small operations
or a few large ones (a multiplier's middle bits: a few hundred operations, minutes). Tests set
``interval`` to 0 and count lines against operations. One operation that alone takes minutes reports
nothing while it runs. The callback is the tool's usual one (``synthesize`` prints on stderr after
its first second, nothing under ``--quiet``).
"""
from __future__ import annotations

import time
from collections.abc import Callable

#: BDD operations between two progress lines (at least)
EVERY = 1
#: seconds between two progress lines (at least)
INTERVAL = 2.0


class BuildProgress:
    """Counts BDD operations of a game's construction and reports where it is."""

    def __init__(self, progress: Callable[[str], None], clauses: int, *, every: int | None = None,
                 interval: float | None = None, clock: Callable[[], float] = time.monotonic) -> None:
        """``every`` and ``interval`` default to the module's ``EVERY`` and ``INTERVAL`` as they are
        when the game is built (a test sets them)."""
        self.progress = progress
        self.clauses = clauses  # in all sections
        self.every = every = EVERY if every is None else every
        self.interval = INTERVAL if interval is None else interval
        self.clock = clock
        self.operations = 0
        self.done = 0  # clauses turned into BDDs so far
        self.stage = "reading clauses"
        self._next = every
        self._last = clock()

    def at(self, stage: str) -> None:
        """The construction moved on to ``stage`` (a section's clause, a conjunction)."""
        self.stage = stage

    def clause_done(self) -> None:
        self.done += 1

    def tick(self) -> None:
        """One BDD operation: report when ``every`` of them and ``interval`` seconds passed since the last line."""
        self.operations += 1
        if self.operations < self._next:
            return
        self._next = self.operations + self.every
        now = self.clock()
        if now - self._last < self.interval:
            return
        self._last = now
        self.progress(f"building the BDDs: {self.stage} ({self.done:,}/{self.clauses:,} clauses, "
                      f"{self.operations:,} BDD operations)")
