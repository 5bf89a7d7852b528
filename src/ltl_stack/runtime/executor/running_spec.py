"""What an executor runs, as it tells viewers (``~source``, ``ltl_stack/ControllerSource``), free of ROS.

A view that draws a controller must draw the automaton the executor runs, not a file the user named:
smach_viewer draws the structure the running machine publishes. The executor publishes, latched, the
spec of its running strategy (path, SHA-256 and text), the strategy generation, the synthesis options
that change the automaton and its start time; the view compares the SHA-256 with the file it was given
and follows a restart (a new start time) or a new strategy (a new generation).
"""
from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from typing import Any

from ltl_stack.runtime.executor.node_reports import strategy_source
from ltl_stack.synthesis import DEFAULT_OPTIONS

#: The largest spec text sent on ~source (a larger one is sent by path and digest only).
MAX_TEXT = 1_000_000


@dataclass(frozen=True)
class RunningSpec:
    """One ``~source`` message's content (see ``msg/ControllerSource.msg``)."""

    spec_file: str
    spec_sha256: str
    spec_text: str
    strategy_file: str
    generation: int
    robotics_semantics: bool
    cooperative: bool
    max_explicit_states: int

    @property
    def key(self) -> tuple[int, str, str]:
        """What identifies the strategy drawn: its generation, spec file and content."""
        return (self.generation, self.spec_file, self.spec_sha256)


def spec_digest(text: str) -> str:
    """The SHA-256 of a spec's text (hex), as ``~source`` carries it."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def read_spec(path: str) -> tuple[str, str]:
    """``(text, sha256)`` of the spec file at ``path``; ``("", "")`` when it cannot be read."""
    if not path:
        return "", ""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError):
        return "", ""
    return text, spec_digest(text)


def running_spec(original: str, resilient: Any | None, options: Any) -> RunningSpec:
    """What the executor runs: ``original`` is the spec it was started with, ``resilient`` its
    ``BackgroundResilience`` (None without characterization), ``options`` its ``setup.Options``
    (unset synthesis options take the library's defaults, as ``build_strategy`` synthesizes)."""
    path, generation = strategy_source(original, resilient)
    text, digest = read_spec(path)
    robotics = options.robotics_semantics
    cooperative = options.cooperative
    return RunningSpec(
        spec_file=path, spec_sha256=digest, spec_text=text if len(text) <= MAX_TEXT else "",
        strategy_file=os.path.abspath(options.strategy) if options.strategy else "", generation=generation,
        robotics_semantics=DEFAULT_OPTIONS.robotics_semantics if robotics is None else bool(robotics),
        cooperative=DEFAULT_OPTIONS.cooperative if cooperative is None else bool(cooperative),
        max_explicit_states=max(0, int(options.max_explicit_states)))


__all__ = ["MAX_TEXT", "RunningSpec", "read_spec", "running_spec", "spec_digest"]
