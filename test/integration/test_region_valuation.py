"""One region change is one update: a node owning several inputs (region localization) publishes
their valuation at once on ``~valuation``, and the executor takes that message instead of the
per-region Bool topics, which a slow link may deliver apart (the new region on long before the old
one off: two regions at once, an assumption violation)."""
from __future__ import annotations

import sys

from helpers import wait_for
from two_regions import MAPPING, SPEC

#: Region localization over a slow link: on "b" the valuation at once, the new region's Bool at
#: once, the old region's Bool 3 s later.
LOCALIZATION = '''
import sys, time
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Bool
from ltl_stack.msg import PropositionValuation
from ltl_stack.ros.valuation import valuation_to_msg

rospy.init_node("localization", disable_signals=True)
topics = {r: rospy.resolve_name("/loc/inputs/" + r + "_rc") for r in "ab"}
bools = {r: rospy.Publisher(t, Bool, queue_size=10, latch=True) for r, t in topics.items()}
whole = rospy.Publisher("~valuation", PropositionValuation, queue_size=10, latch=True)
whole.publish(valuation_to_msg({topics["a"]: True, topics["b"]: False}))
bools["a"].publish(Bool(True))
bools["b"].publish(Bool(False))
deadline = time.monotonic() + 20  # an executor that reads ~valuation has connected to it by then
while whole.get_num_connections() < 1 and time.monotonic() < deadline:
    time.sleep(0.05)
print("up", flush=True)
for line in sys.stdin:
    if line.strip() == "b":
        whole.publish(valuation_to_msg({topics["a"]: False, topics["b"]: True}))
        bools["b"].publish(Bool(True))
        time.sleep(3.0)
        bools["a"].publish(Bool(False))
        print("done", flush=True)
'''


def test_a_region_change_is_one_step_whatever_the_order_of_its_bool_messages(ros_master, tmp_path):
    import subprocess

    spec, mapping, script = tmp_path / "loc.structuredslugs", tmp_path / "loc.yaml", tmp_path / "loc.py"
    spec.write_text(SPEC)
    mapping.write_text(MAPPING)
    script.write_text(LOCALIZATION)
    executor = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping),
                               "--no-recovery"], name="executor")
    ros_master.wait_for_subscriber("/loc/inputs/a_rc")
    log = open(tmp_path / "loc.log", "w")  # noqa: SIM115 - closed below
    fake = subprocess.Popen([sys.executable, str(script), "__ns:=/loc"], env=ros_master.env, stdin=subprocess.PIPE,
                            stdout=log, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        executor.wait_output("initial state", timeout=60)
        wait_for(lambda: "up" in (tmp_path / "loc.log").read_text(), 60, "the localization's connections")
        executor.wait_output("now come from /loc/localization/valuation", timeout=60)
        fake.stdin.write("b\n")
        fake.stdin.flush()
        executor.wait_output("inputs !a_rc b_rc", timeout=60)
        wait_for(lambda: "done" in (tmp_path / "loc.log").read_text(), 60, "the old region's late Bool")
        assert "mode holding" not in executor.output() and "violated" not in executor.output(), executor.output()
    finally:
        fake.kill()
        fake.wait(10)
        log.close()
