"""Thesis Examples 4 and 6, the drive rule, unknown sources, joint rates (B.2), the A.1 distribution
prompt and the Table 2.5 command (chapter 2)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import REPO_ROOT, require_shared

from ltl_stack.errors import Exit
from ltl_stack.transfer.channels import load_listing
from ltl_stack.transfer.codebase import parse_stats_file
from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.limits import load_limits, scale_command
from ltl_stack.transfer.profiles import KNOWN_DRIVES, load_profile, unknown_profile
from ltl_stack.transfer.thesis_table import ROWS
from ltl_stack.transfer.thesis_table import main as table_main
from ltl_stack.transfer.transfer import TransferOptions, TransferRefused, transfer_program
from ltl_stack.transfer.urdf import load_urdf

DATA = Path(__file__).resolve().parents[2] / "data" / "transfer"


def changed_lines(before, after):
    a, b = before.splitlines(), after.splitlines()
    assert len(a) == len(b)
    return {i + 1: (x.strip(), y.strip()) for i, (x, y) in enumerate(zip(a, b)) if x != y}


def answers(mapping):
    """An asker answering by message type (1-based, as a user would), recording what it was asked."""
    asked = []

    def ask(word, msg_type, original, options):
        asked.append((word, msg_type.split("/")[-1], original, list(options)))
        return mapping[msg_type.split("/")[-1]] - 1

    return ask, asked


# ---- Example 4: Greet, Pepper -> NAO, with the shared robot files as they are ----

def test_pepper_and_nao_are_holonomic_from_the_known_robots_table():
    robots = require_shared("robots")
    pepper, nao = load_profile(robots, "pepper"), load_profile(robots, "nao")
    # the shared Pepper limits alone would say differential (linear.y 0..0)
    assert pepper.limits["linear.y"].upper == 0 and pepper.limits["linear.y"].lower == 0
    assert (pepper.drive, pepper.drive_source) == ("holonomic", "known robots table"), pepper.describe()
    assert (nao.drive, nao.drive_source) == ("holonomic", "known robots table"), nao.describe()
    assert KNOWN_DRIVES["jackal"] == "differential"


def test_example_4_greet_pepper_to_nao():
    robots = require_shared("robots")
    text = (DATA / "greet_pepper.py").read_text()
    listing = load_listing(str(DATA / "topics" / "nao.yaml"))
    ask, asked = answers({"JointTrajectoryAction": 2})
    result = transfer_program(text, load_profile(robots, "pepper"), load_profile(robots, "nao"),
                              TransferOptions(live=listing, ask=ask), filename="greet_pepper.py")
    report = result.report
    got = changed_lines(text, result.text)
    # two A.2 channels: the Twist topic is the only one of its type, the action needs the user
    assert got[53] == ("self.velocity = rospy.Publisher('cmd_vel', Twist, queue_size=1)",
                       "self.velocity = rospy.Publisher('/cmd_vel', Twist, queue_size=1)"), got
    assert got[54][1] == ("self.arm = actionlib.SimpleActionClient('/nao_robot/pose/joint_trajectory', "
                          "JointTrajectoryAction)"), got
    assert [a[:3] for a in asked] == [("action", "JointTrajectoryAction", "/pepper_robot/pose/joint_trajectory")]
    assert [c.method for c in report.channels] == ["A.2 live master (the only channel of this type)",
                                                   "A.2 live master, chosen by the user"]
    assert report.user_inputs == 1 and report.channels_replaced == 2
    # the Twist literals scaled by B.2 (Eqs. 2.1/2.2) between the two robots' limits
    pepper_limits = load_limits(robots / "limits" / "pepper.yaml")
    nao_limits = load_limits(robots / "limits" / "nao.yaml")
    for line, field, value in ((99, "linear.x", 0.3), (103, "linear.x", -0.3), (107, "angular.z", 0.5),
                               (111, "angular.z", -0.5)):
        expected = scale_command(value, pepper_limits[field], nao_limits[field])
        assert f"{expected:.6g}"[:6] in got[line][1], (line, got[line], expected)
    twist = [p for p in report.parameters if p.what in ("linear.x", "angular.z")]
    assert len(twist) == 4 and all(p.method.startswith("B.2 scaled") for p in twist), twist
    # the joint trajectory retargeted by B.3 (same joint names on both: NAO's arm, its own limits)
    nao_urdf = load_urdf(robots / "urdf" / "nao_robot_v3.urdf")
    positions = [p for p in report.parameters if p.what.startswith("positions")]
    assert len(positions) == 4 and all(p.method == "B.3 retargeted" and p.changed for p in positions), positions
    for p in positions:
        values = eval(p.replacement)
        for name, value in zip(report.retargeting["target_joints"], values):
            lower, upper = nao_urdf.limits(name)
            assert lower - 1e-4 <= value <= upper + 1e-4, (name, value)
    assert report.retargeting["target_rule"] == "the target has the program's joints"
    assert not report.unresolved, report.unresolved


def test_example_4_through_the_real_script_with_the_shared_files(tmp_path):
    robots = require_shared("robots")
    done = subprocess.run(
        [sys.executable, str(REPO_ROOT / "scripts" / "ros_code_transfer"), str(DATA / "greet_pepper.py"),
         "--from", "pepper", "--to", "nao", "--robots", str(robots), "-o", str(tmp_path / "greet_nao.py"),
         "--topics", str(DATA / "topics" / "nao.yaml"), "--json", "-q"],
        input="2\n", capture_output=True, text=True, timeout=300,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO_ROOT / "src"), os.environ.get("PYTHONPATH", "")])})
    assert done.returncode == Exit.OK, done.stderr
    summary = json.loads(done.stdout)["summary"]
    assert (summary["channels_replaced"], summary["user_inputs"], summary["unresolved"]) == (2, 1, 0), summary
    assert "'/nao_robot/pose/joint_trajectory'" in (tmp_path / "greet_nao.py").read_text()


def test_differential_to_holonomic_still_refused_and_names_where_the_drive_came_from():
    robots = require_shared("robots")
    text = (DATA / "keyboard_jackal.py").read_text()
    with pytest.raises(TransferRefused) as err:
        transfer_program(text, load_profile(robots, "jackal"), load_profile(robots, "pepper"))
    assert "jackal has a differential drive (known robots table)" in str(err.value), str(err.value)
    assert err.value.code == Exit.REFUSED


# ---- Example 6: Localization, source robot unknown -> Turtlebot and Jackal ----

@pytest.mark.parametrize("target, user_type, answer, expected", [
    ("turtlebot", "Imu", 1, {62: "/scan", 63: "/odom", 64: "/mobile_base/sensors/imu_data",
                              65: "/cmd_vel_mux/input/navi", 66: "/initialpose"}),
    ("jackal", "Odometry", 2, {62: "/front/scan", 63: "/odometry/filtered", 64: "/imu/data", 65: "/cmd_vel",
                               66: "/initialpose"}),
])
def test_example_6_localization_from_an_unknown_robot(target, user_type, answer, expected):
    robots = require_shared("robots")
    stats = parse_stats_file(require_shared("codebase", "channel_counts.yaml")).get(target)
    text = (DATA / "localization.py").read_text()
    ask, asked = answers({user_type: answer})
    source = load_profile(robots, "unknown", allow_unknown=True)
    assert source == unknown_profile() and source.unknown and source.limits is None
    result = transfer_program(text, source, load_profile(robots, target),
                              TransferOptions(stats=stats, live=load_listing(str(DATA / "topics" / f"{target}.yaml")),
                                              ask=ask), filename="localization.py")
    got = changed_lines(text, result.text)
    assert sorted(got) == sorted(expected), got
    for line, name in expected.items():
        assert f"rospy.Subscriber('{name}'," in got[line][1], (line, got[line])
    assert [a[1] for a in asked] == [user_type], asked
    summary = result.report.summary()
    assert (summary["channels_replaced"], summary["parameters_replaced"], summary["user_inputs"],
            summary["unresolved"], summary["target_robot_examples"]) == (5, 0, 1, 0, stats.scripts), summary
    # A.1 names the master confirms are taken without asking (Twist on both, LaserScan on the Jackal)
    methods = {c.msg_type.split("/")[-1]: c.method for c in result.report.channels}
    assert methods["Twist"].endswith("verified on the live master (A.2)"), methods


def test_an_unknown_source_is_only_checked_never_scaled():
    robots = require_shared("robots")
    text = "from geometry_msgs.msg import Twist, Vector3\na = Twist(Vector3(0.5, 0, 0), Vector3(0, 0, 9.0))\n"
    result = transfer_program(text, unknown_profile(), load_profile(robots, "turtlebot"))
    assert result.text.endswith("a = Twist(Vector3(0.5, 0, 0), Vector3(0, 0, 5.4))\n"), result.text
    methods = [(p.what, p.method) for p in result.report.parameters]
    assert methods == [("linear.x", "B.1 checked"), ("angular.z", "B.1 clamped")], methods


def test_a_robot_named_unknown_in_the_folder_wins(tmp_path):
    (tmp_path / "limits").mkdir()
    (tmp_path / "limits" / "unknown.yaml").write_text("linear: {x: {lower: -1, upper: 1}}\n")
    assert load_profile(tmp_path, "unknown", allow_unknown=True).limits is not None
    (tmp_path / "empty").mkdir()
    with pytest.raises(TransferError, match="no robot named 'unknown'"):   # only a source may be unknown
        load_profile(tmp_path / "empty", "unknown")


# ---- joint velocities and accelerations: B.2 against the URDF velocity limits ----

def test_joint_rates_are_scaled_by_the_velocity_limits_same_joints():
    robots = require_shared("robots")
    text = (DATA / "greet_pepper.py").read_text()
    result = transfer_program(text, load_profile(robots, "pepper"), load_profile(robots, "nao"))
    pepper, nao = load_urdf(robots / "urdf" / "pepper.urdf"), load_urdf(robots / "urdf" / "nao_robot_v3.urdf")
    joints = ["RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"]
    rates = {p.what: p for p in result.report.parameters if p.what.startswith("velocities")}
    assert set(rates) == {"velocities (variable SWING_OUT)", "velocities (variable SWING_IN)"}, rates
    source = [0.0, -1.5, 0.0, 2.0, 0.0]
    expected = [v * nao.velocity_limit(j) / pepper.velocity_limit(j) for v, j in zip(source, joints)]
    got = eval(rates["velocities (variable SWING_OUT)"].replacement)
    assert got == pytest.approx(expected, abs=1e-4), (got, expected)
    assert rates["velocities (variable SWING_OUT)"].method == "B.2 scaled (joint velocity limits)"
    assert "SWING_OUT = [0.0000, -0.4877, 0.0000, 0.6502, 0.0000]" in result.text, result.text


def test_joint_rates_between_different_arms_follow_the_joint_order_and_limits():
    robots = require_shared("robots")
    text = (DATA / "follow_trajectory_ur5.py").read_text().replace(
        "velocities=[0] * 6, time_from_start=rospy.Duration(2.0)",
        "velocities=[0.63, 0, -0.63, 0, 0, 3.15], accelerations=[0.1, 0, 0, 0, 0, 0.2], "
        "time_from_start=rospy.Duration(2.0)")
    result = transfer_program(text, load_profile(robots, "ur5"), load_profile(robots, "j2s7s300"))
    rates = {p.what: eval(p.replacement) for p in result.report.parameters
             if p.what in ("velocities", "accelerations") and "[0] *" not in p.replacement}
    jaco = load_urdf(robots / "urdf" / "j2s7s300.urdf")
    ur5 = load_urdf(robots / "urdf" / "ur5.urdf")
    ur5_joints = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
                  "wrist_3_joint"]
    source_v, source_a = [0.63, 0, -0.63, 0, 0, 3.15], [0.1, 0, 0, 0, 0, 0.2]
    # 6 -> 7 joints by place from base to tip: first <- first, last <- last
    match = [0, 1, 2, 3, 3, 4, 5]
    ratio = [jaco.velocity_limit(f"j2s7s300_joint_{j + 1}") / ur5.velocity_limit(ur5_joints[i])
             for j, i in enumerate(match)]
    assert rates["velocities"] == pytest.approx([source_v[i] * r for i, r in zip(match, ratio)],
                                                abs=1e-4)
    assert rates["accelerations"] == pytest.approx([source_a[i] * r for i, r in zip(match, ratio)],
                                                   abs=1e-4)
    assert rates["velocities"][0] != 0 and rates["velocities"][6] != 0, rates


def test_joint_velocities_without_a_source_urdf_are_clamped_to_the_target():
    robots = require_shared("robots")
    text = ("from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint\n"
            "t = JointTrajectory(joint_names=['RShoulderPitch', 'RElbowRoll'])\n"
            "p = JointTrajectoryPoint(positions=[0.1, 0.5], velocities=[5.0, -1.0])\n")
    result = transfer_program(text, unknown_profile(), load_profile(robots, "nao"))
    assert "velocities=[3.0000, -1.0000]" in result.text, result.text


# ---- A.1: choosing from the distribution ----

def _keyboard_args(tmp_path, *extra):
    return [str(REPO_ROOT / "scripts" / "ros_code_transfer"), str(DATA / "keyboard_jackal.py"), "--from",
            "jackal", "--to", "turtlebot", "--robots", str(require_shared("robots")), "--codebase",
            str(require_shared("codebase", "channel_counts.yaml")), "-o", str(tmp_path / "kb.py"), "--json", "-q",
            *extra]


def _env():
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO_ROOT / "src"), os.environ.get("PYTHONPATH", "")])}


def test_choose_by_distribution_prompts_through_a_pipe(tmp_path):
    done = subprocess.run([sys.executable, *_keyboard_args(tmp_path, "--choose-by-distribution")],
                          input="x\n2\n", capture_output=True, text=True, timeout=300, env=_env())
    assert done.returncode == Exit.OK, done.stderr
    assert ("Please select a topic for Twist from the list.\n"
            "The original topic was 'cmd_vel'. Input Example: 1\n"
            "1. cmd_vel_mux/input/navi (15 uses, p=0.52)\n"
            "2. cmd_vel_mux/input/teleop (8 uses, p=0.28)\n"
            "3. mobile_base/commands/velocity (3 uses, p=0.10)\n"
            "4. cmd_vel (2 uses, p=0.07)\n"
            "5. cmd_vel_mux/input/switch (1 use, p=0.03)\n"
            "Please enter a number from 1 to 5.\n") in done.stderr, done.stderr
    channel = json.loads(done.stdout)["channels"][0]
    assert channel["replacement"] == "cmd_vel_mux/input/teleop" and channel["user_input"], channel
    assert "chosen by the user (8 of 29 uses, p=0.28)" in channel["method"], channel
    assert "Publisher('cmd_vel_mux/input/teleop'" in (tmp_path / "kb.py").read_text()


def test_choose_by_distribution_with_a_given_answer_and_without_one(tmp_path):
    done = subprocess.run([sys.executable, *_keyboard_args(tmp_path, "--choose-by-distribution", "--choose",
                                                           "Twist=3", "--non-interactive")],
                          capture_output=True, text=True, timeout=300, env=_env(), stdin=subprocess.DEVNULL)
    assert done.returncode == Exit.OK, done.stderr
    channel = json.loads(done.stdout)["channels"][0]
    assert channel["replacement"] == "mobile_base/commands/velocity" and channel["user_input"], channel
    # no answer at all from a closed stdin: one clear error, nothing written
    done = subprocess.run([sys.executable, *_keyboard_args(tmp_path, "--choose-by-distribution")],
                          capture_output=True, text=True, timeout=300, env=_env(), stdin=subprocess.DEVNULL)
    assert done.returncode == Exit.BAD_INPUT and "no answer to the question about the topic 'cmd_vel'" in done.stderr
    assert not (tmp_path / "kb.py").exists() or "teleop" not in (tmp_path / "kb.py").read_text()


@pytest.mark.parametrize("bad", ["Twist", "Twist=0", "=2", "Twist=two"])
def test_bad_choose_values_are_bad_input(tmp_path, capsys, bad):
    from ltl_stack.transfer.cli import main

    argv = _keyboard_args(tmp_path, "--choose", bad)[1:]
    assert main(argv) == Exit.BAD_INPUT
    assert "--choose" in capsys.readouterr().err and not (tmp_path / "kb.py").exists()


# ---- Table 2.5 ----

def test_table_2_5_command_reproduces_the_seven_rows(capsys):
    # the package's robot profiles: no ../shared needed
    assert table_main(["--json"]) == Exit.OK
    rows = json.loads(capsys.readouterr().out)
    assert [r["example"] for r in rows] == [row.label for row in ROWS] and len(rows) == 7
    ours = [(r["ours"]["channels_replaced"], r["ours"]["user_inputs"], r["ours"]["target_robot_examples"],
             r["ours"]["unresolved"]) for r in rows]
    thesis = [(r["thesis"]["channels_replaced"], r["thesis"]["user_inputs"], r["thesis"]["target_robot_examples"],
               r["thesis"]["replacement_errors"]) for r in rows]
    # channels, user inputs and target examples as the thesis has them, nothing unresolved
    assert ours == thesis, (ours, thesis)
    assert all(r["exit_code"] == 0 for r in rows), rows
    assert table_main([]) == Exit.OK
    text = capsys.readouterr().out
    assert text.startswith("| example | time taken (s) | channels |") and text.count("\n") == 9, text
