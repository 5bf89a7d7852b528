"""Thesis Examples 1 and 2 end to end through the pure layer, and the rewriting guarantees."""
import json
from pathlib import Path

import pytest
from helpers import require_shared

from ltl_stack.transfer.codebase import parse_stats_file
from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.transfer import TransferOptions, TransferRefused, transfer_program

DATA = Path(__file__).resolve().parents[2] / "data" / "transfer"


def run(program, source, target):
    robots = require_shared("robots")
    stats = parse_stats_file(require_shared("codebase", "channel_counts.yaml")).get(target)
    text = (DATA / program).read_text()
    result = transfer_program(text, load_profile(robots, source), load_profile(robots, target),
                              TransferOptions(stats=stats), filename=program)
    return text, result


def changed_lines(before, after):
    a, b = before.splitlines(keepends=True), after.splitlines(keepends=True)
    assert len(a) == len(b)
    return {i + 1: (x.strip(), y.strip()) for i, (x, y) in enumerate(zip(a, b)) if x != y}


def test_example_1_keyboard_jackal_to_turtlebot():
    before, result = run("keyboard_jackal.py", "jackal", "turtlebot")
    got = changed_lines(before, result.text)
    assert got == {
        33: ("return Twist(Vector3(0.5, 0, 0), Vector3(0, 0, 0))", "return Twist(Vector3(0.2, 0, 0), Vector3(0, 0, 0))"),
        35: ("return Twist(Vector3(-0.5, 0, 0), Vector3(0, 0, 0))", "return Twist(Vector3(-0.2, 0, 0), Vector3(0, 0, 0))"),
        37: ("return Twist(Vector3(0, 0, 0), Vector3(0, 0, 0.5))", "return Twist(Vector3(0, 0, 0), Vector3(0, 0, 0.675))"),
        39: ("return Twist(Vector3(0, 0, 0), Vector3(0, 0, -0.5))", "return Twist(Vector3(0, 0, 0), Vector3(0, 0, -0.675))"),
        47: ("pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)",
             "pub = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=1)"),
    }, got
    summary = result.report.summary()
    assert (summary["channels_replaced"], summary["parameters_replaced"], summary["user_inputs"],
            summary["unresolved"], summary["target_robot_examples"]) == (1, 4, 0, 0, 67), summary


def test_example_2_wander_turtlebot_to_jackal_changes_only_the_command():
    before, result = run("wander_turtlebot.py", "turtlebot", "jackal")
    got = changed_lines(before, result.text)
    assert got[20] == ("rospy.Subscriber('scan', LaserScan, scan_callback)",
                       "rospy.Subscriber('front/scan', LaserScan, scan_callback)"), got
    assert got[21] == ("vel_pub = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=1)",
                       "vel_pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)"), got
    assert got[30] == ("vel=.3", "vel=0.75"), got
    assert 29 not in got, "the .3 in the comparison is not a command and must stay"
    assert "if SCAN.ranges[middle]/10 >= .3:" in result.text
    assert sorted(got) == [20, 21, 30, 34], got   # 34: the turn, scaled by Eq. 2.2


def test_everything_outside_the_edits_is_byte_identical():
    before, result = run("wander_turtlebot.py", "turtlebot", "jackal")
    data, edits = before.encode(), sorted(result.edits, key=lambda e: e.span.start)
    out, pos = bytearray(), 0
    for edit in edits:
        out += data[pos:edit.span.start] + edit.text.encode()
        pos = edit.span.end
    out += data[pos:]
    assert bytes(out) == result.text.encode()
    kept = [data[a.span.end:b.span.start] for a, b in zip(edits, edits[1:])]
    assert all(chunk in result.text.encode() for chunk in kept)


def test_report_json_has_the_table_2_5_row():
    _, result = run("keyboard_jackal.py", "jackal", "turtlebot")
    data = json.loads(result.report.to_json())
    assert data["summary"]["total_replacements"] == 5, data["summary"]
    assert data["channels"][0]["original"] == "cmd_vel", data["channels"][0]
    assert data["channels"][0]["candidates"][0] == {"name": "cmd_vel_mux/input/navi", "count": 15,
                                                   "probability": 0.52}, data["channels"][0]["candidates"]
    text = result.report.to_text()
    assert "'cmd_vel' replaced -> 'cmd_vel_mux/input/navi'" in text, text
    assert "linear.x 0.5 -> 0.2  [B.2 scaled (Eq. 2.1)]" in text, text


def test_differential_to_holonomic_is_refused_with_the_reason():
    robots = require_shared("robots")
    text = (DATA / "keyboard_jackal.py").read_text()
    with pytest.raises(TransferRefused) as err:
        transfer_program(text, load_profile(robots, "jackal"), load_profile(robots, "youbot"))
    assert "differential" in str(err.value) and "holonomic" in str(err.value) and "§2.8" in str(err.value)


def test_commands_out_of_the_source_limits_are_clamped_and_flagged():
    robots = require_shared("robots")
    text = "from geometry_msgs.msg import Twist, Vector3\nt = Twist(Vector3(3.0, 0, 0), Vector3())\n"
    result = transfer_program(text, load_profile(robots, "jackal"), load_profile(robots, "turtlebot"))
    assert "Vector3(0.8, 0, 0)" in result.text, result.text
    change = result.report.parameters[0]
    assert change.method == "B.1 clamped" and "outside jackal's limits" in change.note, change


def test_deadband_of_the_target_and_a_field_the_target_lacks():
    robots = require_shared("robots")
    text = "msg.linear.x, msg.linear.y = 0.4, -0.4\nmsg.angular.z = 0.3\n"
    result = transfer_program(text, load_profile(robots, "youbot"), load_profile(robots, "sphero"))
    # Eq. 2.1/2.2 with sphero's deadband 30: half of youbot's range -> 30 + 0.5 * (80 - 30)
    assert result.text == "msg.linear.x, msg.linear.y = 55.0, -55.0\nmsg.angular.z = 0.3\n", result.text
    assert [(u.what, u.line) for u in result.report.unresolved] == [("angular.z", 2)], result.report.unresolved
    assert "sphero has no angular.z" in result.report.unresolved[0].reason


def test_list_formatting_keeps_a_wrapped_list_wrapped():
    from ltl_stack.transfer.source_ast import format_angle, format_list

    like = "['a', 'b',\n     'c']"
    got = format_list([f"'name_{i}'" for i in range(12)], like, width=40)
    lines = got.split("\n")
    assert len(lines) > 1 and all(line.startswith("     ") for line in lines[1:]), got
    assert eval(got) == [f"name_{i}" for i in range(12)], got
    assert format_list(["1", "2"], "[0, 0]") == "[1, 2]"
    assert format_angle(-0.00001) == "0.0000" and format_angle(-1.23456) == "-1.2346"


def test_the_same_channel_twice_is_asked_once_and_edited_everywhere():
    robots = require_shared("robots")
    text = ("import rospy\nfrom geometry_msgs.msg import Twist\nTOPIC = 'cmd_vel'\n"
            "a = rospy.Publisher(TOPIC, Twist)\nb = rospy.Publisher('cmd_vel', Twist)\n")
    live = [("/cmd_vel_mux/input/navi", "geometry_msgs/Twist"), ("/cmd_vel_mux/input/teleop", "geometry_msgs/Twist"),
            ("/odom", "nav_msgs/Odometry")]
    asked = []

    def ask(word, msg_type, original, options):
        asked.append(options)
        return 1

    result = transfer_program(text, load_profile(robots, "jackal"), load_profile(robots, "turtlebot"),
                              TransferOptions(live=live, ask=ask))
    assert asked == [["/cmd_vel_mux/input/navi", "/cmd_vel_mux/input/teleop"]], asked
    assert result.text.count("'/cmd_vel_mux/input/teleop'") == 2, result.text
    assert result.report.user_inputs == 1 and result.report.channels_replaced == 2, result.report.summary()
