"""Edges and staleness of a Boolean signal, the ROS-free core of the proposition nodes (thesis 3.5.1).

An output proposition node reacts to the *edges* of its proposition (``EdgeDetector``); an input
proposition node notices when its sensing has stopped (``StaleWatch``). Times are passed in, so the
logic runs and is tested without ROS.
"""
from __future__ import annotations

import threading
from enum import Enum


class Edge(Enum):
    """A change of a Boolean signal."""

    RISING = "rising"
    FALLING = "falling"


RISING = Edge.RISING
FALLING = Edge.FALLING


class EdgeDetector:
    """Turns a stream of Booleans into rising/falling edges. The value starts false."""

    def __init__(self, initial: bool = False) -> None:
        self.value = bool(initial)

    def update(self, value: bool) -> Edge | None:
        """Record ``value``; return RISING, FALLING or None when it did not change."""
        value = bool(value)
        if value == self.value:
            return None
        self.value = value
        return RISING if value else FALLING


class StaleWatch:
    """Tells when sensing has not arrived for ``after`` seconds. ``after <= 0`` disables it."""

    def __init__(self, after: float, now: float) -> None:
        self.after = float(after)
        self._last = now
        self.stale = False
        self._lock = threading.Lock()

    def seen(self, now: float) -> bool:
        """Record fresh sensing; return whether it ends a stale period."""
        with self._lock:
            self._last = now
            ended, self.stale = self.stale, False
        return ended

    def check(self, now: float) -> bool:
        """Return True exactly once when the sensing becomes stale."""
        with self._lock:
            if self.after <= 0 or self.stale or now - self._last < self.after:
                return False
            self.stale = True
            return True


__all__ = ["FALLING", "RISING", "Edge", "EdgeDetector", "StaleWatch"]
