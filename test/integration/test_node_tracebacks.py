"""Every node script of the package starts on a real master without a Python traceback on its output
(timed_proposition_server printed an AttributeError at start-up and kept serving).

Each node is started with the parameters it needs, then the test waits until it has registered a
topic of its own with the master (it has built its publishers, servers and subscribers), stops it,
and reads everything it printed. The timed server also completes one goal first: its ``spin`` has
certainly run by then.
"""
from __future__ import annotations

from pathlib import Path

import pytest
from helpers import run_script, stop_all, wait_for

pytestmark = pytest.mark.ros

ROOT = Path(__file__).resolve().parents[2]
LOCK_SPEC = ROOT / "test" / "unit" / "runtime" / "lock.slugsin"

#: node script -> the arguments it needs to start (paths are filled in by the test)
NODES = {
    "action_proposition": ["_action:=/pick_server"],
    "controller_executor": [str(LOCK_SPEC)],
    "kitchen_world": [],
    "publish_on_edge": [],
    "region_sensor": ["_region:=kitchen", "_robot_location_topic:=/loc"],
    "scripted_environment": ["_schedule:={schedule}"],
    "set_color": [],
    "set_velocity": [],
    "sim_manipulation_server": [],
    "sim_navigation_server": [],
    "sim_robot": [],
    "story_environment": ["_story:={story}"],
    "timed_proposition_server": ["_action:=/timed", "_duration:=0.2"],
    "topic_threshold_sensor": ["_topic:=/level", "_type:=std_msgs/Float64", "_field:=data"],
}


def own_topics(master, node: str) -> list[str]:
    publishers, subscribers, _ = master.system_state()
    return [topic for topic, nodes in publishers + subscribers if node in nodes and topic != "/rosout"]


def test_every_node_starts_without_a_traceback(ros_master, tmp_path):
    schedule = tmp_path / "schedule.yaml"
    schedule.write_text("events:\n  - {at: 0.0, topic: /env/flag, value: false}\n")
    story = ROOT / "config" / "alice" / "story.yaml"
    started = {}
    for script, args in NODES.items():
        args = [a.format(schedule=schedule, story=story) for a in args]
        started[script] = ros_master.run(["rosrun", "ltl_stack", script, *args, f"__name:={script}_probe"],
                                         name=script)
    for script, proc in started.items():
        wait_for(lambda script=script, proc=proc: own_topics(ros_master, f"/{script}_probe") or not proc.running(),
                 120, f"{script} to register a topic")
    # a node that exits at start-up without a traceback (say, on a parameter it refuses) started nothing
    exited = {script: proc.output()[-2000:] for script, proc in started.items() if not proc.running()}
    goal = run_script(["rosrun", "ltl_stack", "send_proposition_goal", "/timed", "--timeout", "120"],
                      capture_output=True, text=True, timeout=300, env=ros_master.env, check=False)
    assert goal.returncode == 0 and "completed=True" in goal.stdout, (goal.stdout, goal.stderr)
    stop_all(list(started.values()))
    printed = {script: proc.output() for script, proc in started.items()}
    assert not [s for s, out in printed.items() if "Traceback" in out], \
        {s: out[-2000:] for s, out in printed.items() if "Traceback" in out}
    assert not exited, f"nodes that exited at start-up instead of serving: {exited}"
