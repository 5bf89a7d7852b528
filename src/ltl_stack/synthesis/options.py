"""The one set of synthesis defaults every tool shares, and the limits of one synthesis run.

``synthesize`` (library and command), ``controller_executor`` and ``analyze_graph --apply`` solve
with the same ``SynthesisOptions`` unless a flag says otherwise, and print ``describe()`` so a user
sees which ones were used. The default is what a robot needs (thesis §4.6): robotics init semantics
(every position allowed by env_init and sys_init must be winning, slugs'
``--sysInitRoboticsSemantics``) and the cooperative strategy (never force the environment to break
its assumptions, help it reach its liveness goals; slugs' ``--cooperativeGR1Strategy``).

``Limits`` bound one run: a deadline (``Deadline``, checked between BDD operations inside every
fixpoint loop) and the BDD manager's memory cap (``memory_cap``), both ending in ``Exit.LIMIT``.
"""
from __future__ import annotations

import argparse
import os
import re
import resource
import time
from dataclasses import dataclass

from ltl_stack.synthesis.errors import TimeLimitReached

#: the cap when nothing else is said: the machine is shared, so fail rather than swap
DEFAULT_MAX_MEMORY = 4 * 2**30
#: CUDD's own estimate for sizing its tables. Creating a manager also reserves a "stash" of 1/64
#: of it (kept for running out of memory): 2**30 cost ~1-7 ms of every ``synthesize`` process
#: (start-up time). The estimate also sizes CUDD's computed table and unique-table policies, so it must
#: not be small: 2**24 made factory_assembly_7x5_2_0 3x slower (7.0 -> 22 s CPU), 2**27 made
#: basicEvasion 1.3x slower (21-27 s at 2**30, 28-36 s at 2**27, 21-29 s at 2**28, load ~1).
#: 2**28: a 4 MiB stash, ~0.5 ms to create. The cap itself is ``max_memory``.
MANAGER_ESTIMATE = 2**28
#: nodes up to which CUDD's unique table grows eagerly (``loose_up_to``): the value a 2**30 estimate
#: gave (bytes / 32-byte node / 5), kept when the estimate was lowered so large specs run as before
LOOSE_UP_TO = 2**30 // 160


@dataclass(frozen=True)
class SynthesisOptions:
    """Init semantics and strategy kind of a synthesis run (the defaults are every tool's defaults)."""

    robotics_semantics: bool = True
    cooperative: bool = True

    def describe(self) -> str:
        """One phrase for logs and text output, e.g. ``robotics init semantics, cooperative strategy``."""
        semantics = "robotics init semantics" if self.robotics_semantics else "slugs' default init semantics"
        strategy = "cooperative strategy" if self.cooperative else "non-cooperative strategy"
        return f"{semantics}, {strategy}"

    def to_dict(self) -> dict[str, bool]:
        """The options as JSON fields (``--json`` summaries, strategy metadata)."""
        return {"robotics_semantics": self.robotics_semantics, "cooperative": self.cooperative}


DEFAULT_OPTIONS = SynthesisOptions()


def add_option_flags(parser: argparse.ArgumentParser) -> None:
    """``--robotics-semantics/--no-robotics-semantics`` and ``--cooperative/--no-cooperative``.

    Both default to ``None`` (not given), so a tool can merge them with parameters; ``options_from``
    fills what is still ``None`` from ``DEFAULT_OPTIONS``.
    """
    _add_switch(parser, "robotics-semantics",
                "every position satisfying env_init and sys_init must be winning (default); "
                "--no-robotics-semantics: slugs' default init semantics (for every allowed "
                "initial input some sys_init answer is winning)")
    _add_switch(parser, "cooperative",
                "never force the environment to break its assumptions and help it reach its "
                "liveness goals (default); --no-cooperative: any winning move")


def _add_switch(parser: argparse.ArgumentParser, name: str, help: str) -> None:
    """``--NAME`` sets True, ``--no-NAME`` False (the last one given wins), neither leaves None
    (argparse's ``BooleanOptionalAction``, which Python 3.8 lacks)."""
    dest = name.replace("-", "_")
    parser.add_argument(f"--{name}", dest=dest, action="store_true", default=None, help=help)
    parser.add_argument(f"--no-{name}", dest=dest, action="store_false", default=None, help=argparse.SUPPRESS)


def options_from(robotics_semantics: bool | None = None, cooperative: bool | None = None) -> SynthesisOptions:
    """``SynthesisOptions`` with every ``None`` replaced by the default."""
    return SynthesisOptions(
        DEFAULT_OPTIONS.robotics_semantics if robotics_semantics is None else bool(robotics_semantics),
        DEFAULT_OPTIONS.cooperative if cooperative is None else bool(cooperative))


class Deadline:
    """A point in time after which long work stops with ``TimeLimitReached``.

    ``check()`` costs one clock read; the fixpoint loops call it between BDD operations, so a run
    ends within one operation of the deadline.
    """

    __slots__ = ("seconds", "at")

    def __init__(self, seconds: float | None = None):
        if seconds is not None and not seconds > 0:
            raise ValueError(f"a timeout must be a positive number of seconds, got {seconds!r}")
        self.seconds = seconds
        self.at = None if seconds is None else time.monotonic() + seconds

    def check(self) -> None:
        """Raise ``TimeLimitReached`` once the deadline has passed."""
        if self.at is not None and time.monotonic() > self.at:
            raise TimeLimitReached(f"gave up after {self.seconds:g} s (the time limit, --timeout)")

    def remaining(self) -> float | None:
        """Seconds left (never negative), or None without a deadline."""
        return None if self.at is None else max(0.0, self.at - time.monotonic())


NO_DEADLINE = Deadline()


def memory_cap(requested: int | None = None) -> int:
    """The byte cap for a BDD manager: ``requested`` (or ``DEFAULT_MAX_MEMORY``), lowered to stay
    inside an address-space limit (``ulimit -v``) with room for Python, so CUDD refuses to grow
    (a clean ``MemoryLimitReached``) before ``malloc`` fails (which CUDD answers by exiting)."""
    cap = DEFAULT_MAX_MEMORY if requested is None else int(requested)
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY:
        room = soft - _address_space_in_use()
        cap = min(cap, max(room // 2, 2**20))
    return cap


def _address_space_in_use() -> int:
    try:
        with open("/proc/self/statm") as f:
            pages = int(f.read().split()[0])
        return pages * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        return 0


def parse_size(text: str) -> int:
    """``512M``, ``4G``, ``1.5G``, ``100000000`` (bytes) as a number of bytes; ValueError otherwise."""
    units = {"K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}
    word = re.sub(r"I?B?$", "", text.strip().upper(), count=1)
    factor = 1
    if word and word[-1] in units:
        factor, word = units[word[-1]], word[:-1]
    try:
        value = float(word)
    except ValueError:
        raise ValueError(f"expected a size such as 512M or 4G, got {text!r}") from None
    if not value > 0 or value == float("inf"):
        raise ValueError(f"a size must be positive, got {text!r}")
    return int(value * factor)
