"""The clean-and-patrol story (thesis Fig. 3.10) told from a controller trace (ROS-free)."""
from __future__ import annotations

from ltl_stack.runtime.runs.trace import TraceStep
from ltl_stack.sim.narration import KEYS, REGIONS, CleanAndPatrolStory

INPUTS = ["object", "pickup_ac", "drop_ac", *(f"{r}_rc" for r in REGIONS)]
OUTPUTS = ["pickup", "drop", "holdingObject", "sawObject", "stop", *REGIONS]


def step(t: float, true: set[str]) -> TraceStep:
    return TraceStep(t, int(t * 10), 0, {n: n in true for n in INPUTS}, {n: n in true for n in OUTPUTS})


def patrol(t: float, lanes) -> list[TraceStep]:
    out = []
    for here, there in zip(lanes, lanes[1:]):
        out.append(step(t, {f"{here}_rc", there}))
        t += 1
    return out


def thesis_run(object_after_laps: int = 1) -> list[TraceStep]:
    lap = ["topLane", "rightLane", "bottomLane", "leftLane"]
    steps = patrol(0, lap * object_after_laps + ["topLane", "rightLane", "bottomLane", "leftLane"])
    t = 100.0
    return steps + [
        step(t, {"bottomLane_rc", "object", "pickup", "sawObject"}),
        step(t + 1, {"bottomLane_rc", "pickup", "sawObject"}),
        step(t + 2, {"bottomLane_rc", "pickup_ac", "holdingObject"}),
        step(t + 3, {"bottomLane_rc", "holdingObject", "rightGround"}),
        step(t + 4, {"rightGround_rc", "bottomLane_rc", "holdingObject", "drop", "stop"}),  # crossing
        step(t + 5, {"rightGround_rc", "drop_ac"}),
        step(t + 6, {"rightGround_rc", "topLane"}),
    ]


def tell(steps) -> CleanAndPatrolStory:
    story = CleanAndPatrolStory()
    for s in steps:
        story.feed(s)
    return story


def test_the_thesis_run_tells_every_part_in_order_with_where_it_happened():
    story = tell(thesis_run())
    assert story.complete and [c.key for c in story.chapters] == list(KEYS)
    by_key = {c.key: c for c in story.chapters}
    assert by_key["object"].region == "bottomLane" and "after 1 lap(s)" in by_key["object"].text
    assert by_key["pickup"].region == "bottomLane" and by_key["drop"].region == "rightGround"
    assert "heads for topLane" in by_key["again"].text
    assert [c.figure for c in story.chapters] == ["3.10a", "3.10b", "3.10b", "3.10b", "3.10c", "3.10c", "3.10d"]


def test_an_object_before_a_whole_lap_stops_the_story_at_the_lap():
    """The old scenario: the object showed up in topLane before any lap; no part after (a) is told."""
    early = [step(0, {"topLane_rc", "rightLane"}), step(1, {"topLane_rc", "object", "pickup", "sawObject"}),
             *thesis_run()[-6:]]
    story = tell(early)
    assert story.chapters == [] and story.next_key == "lap"


def test_parts_out_of_order_are_not_told():
    run = thesis_run()
    without_drop = [s for s in run if not s.outputs["drop"]]
    story = tell(without_drop)
    assert [c.key for c in story.chapters] == list(KEYS[:4]) and not story.complete


def test_laps_count_entries_into_all_four_lanes():
    story = tell(thesis_run(object_after_laps=2)[:-7])
    assert story.laps == 2
