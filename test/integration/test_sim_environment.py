"""scripted_environment against a real master: events fire on schedule, in order."""
from __future__ import annotations

import re
import time

import pytest
from helpers import wait_for
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits


@pytest.fixture
def ros(request):
    return make_session(request)


def test_scripted_events_fire_on_schedule(ros, tmp_path):
    from std_msgs.msg import Bool, Float64, String

    schedule = tmp_path / "env.yaml"
    schedule.write_text(f"""events:
  - {{at: 0.0, topic: {ros.topic('env/person')}, value: false}}
  - {{at: 0.6, topic: {ros.topic('env/person')}, value: true, name: a person shows up}}
  - {{at: 0.9, topic: {ros.topic('env/object_distance')}, type: std_msgs/Float64, value: {{data: 0.25}}}}
  - {{at: 1.5, topic: {ros.topic('env/person')}, value: false, name: the person leaves}}
""")
    person = ros.record(ros.topic("env/person"), Bool)
    distance = ros.record(ros.topic("env/object_distance"), Float64)
    node = ros.run("scripted_environment", f"_schedule:={schedule}", "_wait_for_subscribers:=10",
                   name="env")
    fired = ros.record(f"{ros.ns}_env/fired", String)
    person.wait(lambda ms: [m.data for m in ms] == [False, True, False], what="person false, true, false")
    distance.wait(lambda ms: len(ms) == 1, what="the object distance")
    assert distance.last().data == 0.25
    # The node logs each event with the scheduled clock's elapsed time when it fired. No event may
    # fire before its time, and they fire in schedule order; how late they fire depends on the load.
    fired_at = wait_for(lambda: _fired_times(node.output()) if len(_fired_times(node.output())) == 4 else None,
                        60, "four 't=... event' log lines")
    names = [name for name, _ in fired_at]
    assert names == [f"{ros.topic('env/person')} := False", "a person shows up",
                     f"{ros.topic('env/object_distance')} := {{'data': 0.25}}", "the person leaves"], names
    for (name, elapsed), at in zip(fired_at, [0.0, 0.6, 0.9, 1.5]):
        assert elapsed >= at - 0.01, (name, elapsed, at)
    assert [t for _, t in fired_at] == sorted(t for _, t in fired_at)
    # ~fired is latched: a late subscriber may first get an earlier event, then the last one
    fired.wait(lambda ms: any(m.data == "the person leaves" for m in ms), what="the last fired event (latched)")
    assert node.running()  # it keeps the latched topics up after the schedule


def test_clock_starts_on_the_first_message_of_start_on(ros, tmp_path):
    from std_msgs.msg import Bool, String

    schedule = tmp_path / "env.yaml"
    schedule.write_text(f"events:\n  - {{at: 0.0, topic: {ros.topic('env/door')}, value: true, name: door}}\n")
    door = ros.record(ros.topic("env/door"), Bool)
    node = ros.run("scripted_environment", f"_schedule:={schedule}", f"_start_on:={ros.topic('go')}",
                   "_wait_for_subscribers:=60", name="env")
    # it waits for our recorder first, so from this line on the door event would reach us at once
    node.wait_output("waiting for the first message on", 60)
    time.sleep(1.0)  # a window in which nothing may fire: nobody has published on the start topic yet
    assert door.messages == [] and node.running(), node.output()
    ros.publish(ros.topic("go"), String(data="start"))
    door.wait(lambda ms: [m.data for m in ms] == [True], what="the door event after the start message")


def test_the_clock_waits_until_every_controller_it_drives_has_started(ros, tmp_path):
    """A controller on another host starting later must not miss the first events: a ~state counts
    once its controller has started (state_id >= 0), and the clock waits for each start_on topic."""
    from std_msgs.msg import Bool

    from ltl_stack.msg import ControllerState

    schedule = tmp_path / "env.yaml"
    schedule.write_text(f"events:\n  - {{at: 0.0, topic: {ros.topic('env/door')}, value: true, name: door}}\n")
    door = ros.record(ros.topic("env/door"), Bool)
    first, second = ros.topic("r1/controller_executor/state"), ros.topic("r2/controller_executor/state")
    node = ros.run("scripted_environment", f"_schedule:={schedule}", f"_start_on:={first} {second}",
                   "_wait_for_subscribers:=60", name="env")
    node.wait_output("waiting for the first message on", 60)
    ros.publish(first, ControllerState(state_id=-1))  # r1's executor is up, waiting for its inputs
    node.wait_output(f"{first}: the controller has not started yet", 60)
    ros.publish(first, ControllerState(state_id=0))  # r1 has started; r2 has not said anything yet
    ros.publish(second, ControllerState(state_id=-1))
    node.wait_output(f"{second}: the controller has not started yet", 60)
    assert door.messages == [] and "playing" not in node.output(), node.output()
    ros.publish(second, ControllerState(state_id=3))
    door.wait(lambda ms: [m.data for m in ms] == [True], what="the door event once both controllers started")


def test_when_events_wait_for_the_count_th_change_on_a_topic(ros, tmp_path):
    """clean_and_patrol's camera: the object shows up the second time the robot is in a region."""
    from std_msgs.msg import Bool, Float64

    schedule = tmp_path / "env.yaml"
    schedule.write_text(f"""events:
  - {{at: 0.0, topic: {ros.topic('camera')}, type: std_msgs/Float64, value: 10.0}}
  - when: {{topic: {ros.topic('in_region')}, type: std_msgs/Bool, value: true, count: 2}}
    at: 0.2
    topic: {ros.topic('camera')}
    type: std_msgs/Float64
    value: 0.4
    name: object
""")
    camera = ros.record(ros.topic("camera"), Float64)
    node = ros.run("scripted_environment", f"_schedule:={schedule}", "_wait_for_subscribers:=60", name="env")
    camera.wait(lambda ms: [m.data for m in ms] == [10.0], what="nothing in sight")
    # the second change to true (the counting itself is unit-tested in test_schedule.py)
    for value in (True, True, False, True):
        ros.publish(ros.topic("in_region"), Bool(data=value))
    camera.wait(lambda ms: [m.data for m in ms] == [10.0, 0.4], what="the object on the second entry")
    assert "'when' events start" in node.output(), node.output()


def _fired_times(output: str) -> list[tuple[str, float]]:
    return [(m.group(2), float(m.group(1))) for m in re.finditer(r"t=(\d+\.\d+) (.+?)\s*$", output, re.M)]


def test_bad_schedule_is_one_clear_error(ros, tmp_path):
    schedule = tmp_path / "bad.yaml"
    schedule.write_text("events:\n  - {at: 1, topic: /a, type: std_msgs/Nope, value: 1}\n")
    node = ros.run("scripted_environment", f"_schedule:={schedule}")
    wait_for(lambda: not node.running(), 90, "the node to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert f"{schedule}: topic /a: unknown message type 'std_msgs/Nope'" in out, out
    assert "Traceback" not in out, out
