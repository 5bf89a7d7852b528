"""The package's generated message and action cross a real ROS master between real nodes."""
from __future__ import annotations

import json

import pytest

pytestmark = pytest.mark.ros


def _json_lines(text: str) -> list[dict]:
    return [json.loads(line) for line in text.splitlines() if line.startswith("{")]


def test_valuation_message_crosses_the_master(ros_master):
    monitor = ros_master.run(["rosrun", "ltl_stack", "proposition_monitor", "/demo/valuation",
                              "--json", "--count", "1"])
    ros_master.wait_for_subscriber("/demo/valuation")
    sender = ros_master.run(["rosrun", "ltl_stack", "set_propositions", "/demo/valuation",
                             "person=1,move=0,stop=true", "--wait-subscribers", "1"])
    assert sender.popen.wait(30) == 0, sender.output()
    assert monitor.popen.wait(30) == 0, monitor.output()
    received = _json_lines(monitor.output())
    assert [r["valuation"] for r in received] == [{"person": True, "move": False, "stop": True}], received
    assert received[0]["topic"] == "/demo/valuation"
    assert received[0]["stamp"] > 0, received


def test_set_propositions_rejects_a_bad_valuation_without_traceback(ros_master):
    sender = ros_master.run(["rosrun", "ltl_stack", "set_propositions", "/x", "person=maybe"])
    assert sender.popen.wait(30) == 2
    out = sender.output()
    assert "person=maybe" in out and "Traceback" not in out, out


def test_proposition_action_through_real_actionlib(ros_master):
    ros_master.run(["rosrun", "ltl_stack", "timed_proposition_server", "_action:=/pickup", "_duration:=0.5"])
    ros_master.wait_for_subscriber("/pickup/goal")
    client = ros_master.run(["rosrun", "ltl_stack", "send_proposition_goal", "/pickup", "--json"])
    assert client.popen.wait(30) == 0, client.output()
    events = _json_lines(client.output())
    assert {e["event"] for e in events} <= {"feedback", "result"}, events
    results = [e for e in events if e["event"] == "result"]
    assert results == [{"event": "result", "state": "SUCCEEDED", "completed": True}], events
    # Feedback and result travel on different topics: actionlib keeps each topic in order but does not
    # order one against the other, so the final feedback (progress 1.0) may come after the result and
    # never be printed. What it promises: progress arrives in order, within [0, 1].
    feedback = [e["progress"] for e in events if e["event"] == "feedback"]
    assert feedback, events
    assert feedback == sorted(feedback) and 0.0 <= feedback[0] and feedback[-1] <= 1.0, feedback


def test_cancelled_proposition_action_reports_not_completed(ros_master):
    ros_master.run(["rosrun", "ltl_stack", "timed_proposition_server", "_action:=/drop", "_duration:=5.0"])
    ros_master.wait_for_subscriber("/drop/goal")
    client = ros_master.run(["rosrun", "ltl_stack", "send_proposition_goal", "/drop", "--json",
                             "--cancel-after", "0.3"])
    assert client.popen.wait(30) == 1, client.output()
    result = _json_lines(client.output())[-1]
    assert result == {"event": "result", "state": "PREEMPTED", "completed": False}, result
