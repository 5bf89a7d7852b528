"""The thesis' story of Example 8 (Fig. 3.10 a-d) told from a controller trace. ROS-free.

``CleanAndPatrolStory`` reads the clean-and-patrol controller's states one by one (``TraceStep``)
and says when each part of the story happens: (a) the robot patrols the four lanes, (b) sees an
object, stops where it is and picks it up, (c) carries it to rightGround and drops it there,
(d) patrols again. Each part must follow the one before; the story is complete after (d).
The demo prints these lines next to the trace, so what the README says is what the run shows.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ltl_stack.runtime.runs.trace import TraceStep

LANES = ("topLane", "rightLane", "bottomLane", "leftLane")
REGIONS = (*LANES, "leftGround", "rightGround")


@dataclass(frozen=True)
class Chapter:
    """One part of the story: ``key`` (lap, object, pickup, carry, drop, dropped, again), the figure
    panel it shows, a sentence, and the state where it happened."""

    key: str
    figure: str
    text: str
    time: float
    state: int
    region: str  # where the robot is (``where``)

    def to_dict(self) -> dict:
        return {"event": "story", "chapter": self.key, "figure": self.figure, "text": self.text,
                "time": round(self.time, 3), "state": self.state, "region": self.region}


#: the parts in the order they must happen
KEYS = ("lap", "object", "pickup", "carry", "drop", "dropped", "again")


def where(step: TraceStep, previous: TraceStep | None = None) -> str:
    """The region the robot is in (``R_rc`` true). While it crosses a border the sensors of both
    regions may read true for a moment (each has its own topic): then the one just entered, the
    one not true in ``previous``; otherwise the regions '/'-joined, or '?' for none."""
    now = [r for r in REGIONS if step.inputs.get(f"{r}_rc")]
    if len(now) > 1 and previous is not None:
        entered = [r for r in now if not previous.inputs.get(f"{r}_rc")]
        if len(entered) == 1:
            return entered[0]
    return "/".join(now) or "?"


@dataclass
class CleanAndPatrolStory:
    chapters: list[Chapter] = field(default_factory=list)
    laps: int = 0
    _visited: list[str] = field(default_factory=list)
    _previous: TraceStep | None = None

    @property
    def complete(self) -> bool:
        return len(self.chapters) == len(KEYS)

    @property
    def next_key(self) -> str | None:
        return None if self.complete else KEYS[len(self.chapters)]

    def feed(self, step: TraceStep) -> list[Chapter]:
        """Read the next state; the parts of the story it completes (usually none)."""
        told = []
        self._count_laps(step)
        while not self.complete:
            chapter = self._check(step)
            if chapter is None:
                break
            self.chapters.append(chapter)
            told.append(chapter)
        self._previous = step
        return told

    def _count_laps(self, step: TraceStep) -> None:
        """A lap: all four lanes entered (``R_rc`` rising) since the last lap, before any object."""
        if self.chapters[1:]:  # the object was seen: patrolling is over for now
            return
        for lane in LANES:
            was = self._previous is not None and self._previous.inputs.get(f"{lane}_rc")
            if step.inputs.get(f"{lane}_rc") and not was and lane not in self._visited:
                self._visited.append(lane)
        if set(self._visited) == set(LANES):
            self.laps += 1
            self._visited = []

    def _check(self, step: TraceStep) -> Chapter | None:
        out, inp, key = step.outputs, step.inputs, self.next_key
        here = where(step, self._previous)

        def chapter(figure: str, text: str) -> Chapter:
            return Chapter(key, figure, text, step.time, step.state_id, here)
        if key == "lap" and self.laps >= 1:
            return chapter("3.10a", "the robot started in topLane and patrolled all four lanes "
                                    "(topLane, rightLane, bottomLane, leftLane)")
        if key == "object" and inp.get("object"):
            return chapter("3.10b", f"after {self.laps} lap(s) the robot sees an object in {here}")
        if key == "pickup" and out.get("pickup"):
            return chapter("3.10b", f"it stops in {here} and picks the object up")
        if key == "carry" and out.get("holdingObject") and out.get("rightGround"):
            return chapter("3.10b", f"pick-up finished; holding the object, it heads from {here} to rightGround")
        if key == "drop" and out.get("drop"):
            return chapter("3.10c", f"it stops in {here} and drops the object")
        if key == "dropped" and inp.get("drop_ac") and not out.get("holdingObject"):
            return chapter("3.10c", f"drop finished in {here}; it holds nothing")
        if key == "again":
            lanes = [lane for lane in LANES if out.get(lane)]
            if lanes:
                return chapter("3.10d", f"it patrols again: from {here} it heads for {lanes[0]}")
        return None
