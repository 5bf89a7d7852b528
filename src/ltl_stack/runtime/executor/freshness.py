"""How old an input reading may be before the executor treats the input as unknown, free of ROS.

The executor keeps the last reading of every input; over a partition or with a dead sensor that
reading goes on standing for the truth. Each input gets a *freshness bound*: a reading older than
it makes the input unknown (``Controller.set_unknown``: outputs safe for every value of it, nothing
stepped), until a new message arrives.

The bound of an input, in this order:

* ``freshness: S`` in its mapping entry (seconds; 0: never stale);
* derived from its node's publish rate when the mapping names one of our input proposition nodes,
  which republish their Boolean every 1/rate s (``~rate``, default ``DEFAULT_RATE``): ``FRESH_PERIODS``
  periods, at least ``MIN_BOUND`` s (a busy machine delays timers); rate 0 (only on change): none;
* else the executor's ``--freshness`` (default 0: none — a publisher of unknown rate may well
  publish only on change).

An input with a bound that has *never* reported holds the start for ``--ready-timeout`` s (the ready
handshake); after that it is unknown too, so that a robot starts while a peer's host is down, its
outputs keeping ``[SYS_INIT]`` (and then rho_s) for every value of the peer's propositions. An input
without a bound goes on holding the start (its node may publish only on change).
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

#: Our input proposition nodes: they republish their Boolean at ``~rate`` Hz (``ros.proposition_node``).
RATE_NODES = frozenset({"topic_threshold_sensor", "topic_predicate_sensor", "region_sensor", "region_localization"})
#: Their default ``~rate`` (Hz).
DEFAULT_RATE = 10.0
#: Publish periods an input may miss before it is stale.
FRESH_PERIODS = 5
#: The smallest derived bound (s).
MIN_BOUND = 2.0


def bound_for_rate(rate: float) -> float:
    """The bound derived from a publish rate (Hz); 0 (never stale) for rate 0."""
    if rate <= 0:
        return 0.0
    return max(FRESH_PERIODS / rate, MIN_BOUND)


def freshness_bounds(mapping: Any, inputs: Iterable[str], default: float = 0.0) -> dict[str, float]:
    """Every input's freshness bound (seconds; 0: never stale), from ``mapping`` (a
    ``runtime.config.mapping.Mapping`` or None) as the module docstring says."""
    bounds = {}
    for prop in inputs:
        entries = (mapping.inputs.get(prop) or []) if mapping is not None else []
        bound = default
        for entry in entries:
            if entry.freshness is not None:
                bound = entry.freshness
                break
            if entry.executable in RATE_NODES:
                rate = entry.parameters.get("rate", DEFAULT_RATE)
                usable = isinstance(rate, (int, float)) and not isinstance(rate, bool)
                bound = bound_for_rate(float(rate)) if usable else default
                break
        bounds[prop] = float(bound)
    return bounds


class Freshness:
    """When each input last reported, and which ones are stale now (times: ``time.monotonic``)."""

    def __init__(self, bounds: Mapping[str, float]) -> None:
        self.bounds = {p: float(b) for p, b in bounds.items()}
        self._seen: dict[str, float] = {}

    @property
    def active(self) -> bool:
        """Some input can go stale."""
        return any(b > 0 for b in self.bounds.values())

    def seen(self, prop: str, now: float) -> None:
        """A message of ``prop`` arrived at ``now``."""
        self._seen[prop] = now

    def stale(self, now: float, unheard: Iterable[str] = ()) -> list[str]:
        """The inputs that reported once and not within their bound, in the bounds' order; with them
        the inputs of ``unheard`` that have a bound (never reported, and the start no longer waits
        for them: the executor passes them after ``--ready-timeout``). An input without a bound (0)
        is never stale, and one that never reported holds the start (the ready handshake)."""
        unheard = set(unheard)
        return [p for p, b in self.bounds.items()
                if b > 0 and (now - self._seen[p] > b if p in self._seen else p in unheard)]

    def age(self, prop: str, now: float) -> float | None:
        """Seconds since ``prop`` last reported (None: never)."""
        return now - self._seen[prop] if prop in self._seen else None

    def check_period(self) -> float:
        """How often to look for stale inputs: a quarter of the smallest bound, within [0.05, 0.5] s."""
        bounds = [b for b in self.bounds.values() if b > 0]
        return min(0.5, max(0.05, min(bounds) / 4)) if bounds else 0.0


def unknown_text(unknown: Iterable[str], topics: Mapping[str, str], freshness: Freshness, now: float) -> str:
    """``person (/ns/inputs/person, no message for 3.1 s > 2.0 s), ...``: the stale inputs, named."""
    parts = []
    for prop in unknown:
        age = freshness.age(prop, now)
        since = f"no message for {age:.1f} s > {freshness.bounds.get(prop, 0):.1f} s" if age is not None \
            else "no message yet"
        parts.append(f"{prop} ({topics.get(prop, '?')}, {since})")
    return ", ".join(parts)
