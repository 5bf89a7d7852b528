"""Proposition nodes against a real master: set_velocity, set_color, the sensors."""
from __future__ import annotations

import time

import pytest
from helpers import require_shared, wait_for
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits

# Absence of messages cannot be waited for; we watch for this many seconds (many node periods).
QUIET_WINDOW = 0.6


@pytest.fixture
def ros(request):
    return make_session(request)


def nonzero(t) -> bool:
    return any((t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z))


def test_set_velocity_publishes_while_true_and_one_zero_on_falling_edge(ros):
    from geometry_msgs.msg import Twist

    cmd = ros.record(ros.topic("cmd_vel"), Twist)
    ros.run("set_velocity", f"_topic:={ros.topic('cmd_vel')}", "_vx:=0.5", "_az:=-0.25", "_rate:=20",
            f"proposition:={ros.topic('outputs/move')}")
    ros.set_bool(ros.topic("outputs/move"), False)
    ros.master.wait_for_publisher(ros.topic("cmd_vel"))
    time.sleep(QUIET_WINDOW)
    assert cmd.snapshot() == [], "set_velocity published while the proposition was false"

    ros.set_bool(ros.topic("outputs/move"), True)
    cmd.wait(lambda ms: len(ms) >= 5, what="5 Twists while true")
    first = cmd.snapshot()[0]
    assert (first.linear.x, first.angular.z) == (0.5, -0.25), first

    ros.set_bool(ros.topic("outputs/move"), False)
    cmd.wait_last(lambda t: not nonzero(t), what="a zero Twist after the falling edge")
    count = len(cmd.snapshot())
    time.sleep(QUIET_WINDOW)
    after = cmd.snapshot()[count:]
    assert after == [], f"{len(after)} Twists after the falling edge"
    zeros = [t for t in cmd.snapshot() if not nonzero(t)]
    assert len(zeros) == 1, len(zeros)


def test_set_velocity_reads_the_thesis_mapping_parameter_names_and_stops_on_shutdown(ros):
    from geometry_msgs.msg import Twist

    cmd = ros.record(ros.topic("turtle1/cmd_vel"), Twist)
    node = ros.run("set_velocity", f"_publish_topic:={ros.topic('turtle1/cmd_vel')}", "_az:=1",
                   f"_proposition_topic:={ros.topic('outputs/move')}")
    ros.set_bool(ros.topic("outputs/move"), True)
    cmd.wait(lambda ms: len(ms) >= 2, what="Twists while true")
    assert cmd.snapshot()[0].angular.z == 1.0, cmd.snapshot()[0]
    assert node.stop() == 0, node.output()
    cmd.wait_last(lambda t: not nonzero(t), what="a zero Twist on shutdown")


def test_set_velocity_bad_parameter_is_one_clear_error(ros):
    node = ros.run("set_velocity", "_vx:=fast")
    wait_for(lambda: not node.running(), 90, "set_velocity to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert "~vx must be a number" in out, out
    assert "Traceback" not in out, out


def test_set_color_sets_the_colour_on_rising_edge_and_black_on_falling(ros):
    from std_msgs.msg import ColorRGBA

    colors = ros.record(ros.topic("sphero/set_color"), ColorRGBA)
    ros.run("set_color", f"_publish_topic:={ros.topic('sphero/set_color')}", "_r:=255", "_g:=0", "_b:=0",
            "_off_on_false:=true", f"proposition:={ros.topic('outputs/turn_red')}")
    colors.wait_connected()  # the colours are counted: none may go out before the recorder hears them
    ros.set_bool(ros.topic("outputs/turn_red"), True)
    red = colors.wait_last(lambda c: c.r == 255.0, what="red")
    assert (red.g, red.b) == (0.0, 0.0), red
    ros.set_bool(ros.topic("outputs/turn_red"), False)
    colors.wait_last(lambda c: (c.r, c.g, c.b) == (0.0, 0.0, 0.0), what="black")
    assert len(colors.snapshot()) == 2, colors.snapshot()


def test_threshold_sensor_compares_a_field_with_hysteresis(ros):
    from sensor_msgs.msg import Range
    from std_msgs.msg import Bool

    out = ros.record(ros.topic("inputs/obstacle"), Bool)
    ros.run("topic_threshold_sensor", f"_topic:={ros.topic('range')}", "_type:=sensor_msgs/Range",
            "_field:=range", "_comparison:=<", "_threshold:=0.5", "_hysteresis:=0.1",
            f"_proposition_topic:={ros.topic('inputs/obstacle')}")
    out.wait_last(lambda b: b.data is False, what="the initial False")
    for value, expected in [(0.3, True), (0.55, True), (0.65, False), (0.45, False), (0.35, True)]:
        ros.publish(ros.topic("range"), Range(range=value))
        out.wait_last(lambda b, e=expected: b.data is e, what=f"{expected} after range {value}")


def test_threshold_sensor_publishes_the_stale_value_while_sensing_stops(ros):
    import threading

    from sensor_msgs.msg import Range
    from std_msgs.msg import Bool

    out = ros.record(ros.topic("inputs/clear"), Bool)
    ros.run("topic_threshold_sensor", f"_topic:={ros.topic('range')}", "_type:=sensor_msgs/Range",
            "_field:=range", "_comparison:=gt", "_threshold:=0.5", "_stale_after:=1.0",
            "_stale_value:=false", f"_proposition_topic:={ros.topic('inputs/clear')}")
    ros.master.wait_for_subscriber(ros.topic("range"))
    # sensing at 20 Hz for well over the limit: the value stays true throughout
    stop = threading.Event()

    def sense():
        while not stop.wait(0.05):
            ros.publish(ros.topic("range"), Range(range=1.0))
    feeder = threading.Thread(target=sense, daemon=True)
    feeder.start()
    try:
        out.wait_last(lambda b: b.data is True, what="True while sensing")
        count = len(out.snapshot())
        time.sleep(2 * 1.0)  # two stale periods; the feeder sends every 0.05 s, far more often
        assert all(b.data for b in out.snapshot()[count:]), "went stale while sensing arrived"
    finally:
        stop.set()
        feeder.join()
    out.wait_last(lambda b: b.data is False, what="the stale value after sensing stopped")
    ros.publish(ros.topic("range"), Range(range=1.0))
    out.wait_last(lambda b: b.data is True, what="True again once sensing resumed")


def test_negative_stale_after_is_one_clear_error(ros):
    node = ros.run("topic_threshold_sensor", "_topic:=/x", "_type:=sensor_msgs/Range",
                   "_stale_after:=-1")
    wait_for(lambda: not node.running(), 90, "the sensor to exit")
    assert node.popen.returncode == 2, node.output()
    assert "~stale_after must be a number >= 0" in node.output(), node.output()
    assert "Traceback" not in node.output(), node.output()


def test_threshold_sensor_learns_the_type_from_the_master_and_forwards_a_bool(ros):
    from std_msgs.msg import Bool

    out = ros.record(ros.topic("inputs/pickup_ac"), Bool)
    ros.publish(ros.topic("outputs/pickup_status"), Bool(data=False), subscribers=0)
    ros.run("topic_threshold_sensor", f"_sensor_topic:={ros.topic('outputs/pickup_status')}",
            "_comparison:===", "_threshold:=1", f"proposition:={ros.topic('inputs/pickup_ac')}")
    ros.master.wait_for_subscriber(ros.topic("outputs/pickup_status"))
    ros.publish(ros.topic("outputs/pickup_status"), Bool(data=True))
    out.wait_last(lambda b: b.data is True, what="True forwarded")
    ros.publish(ros.topic("outputs/pickup_status"), Bool(data=False))
    out.wait_last(lambda b: b.data is False, what="False forwarded")


def test_threshold_sensor_unknown_type_is_one_clear_error(ros):
    node = ros.run("topic_threshold_sensor", "_topic:=/x", "_type:=nosuch_msgs/Thing")
    wait_for(lambda: not node.running(), 90, "the sensor to exit")
    assert node.popen.returncode == 2, node.output()
    assert "unknown message type 'nosuch_msgs/Thing'" in node.output(), node.output()
    assert "Traceback" not in node.output(), node.output()


def test_region_sensor_with_a_real_regions_file(ros):
    from geometry_msgs.msg import PoseStamped
    from std_msgs.msg import Bool

    from ltl_stack.runtime.propositions.regions import RegionMap

    path = require_shared("specs", "move_group_and_move_base", "lab_loop.regions")
    regions = RegionMap.load(path, scale=0.005)
    inside = regions.find("left_ground").interior_point()
    elsewhere = regions.find("top_lane").interior_point()

    out = ros.record(ros.topic("inputs/leftGround_rc"), Bool)
    ros.run("region_sensor", f"_regions_file:={path}", "_region_in_consideration:=leftGround",
            "_scale:=0.005", f"_pose_topic:={ros.topic('pose')}", "_pose_type:=geometry_msgs/PoseStamped",
            f"proposition:={ros.topic('inputs/leftGround_rc')}")
    out.wait_last(lambda b: b.data is False, what="the initial False")
    for (x, y), expected in [(inside, True), (elsewhere, False), (inside, True)]:
        pose = PoseStamped()
        pose.pose.position.x, pose.pose.position.y = x, y
        ros.publish(ros.topic("pose"), pose)
        out.wait_last(lambda b, e=expected: b.data is e, what=f"{expected} at ({x:.2f}, {y:.2f})")


def test_region_sensor_unknown_region_names_the_file_and_the_known_regions(ros):
    path = require_shared("specs", "move_group_and_move_base", "lab_loop.regions")
    node = ros.run("region_sensor", f"_regions_file:={path}", "_region:=kitchen")
    wait_for(lambda: not node.running(), 90, "the sensor to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert f"{path}: no region named 'kitchen'" in out and "left_ground" in out, out
    assert "Traceback" not in out, out


def test_region_sensor_reads_the_region_name_topic_of_the_thesis_mappings(ros):
    from std_msgs.msg import Bool, String

    out = ros.record(ros.topic("inputs/kitchen_rc"), Bool)
    ros.run("region_sensor", f"_robot_location_topic:={ros.topic('robot_current_region')}",
            "_region_in_consideration:=kitchen", f"proposition:={ros.topic('inputs/kitchen_rc')}")
    out.wait_last(lambda b: b.data is False, what="the initial False")
    for name, expected in [("kitchen", True), ("porch", False), ("Kitchen", True), ("", False)]:
        ros.publish(ros.topic("robot_current_region"), String(data=name))
        out.wait_last(lambda b, e=expected: b.data is e, what=f"{expected} for region {name!r}")


def test_rosnode_kill_stops_an_active_output_node_promptly_and_drives_it_off(ros):
    import subprocess

    from geometry_msgs.msg import Twist

    cmd = ros.record(ros.topic("cmd_vel"), Twist)
    node = ros.run("set_velocity", f"_topic:={ros.topic('cmd_vel')}", "_vx:=0.3",
                   f"proposition:={ros.topic('outputs/move')}", name="killme")
    ros.set_bool(ros.topic("outputs/move"), True)
    cmd.wait(lambda ms: len(ms) >= 2, what="Twists while true")
    subprocess.run(["rosnode", "kill", f"{ros.ns.strip('/')}_killme"], env=ros.master.env, check=True,
                   capture_output=True, timeout=300)
    wait_for(lambda: not node.running(), 90, "set_velocity to exit after rosnode kill")  # by itself, not stop()
    assert node.popen.returncode == 0, node.output()
    cmd.wait_last(lambda t: not nonzero(t), what="a zero Twist when killed")


def test_publish_on_edge_sends_configured_messages_of_any_type(ros):
    from std_msgs.msg import String

    out = ros.record(ros.topic("camera/mode"), String)
    ros.run("publish_on_edge", f"_topic:={ros.topic('camera/mode')}", "_type:=std_msgs/String",
            "_on_true:={data: 'off'}", "_on_false:={data: 'on'}",
            f"proposition:={ros.topic('outputs/disableCamera')}")
    ros.set_bool(ros.topic("outputs/disableCamera"), True)
    out.wait_last(lambda m: m.data == "off", what="'off' on the rising edge")
    ros.set_bool(ros.topic("outputs/disableCamera"), False)
    out.wait_last(lambda m: m.data == "on", what="'on' on the falling edge")
    assert [m.data for m in out.snapshot()] == ["off", "on"], out.snapshot()


def test_publish_on_edge_without_a_topic_is_a_dummy_actuator_that_logs_edges(ros):
    node = ros.run("publish_on_edge", f"proposition:={ros.topic('outputs/radio')}")
    ros.set_bool(ros.topic("outputs/radio"), True)
    node.wait_output(f"{ros.topic('outputs/radio')} rose")
