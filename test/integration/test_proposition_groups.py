"""A node of ours owning several propositions that change together publishes the change as one
message: ``~valuation`` (``ros.proposition_node.PropositionGroup``), which the executor reads as one
update (docs/several_machines.md, "Slow and lossy links"). Here the kitchen world (Example 13): D
leaving company for road is one ``~valuation`` with company off and road on, never two regions or none;
its Bool topics still carry each proposition."""
from __future__ import annotations

import sys

from helpers import SAY, wait_for

#: Hears the kitchen world's ~valuation (D's region in each message) and D's road Bool; once it has the
#: first (latched) valuation and the world hears its output topic, it sends D towards road.
RECORDER = SAY + '''
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Bool
from ltl_stack.msg import PropositionValuation

REGIONS = ("company", "road", "storage", "prepArea", "cookingArea")
rospy.init_node("recorder", disable_signals=True)
heard = []

def on_valuation(msg):
    values = dict(zip(msg.keys, msg.values))
    say("regions", " ".join(r for r in REGIONS if values.get("/kitchen/D/inputs/%s_c" % r)))
    heard.append(msg)

rospy.Subscriber("/kitchen/kitchen_world/valuation", PropositionValuation, on_valuation, queue_size=100)
rospy.Subscriber("/kitchen/D/inputs/road_c", Bool, lambda m: say("road_c", m.data), queue_size=100)
go = rospy.Publisher("/kitchen/D/outputs/road", Bool, queue_size=1, latch=True)
while not (heard and go.get_num_connections()) and not rospy.is_shutdown():
    rospy.sleep(0.05)
go.publish(Bool(True))
say("sent")
rospy.spin()
'''


def region_lines(proc) -> list[str]:
    return [line.split()[1:] for line in proc.output().splitlines() if line.startswith("regions")]


def test_a_region_change_of_the_kitchen_world_is_one_valuation_message(ros_master, tmp_path):
    script = tmp_path / "recorder.py"
    script.write_text(RECORDER)
    world = ros_master.run(["rosrun", "ltl_stack", "kitchen_world", "__ns:=/kitchen", "_move_time:=0.2"],
                           name="world")
    recorder = ros_master.run([sys.executable, str(script)], name="recorder")
    # generous: rospy retries a connection that failed under load after 1, 2, 4 ... 32 s
    recorder.wait_output("sent", timeout=120)
    try:
        wait_for(lambda: ["road"] in region_lines(recorder), 120, "D in road on the world's ~valuation")
        wait_for(lambda: "road_c True" in recorder.output(), 120, "D in road on its Bool topic")
    except AssertionError as err:
        raise AssertionError(f"{err}\nworld:\n{world.output()[-3000:]}\nrecorder:\n{recorder.output()[-3000:]}") from None
    regions = region_lines(recorder)
    assert regions[0] == ["company"] and regions[-1] == ["road"], regions
    assert all(len(r) == 1 for r in regions), regions  # exactly one region in every message
    assert regions.count(["company"]) + regions.count(["road"]) == len(regions), regions
