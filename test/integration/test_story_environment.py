"""The ``story_environment`` node's clock: one tick per ``~state`` of the executor, none while it
characterizes or waits for the user (``sim/story_environment.py``), so a beat due "after N
transitions" never overtakes a characterization however long its synthesis takes. Counted, not
timed: a driver node plays the executor's ``~state`` messages in one order on one connection, which
the story node reads in that order."""
from __future__ import annotations

import sys

STORY = """regions: []
inputs: {a: false}
user: "a"
beats:
  - name: first
    after: 3
    set: {a: true}
"""

#: Plays the executor: 20 states while characterizing, 2 normal ones, one waiting for the user (the story
#: node answers that one on ~fired, so everything before it has been read), then one more normal state.
DRIVER = '''
import sys, time
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import String
from ltl_stack.msg import ControllerState

rospy.init_node("driver", disable_signals=True)
fired = []
heard = rospy.Subscriber("/exec/story/fired", String, lambda m: fired.append(m.data), queue_size=100)
states = rospy.Publisher("/exec/controller_executor/state", ControllerState, queue_size=100)


def wait(condition, what):
    deadline = time.monotonic() + 300
    while not condition():
        if time.monotonic() > deadline:
            print("timed out waiting for", what, fired, flush=True)
            sys.exit(1)
        time.sleep(0.05)


def send(mode, count):
    for k in range(count):
        msg = ControllerState()
        msg.state_id, msg.goal_index, msg.running, msg.mode = k, 0, True, mode
        states.publish(msg)


wait(lambda: heard.get_num_connections() > 0 and states.get_num_connections() > 0, "the story node")
send("characterizing", 20)
send("normal", 2)
send("waiting_for_user", 1)
wait(lambda: any(f.startswith("user:") for f in fired), "the story node asking the user")
print("beats after the busy states:", sum(f == "story: first" for f in fired), flush=True)
send("normal", 1)
wait(lambda: "story: first" in fired, "the first beat")
print("beats after one more normal state:", sum(f == "story: first" for f in fired), flush=True)
'''


def test_the_story_clock_stands_still_while_the_executor_characterizes_or_waits_for_the_user(ros_master, tmp_path):
    story, driver = tmp_path / "story.yaml", tmp_path / "driver.py"
    story.write_text(STORY)
    driver.write_text(DRIVER)
    # it subscribes to ~state once the driver hears its ~fired (or after 300 s)
    ros_master.run(["rosrun", "ltl_stack", "story_environment", "__ns:=/exec", "__name:=story", f"_story:={story}",
                    "_wait_for_subscribers:=300", "_service_timeout:=1"], name="story")
    play = ros_master.run([sys.executable, str(driver)], name="driver")
    play.wait_output("beats after one more normal state", timeout=300)
    # 22 states in all, 2 of them counted: the beat due after 3 has not fired; the third counted state fires it
    assert "beats after the busy states: 0" in play.output(), play.output()
    assert "beats after one more normal state: 1" in play.output(), play.output()
