"""Thesis Example 12 (§4.10.2) end to end on a real master, as test_resilience_scenarios.py runs Example 11
(a module of its own so that pytest-xdist runs it beside the Example 11 runs)."""
from __future__ import annotations

import pytest
from test_resilience_scenarios import demo, index, regions_between

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def test_patrol_recycling_recovery_and_characterization(ros_master):
    """Example 12 as §4.10.2 narrates it: the metal item in paper_deposit and the manager's early tap
    are recovered; the alarm with a spill outlasts the threshold, is characterized, unrealizable;
    the user adds GF !spill; the robot waits, then notifies the manager; one resynthesis in all."""
    events = demo(ros_master, "patrol_recycling", timeout=180)
    summary = events[-1]
    assert summary["resyntheses"] == 1 and summary["resyntheses_user"] == 1 and summary["unrealizable"] >= 1
    metal = index(events, lambda e: e.get("message", "").startswith("story: dropping it in paper_deposit"))
    spill = index(events, lambda e: "a spill (A2 broken)" in e.get("message", ""))
    asked = index(events, lambda e: e.get("message", "").startswith("user: adds the env liveness GF(!spill)"))
    cleaned = index(events, lambda e: e.get("message", "").startswith("story: the spill is cleaned up"))
    tap = index(events, lambda e: "taps its head" in e.get("message", ""))
    assert metal < spill < asked < cleaned < tap
    # the story's message and the executor's ~state travel on two topics, and the recovery's ~state can
    # reach the demo before the metal beat's message: look from the start (no assumption breaks before
    # the metal item; the first beat's message may be told before the demo listens, so it is no bound)
    modes = [e for e in events[:spill] if e["event"] == "mode"]
    assert any(e["mode"] == "recovering" for e in modes), ("the metal item is recovered", events[:spill])
    assert not [e for e in events[:spill] if e["event"] == "resynthesis"], "no resynthesis before the spill"
    # the tap fires on the ~state that shows notify (only in the office), and the demo may get that
    # state's "at office" after the story's message (two topics): look after the spill, not before the tap
    assert "office" in regions_between(events, cleaned, len(events)), "it reports in the office after the spill"
